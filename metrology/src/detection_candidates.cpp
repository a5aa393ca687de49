// Every candidate detection of a target (detection.hpp, doc/targets.md).
#include "mire/metrology/detection.hpp"

#include "detection_internal.hpp"

#include <opencv2/imgproc.hpp>

namespace mire::metrology {

std::vector<Detection> detectTargetCandidates(const Target& target, const cv::Mat& image,
                                              const DetectionOptions& options) {
  const TargetType type = target.spec().type;
  if (type != TargetType::AprilTag && type != TargetType::ArucoGrid) return {detectTarget(target, image, options)};
  cv::Mat gray = image;
  if (image.type() == CV_8UC3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  if (image.type() == CV_8UC4) cv::cvtColor(image, gray, cv::COLOR_BGRA2GRAY);
  if (gray.empty() || gray.type() != CV_8UC1) return {detectTarget(target, image, options)};  // its error
  return type == TargetType::AprilTag ? detail::detectAprilTagCandidates(target, gray, options)
                                      : detail::detectArucoGridCandidates(target, gray, options);
}

}  // namespace mire::metrology
