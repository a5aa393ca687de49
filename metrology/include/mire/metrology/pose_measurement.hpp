#pragma once
// One pose from its images (doc/measurement.md): detect the target once (in the first
// image where it is found), refine those features in every other image (cheap), average them
// with their scatter (feature_averaging.hpp), and estimate cTm with its precision
// (pose_estimation.hpp).
#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/detection.hpp"
#include "mire/metrology/feature_averaging.hpp"
#include "mire/metrology/pose_estimation.hpp"
#include "mire/metrology/pose_integrity.hpp"
#include "mire/metrology/target.hpp"

#include <opencv2/core.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace mire::metrology {

struct MeasurementOptions {
  DetectionOptions detection;
  AveragingOptions averaging;
  PoseOptions pose;
  IntegrityOptions integrity;  // static-pose test (pose_integrity.hpp)
};

struct PoseMeasurement {
  bool ok = false;
  std::string error;                  // why the pose failed, naming the image when one is at fault
  std::vector<std::string> warnings;  // e.g. images where the target was not found
  std::vector<std::string> notes;     // duplicates counted once, images left out by a split, σ rule
  IntegrityResult integrity;
  AveragedFeatures features;
  PoseEstimate estimate;
  std::vector<Detection> detections;  // per input image, same order (for --save-detections)
};

// `images`: 8-bit grey images of one static pose; `names` (same size, may be empty) name
// them in messages. Fails when the target is found in no image, when sizes differ, when
// a size differs from the camera's, or when the images do not show one static pose
// (pose_integrity.hpp; with SplitPolicy::KeepLargest the largest consistent group is kept).
PoseMeasurement measurePose(const calibration::Camera& camera, const Target& target, const std::vector<cv::Mat>& images,
                            const std::vector<std::string>& names, const MeasurementOptions& options = {});

// Same from image files (any format OpenCV reads, converted to grey). An unreadable file fails
// the pose, naming the file.
PoseMeasurement measurePoseFromFiles(const calibration::Camera& camera, const Target& target,
                                     const std::vector<std::filesystem::path>& files,
                                     const MeasurementOptions& options = {});

// The image files of one pose folder: regular, non-hidden files, sorted by name.
std::vector<std::filesystem::path> listPoseImages(const std::filesystem::path& folder);

}  // namespace mire::metrology
