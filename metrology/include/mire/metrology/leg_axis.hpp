#pragma once
// A leg's axis at one static pose from its contours in the pose's images (doc/legs.md, "Measuring
// a leg"): the contours' parameters averaged over the images, the axis from the mean contours
// (cylinder_axis.hpp) and its 4×4 covariance in δ (support/line_3d.hpp).
#include "mire/metrology/leg_contours.hpp"
#include "mire/support/line_3d.hpp"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace mire::metrology {

struct LegAxis {
  support::Line3d axis;                                  // camera frame
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Zero();  // of δ = (a1, a2 [rad], b1, b2 [m])
  int images_used = 0;
  // trace(Σ_fit⁻¹·S)/4: the images' scatter S of (θ1, ρ1, θ2, ρ2) against the per-image fits'
  // mean covariance Σ_fit; near 1 when the fits' covariance is honest (1 with a single image).
  double spread_ratio = 1.0;
};

// The mean of the contours' (θ1, ρ1, θ2, ρ2) over the images, its covariance Σ_fit·max(1,
// spread_ratio)/N (the per-image fits' covariance, inflated when the images scatter more than it
// predicts) plus the fits' mean systematic covariance (what no averaging removes: the silhouette
// model's own error), carried to δ through cylinderAxisJacobian. `images` holds at least one
// image's contours. Throws std::invalid_argument when the mean contours bound no cylinder.
LegAxis averageLegAxis(const std::vector<std::array<ContourFit, 2>>& images, double radius);

}  // namespace mire::metrology
