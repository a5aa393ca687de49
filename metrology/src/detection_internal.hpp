#pragma once
// Shared pieces of the detectors (not public API).
#include "mire/metrology/detection.hpp"

#include <opencv2/core.hpp>

#include <array>
#include <map>
#include <string>
#include <vector>

namespace mire::metrology::detail {

// Orders a grid found by OpenCV (row-major, `cols` per row) onto the target's feature
// indices: tries the grid's symmetries, keeps those whose homography from frame M fits and
// keeps the board's handedness (z = x × y away from the camera), applies the chessboard
// colour rule, then the documented tie-break. Empty result if nothing fits.
Detection orderGrid(const Target& target, const cv::Mat& gray, const std::vector<cv::Point2f>& opencv_grid);

// Chessboard corners by cv::findChessboardCornersSB (accuracy mode).
bool findChessboardSB(const cv::Mat& gray, cv::Size pattern, std::vector<cv::Point2f>* corners);
// Chessboard corners by cv::findChessboardCorners + cv::cornerSubPix.
bool findChessboardClassic(const cv::Mat& gray, cv::Size pattern, int window_px, std::vector<cv::Point2f>* corners);

// cornerSubPix half-window for features `spacing_px` apart (0 in options = automatic).
int chessboardWindow(double spacing_px, const DetectionOptions& options);

// Smallest pixel distance between grid neighbours (along rows and columns).
double neighbourSpacingPx(const Target& target, const Detection& detection);

// Sub-pixel circle centres: coverage-weighted centroid of each dark disc (see circles.cpp).
// Drops (returns false for) circles it cannot refine.
std::vector<bool> refineCircleCentres(const cv::Mat& gray, const Target& target, Detection* detection);

// AprilTag 3 detection of a tag grid or layout (detection_apriltag.cpp): every candidate, best
// first (detection_tag_layout.cpp).
std::vector<Detection> detectAprilTagCandidates(const Target& target, const cv::Mat& gray,
                                                const DetectionOptions& options);
Detection detectAprilTagGrid(const Target& target, const cv::Mat& gray, const DetectionOptions& options);

// ChArUco boards and ArUco grids through OpenCV's aruco module (detection_charuco.cpp).
Detection detectCharuco(const Target& target, const cv::Mat& gray, const DetectionOptions& options);
std::vector<Detection> detectArucoGridCandidates(const Target& target, const cv::Mat& gray,
                                                 const DetectionOptions& options);

// One square marker (AprilTag or ArUco) found in an image: its id and corners in the target's
// corner order (top-left, top-right, bottom-right, bottom-left of the upright marker).
struct SquareInstance {
  int id = -1;
  std::array<Eigen::Vector2d, 4> corners;
};

// Square markers of a layout: id -> its four corners in frame M (x, y), same corner order.
using SquareLayout = std::map<int, std::array<Eigen::Vector2d, 4>>;

// Groups of instances that fit the layout (detection_tag_layout.cpp), best first: each group
// holds at most one instance per id (indices into `instances`), all consistent with one
// homography from frame M. Ids outside the layout are ignored; a repeated id keeps the
// instance that fits the others; the instances left over form the next groups (so each
// instance of a single-marker layout is a group of its own). Groups rank by size, then
// by image area.
std::vector<std::vector<int>> groupLayoutInstances(const SquareLayout& layout,
                                                   const std::vector<SquareInstance>& instances);

// One detection per group of groupLayoutInstances (features 4k + j, k = Target::tagIndex),
// best first; `what` names the markers in reasons ("tags", "markers").
std::vector<Detection> layoutDetections(const Target& target, const std::vector<SquareInstance>& instances,
                                        const DetectionOptions& options, const std::string& what);

// The layout of a tag target or ArUco grid (marker k's corners are points 4k..4k+3).
SquareLayout squareLayout(const Target& target);

}  // namespace mire::metrology::detail
