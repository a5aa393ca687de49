#pragma once
// Finding a target's features in an image (OpenCV for chessboards and circle grids,
// AprilTag 3 for tag grids). Pixel convention: OpenCV's.
#include "mire/metrology/target.hpp"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace mire::metrology {

struct DetectionOptions {
  bool subpixel = true;          // corner refinement (chessboard) / edge refinement (tags)
  int subpixel_window_px = 0;    // 0 = chosen from the feature spacing in the image
  bool allow_partial = true;     // AprilTag grids: accept a subset of the tags
};

struct Detection {
  bool found = false;
  std::string reason;                   // why not found (or why partial), for reports
  std::vector<int> ids;                 // indices into Target::points()
  std::vector<Eigen::Vector2d> pixels;  // image position of each feature
  std::size_t size() const { return ids.size(); }
};

// Detects the target in an 8-bit grey image.
Detection detectTarget(const Target& target, const cv::Mat& gray, const DetectionOptions& options = {});

// Cheap re-detection in another image of the same scene: refines `initial`'s features in
// `gray` (sub-pixel), without the full search. Features that cannot be refined are dropped.
Detection refineDetection(const Target& target, const cv::Mat& gray, const Detection& initial,
                          const DetectionOptions& options = {});

}  // namespace mire::metrology
