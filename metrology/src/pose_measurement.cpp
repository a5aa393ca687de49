#include "mire/metrology/pose_measurement.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <sstream>

namespace mire::metrology {
namespace {

std::string imageName(const std::vector<std::string>& names, std::size_t index) {
  if (index < names.size()) return names[index];
  return "image #" + std::to_string(index + 1);
}

std::string sizeText(const cv::Size& size) { return std::to_string(size.width) + "x" + std::to_string(size.height); }

}  // namespace

PoseMeasurement measurePose(const calibration::Camera& camera, const Target& target, const std::vector<cv::Mat>& images,
                            const std::vector<std::string>& names, const MeasurementOptions& options) {
  PoseMeasurement result;
  if (images.empty()) {
    result.error = "no images";
    return result;
  }
  // Sizes first: mixed sizes mean mixed cameras or settings, and the calibration holds for one.
  const cv::Size first_size = images.front().size();
  for (std::size_t j = 0; j < images.size(); ++j) {
    if (images[j].type() != CV_8UC1) {
      result.error = imageName(names, j) + ": not an 8-bit grey image";
      return result;
    }
    if (images[j].size() != first_size) {
      result.error = "mixed image sizes: " + imageName(names, j) + " is " + sizeText(images[j].size()) + " but " +
                     imageName(names, 0) + " is " + sizeText(first_size);
      return result;
    }
  }
  if (first_size != cv::Size(camera.width, camera.height)) {
    result.error = imageName(names, 0) + " is " + sizeText(first_size) + " but the camera was calibrated at " +
                   sizeText(cv::Size(camera.width, camera.height));
    return result;
  }

  // Full detection until the target is found once, then cheap refinement from it.
  std::vector<Detection> detections(images.size());
  std::size_t reference = images.size();
  for (std::size_t j = 0; j < images.size() && reference == images.size(); ++j) {
    detections[j] = detectTarget(target, images[j], options.detection);
    if (detections[j].found) reference = j;
    else result.warnings.push_back(imageName(names, j) + ": target not found (" + detections[j].reason + ")");
  }
  if (reference == images.size()) {
    result.error = "target not found in any of the " + std::to_string(images.size()) + " images";
    if (!detections.empty() && !detections.front().reason.empty()) result.error += " (" + detections.front().reason + ")";
    return result;
  }
  for (std::size_t j = reference + 1; j < images.size(); ++j) {
    detections[j] = refineDetection(target, images[j], detections[reference], options.detection);
    // A refinement that lost much of the target (the camera or the target moved): search again.
    if (!detections[j].found || detections[j].size() * 2 < detections[reference].size())
      detections[j] = detectTarget(target, images[j], options.detection);
    if (!detections[j].found)
      result.warnings.push_back(imageName(names, j) + ": target not found (" + detections[j].reason + ")");
  }

  result.features = averageDetections(detections, options.averaging);
  result.detections = detections;
  for (const int j : result.features.rejected_images)
    result.warnings.push_back(imageName(names, static_cast<std::size_t>(j)) +
                              ": rejected as an outlier (whole-image displacement, chi-square test)");
  result.estimate = estimatePose(camera, target.points(), result.features, options.pose);
  if (!result.estimate.valid) {
    result.error = result.estimate.reason;
    return result;
  }
  if (result.estimate.ambiguous) {
    std::ostringstream text;
    text << "ambiguous pose: the planar flip fits almost as well (cost ratio " << result.estimate.ambiguity_cost_ratio
         << ")";
    result.warnings.push_back(text.str());
  }
  result.ok = true;
  return result;
}

PoseMeasurement measurePoseFromFiles(const calibration::Camera& camera, const Target& target,
                                     const std::vector<std::filesystem::path>& files,
                                     const MeasurementOptions& options) {
  std::vector<cv::Mat> images;
  std::vector<std::string> names;
  for (const auto& file : files) {
    cv::Mat image;
    try {
      image = cv::imread(file.string(), cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception&) {
      image.release();
    }
    if (image.empty()) {
      PoseMeasurement failed;
      failed.error = file.string() + ": unreadable image (not a format OpenCV reads, or corrupt)";
      return failed;
    }
    if (image.depth() != CV_8U) {
      PoseMeasurement failed;
      failed.error = file.string() + ": not an 8-bit image";
      return failed;
    }
    if (image.channels() == 3) cv::cvtColor(image, image, cv::COLOR_BGR2GRAY);
    else if (image.channels() == 4) cv::cvtColor(image, image, cv::COLOR_BGRA2GRAY);
    images.push_back(image);
    names.push_back(file.string());
  }
  return measurePose(camera, target, images, names, options);
}

std::vector<std::filesystem::path> listPoseImages(const std::filesystem::path& folder) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    const std::string name = entry.path().filename().string();
    if (name.empty() || name[0] == '.') continue;
    files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace mire::metrology
