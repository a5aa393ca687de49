#pragma once
// Shared pieces of the detectors (not public API).
#include "mire/metrology/detection.hpp"

#include <opencv2/core.hpp>

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

// AprilTag 3 detection of a tag grid (detection_apriltag.cpp).
Detection detectAprilTagGrid(const Target& target, const cv::Mat& gray, const DetectionOptions& options);

}  // namespace mire::metrology::detail
