// --save-detections / --detections of mire calibrate and mire measure (detections_io.hpp).
#include "detections_io.hpp"

#include <stdexcept>

namespace mire::app {

std::vector<metrology::ImageDetections> calibrationDetections(const pipeline::CalibrationFolder& folder) {
  std::vector<metrology::ImageDetections> images;
  for (const calibration::CalibrationView& view : folder.views) images.push_back({view.name, view.ids, view.pixels});
  return images;
}

std::vector<metrology::ImageDetections> measureDetections(const std::vector<pipeline::PoseFolderMeasurement>& poses) {
  std::vector<metrology::ImageDetections> images;
  for (const pipeline::PoseFolderMeasurement& pose : poses) {
    const std::vector<std::filesystem::path> files = metrology::listPoseImages(pose.folder);
    const auto& detections = pose.measurement.detections;
    for (std::size_t j = 0; j < detections.size() && j < files.size(); ++j) {
      if (!detections[j].found) continue;
      images.push_back({pose.pose_id + "/" + files[j].filename().string(), detections[j].ids, detections[j].pixels});
    }
  }
  return images;
}

pipeline::CalibrationFolder calibrationFolderFromDetections(const metrology::Target& target,
                                                            const std::filesystem::path& path,
                                                            const std::vector<int>& image_size) {
  const metrology::DetectionsFile file = metrology::readDetectionsFile(path, target);
  pipeline::CalibrationFolder folder;
  if (!image_size.empty() && image_size.size() != 2)
    throw std::runtime_error("--image-size needs two values: width height");
  if (file.width && !image_size.empty() && (image_size[0] != *file.width || image_size[1] != *file.height))
    throw std::runtime_error(path.string() + ": image_size_px " + std::to_string(*file.width) + " x " +
                             std::to_string(*file.height) + " differs from --image-size " +
                             std::to_string(image_size[0]) + " x " + std::to_string(image_size[1]));
  if (file.width) {
    folder.width = *file.width, folder.height = *file.height;
  } else if (!image_size.empty()) {
    folder.width = image_size[0], folder.height = image_size[1];
  } else {
    throw std::runtime_error(path.string() + ": the file does not give the image size: add --image-size WIDTH HEIGHT");
  }
  if (folder.width <= 0 || folder.height <= 0) throw std::runtime_error("--image-size must be positive");
  for (const metrology::ImageDetections& image : file.images)
    folder.views.push_back({image.image, image.ids, image.pixels});
  folder.images = folder.views.size();
  return folder;
}

}  // namespace mire::app
