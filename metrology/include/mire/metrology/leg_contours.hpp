#pragma once
// A leg's two straight contours in one image (doc/legs.md, "Measuring a leg"): sub-pixel edge
// points along the normals of the predicted contours, away from the rod's ends, then a robust line
// fit per contour in normalised coordinates (after undistortion) with its covariance from the
// edge points' scatter, moved onto the shaded rod's silhouette.
#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/cylinder_axis.hpp"

#include <opencv2/core.hpp>

#include <Eigen/Core>

#include <array>
#include <string>
#include <vector>

namespace mire::metrology {

struct LegContourOptions {
  double search_px = 25.0;   // half-width of the band searched around each predicted contour
  double end_margin = 0.05;  // fraction of the segment left out at each end (and at least 3 radii)
  double spacing_px = 4.0;   // between edge samples: beyond the gradient's support, so independent
  int min_edge_points = 12;
  // The silhouette model's own error [px] on each half of a contour, which no averaging over
  // images removes: the residual measured on area-sampled renders of shaded rods (doc/legs.md).
  double silhouette_px = 0.01;
};

// The image and its smoothed gradient (Gaussian σ = 1 px, then Sobel), computed once for all legs.
struct EdgeImage {
  cv::Mat grey;    // CV_32F
  cv::Mat gx, gy;  // CV_32F, grey levels per pixel
  static EdgeImage of(const cv::Mat& grey);
};

struct ContourFit {
  ContourLine line;
  // Of (θ, ρ): the edge points' scatter about the line and the silhouette fit's (its shift).
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  Eigen::Matrix2d systematic = Eigen::Matrix2d::Zero();  // of (θ, ρ), from silhouette_px (not averaged)
  int edge_points = 0;                                   // samples where an edge was found
  std::vector<Eigen::Vector2d> inliers_px;               // the edge points the fit kept (pixels)
};

struct LegContours {
  bool ok = false;
  std::string error;  // why the leg was not measured in this image
  std::array<ContourFit, 2> contours;
};

// The contours of the rod of `radius` [m] whose axis runs from `from` to `to` (camera frame, m, the
// predicted joint centres): the search follows the predicted contours (cylinderContours, projected
// with the lens distortion) within ±search_px; facing edge pairs must keep the predicted width, and
// the edge polarity (rod darker or brighter than what is behind it) is the one with more such
// pairs. Each fitted line is then moved onto the silhouette (doc/legs.md, "Measuring a leg").
LegContours measureLegContours(const EdgeImage& image, const calibration::Camera& camera, const Eigen::Vector3d& from,
                               const Eigen::Vector3d& to, double radius, const LegContourOptions& options = {});

}  // namespace mire::metrology
