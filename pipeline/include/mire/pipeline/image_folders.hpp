#pragma once
// The image-folder stages shared by `mire calibrate`, `mire measure` and `mire demo`: the
// target detected in every image of a calibration folder, and one pose measured per pose
// subfolder (doc/file-formats.md, "pose image folder"), each in parallel with a progress bar.
#include "mire/calibration/calibrate.hpp"
#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/detector_bias.hpp"
#include "mire/metrology/pose_measurement.hpp"
#include "mire/metrology/target.hpp"

#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace mire::pipeline {

// Runs work(i) for i in [0, count) on `threads` workers (0 = all cores), each taking the next
// index (items differ in cost).
void parallelForEach(std::size_t count, int threads, const std::function<void(std::size_t)>& work);

struct CalibrationFolder {
  std::vector<calibration::CalibrationView> views;           // images where the target was found
  std::vector<std::pair<std::string, std::string>> skipped;  // image name, why the target was not used
  std::vector<std::pair<std::string, std::string>> notes;    // image name, remark on a found target
  std::size_t images = 0;
  int width = 0, height = 0;
};

// Detects the target in every image of `folder`. Throws std::runtime_error naming the folder
// or the image when the folder is missing or holds no image, an image is unreadable, or the
// images differ in size.
CalibrationFolder detectCalibrationFolder(const metrology::Target& target, const std::filesystem::path& folder,
                                          int threads);

// The pose subfolders of `folder` (id = the subfolder's name), in id order. Throws
// std::runtime_error when `folder` is not a folder, holds no pose subfolder, or an id contains
// ',' or '"'.
std::vector<std::pair<std::string, std::filesystem::path>> poseFolders(const std::filesystem::path& folder);

// The image files of a pose folder (other files, e.g. notes.txt, ignored as in calibration
// folders), each checked: not too large, not truncated, not blank (a blank image would be
// counted as a view without the target); throws std::runtime_error naming the image otherwise.
std::vector<std::filesystem::path> poseImages(const std::filesystem::path& folder);

struct PoseFolderMeasurement {
  std::string pose_id;  // the subfolder's name
  std::filesystem::path folder;
  metrology::PoseMeasurement measurement;  // ok == false with the reason when the pose failed
  int images_total = 0;
};

// One measurement per pose subfolder of `folder`, in pose-id order. A failing pose is reported
// in its entry, never thrown. Throws std::runtime_error when `folder` is not a folder, holds no
// pose subfolder, or a pose id contains ',' or '"'.
std::vector<PoseFolderMeasurement> measurePoseFolders(const calibration::Camera& camera, const metrology::Target& target,
                                                      const std::filesystem::path& folder,
                                                      const metrology::MeasurementOptions& options, int threads);

// The detector's bias shared by the poses measured (metrology/detector_bias.hpp), from the
// poses that succeeded.
metrology::DetectorBiasTerm sharedDetectorBias(const calibration::Camera& camera, const metrology::Target& target,
                                               const std::vector<PoseFolderMeasurement>& poses,
                                               const metrology::MeasurementOptions& options);

}  // namespace mire::pipeline
