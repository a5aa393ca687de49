#pragma once
// Finding a target's features in an image (OpenCV for chessboards and circle grids, OpenCV's
// aruco module for ChArUco and ArUco grid boards, AprilTag 3 for tag targets). Pixel
// convention: OpenCV's.
#include "mire/metrology/target.hpp"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <array>
#include <string>
#include <vector>

namespace mire::metrology {

struct DetectionOptions {
  bool subpixel = true;        // corner refinement (chessboard) / edge refinement (tags)
  int subpixel_window_px = 0;  // 0 = chosen from the feature spacing in the image
  bool allow_partial = true;   // AprilTag grids: accept a subset of the tags
};

struct Detection {
  bool found = false;
  std::string reason;                   // why not found (or why partial), for reports
  std::vector<int> ids;                 // indices into Target::points()
  std::vector<Eigen::Vector2d> pixels;  // image position of each feature
  std::size_t size() const { return ids.size(); }
};

// One AprilTag as AprilTag 3 reports it, converted to this library's conventions.
struct TagDetection {
  int id = -1;
  int hamming = 0;               // bits corrected
  double decision_margin = 0.0;  // AprilTag's decoding confidence
  // Corners with OpenCV's pixel convention (AprilTag's coordinates − 0.5 px), in the target's
  // corner order: top-left, top-right, bottom-right, bottom-left of the upright tag
  // (AprilTag's own p[0..3] are bottom-left, bottom-right, top-right, top-left).
  std::array<Eigen::Vector2d, 4> corners;
};

// Every tag of `family` in an 8-bit grey image (AprilTag 3, quad_decimate = 1, one
// thread; refine_edges as asked). Throws std::invalid_argument for an unknown family.
std::vector<TagDetection> detectAprilTags(const cv::Mat& gray, const std::string& family, bool refine_edges);

// Detects the target in an 8-bit grey image (BGR is converted).
Detection detectTarget(const Target& target, const cv::Mat& image, const DetectionOptions& options = {});

// Every candidate detection of the target, best first (doc/targets.md, "Repeated and foreign
// ids"). For AprilTag targets and ArUco grids: groups of tags/markers that each fit the layout
// (one instance per id), the largest group first, then by image area; a single-tag layout
// gives one candidate per instance of its tag in the scene. Other types: detectTarget's result.
// detectTarget returns the first candidate.
std::vector<Detection> detectTargetCandidates(const Target& target, const cv::Mat& image,
                                              const DetectionOptions& options = {});

// Cheap re-detection in another image of the same scene: refines `initial`'s features in
// `image` (sub-pixel), without the full search. Features that cannot be refined are dropped.
Detection refineDetection(const Target& target, const cv::Mat& image, const Detection& initial,
                          const DetectionOptions& options = {});

}  // namespace mire::metrology
