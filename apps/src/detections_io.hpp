#pragma once
// --save-detections and --detections (doc/targets.md, "Detections file"): the image-folder
// stages' detections to the file, and a calibration folder read back from one.
#include "mire/pipeline/image_folders.hpp"

#include "mire/metrology/detections_file.hpp"

#include <filesystem>
#include <vector>

namespace mire::app {

// Every view of a calibration folder (images where the target was found).
std::vector<metrology::ImageDetections> calibrationDetections(const pipeline::CalibrationFolder& folder);

// Every image of every measured pose ("<pose id>/<file name>"), the target found in it.
std::vector<metrology::ImageDetections> measureDetections(const std::vector<pipeline::PoseFolderMeasurement>& poses);

// A calibration folder from a detections file, without images. The image size comes from the
// file ("# image_size_px") or from `image_size` ({width, height}; required when the file does
// not state it, and must agree when it does). Throws std::runtime_error naming the file.
pipeline::CalibrationFolder calibrationFolderFromDetections(const metrology::Target& target,
                                                            const std::filesystem::path& path,
                                                            const std::vector<int>& image_size);

}  // namespace mire::app
