#pragma once
// Before any image is taken (`mire plan --camera`, doc/plan-and-select.md): will the target be
// seen whole at a pose cTm, and which pose covariance will `measure` then deliver there?
//
// The covariance is the one estimatePose computes (pose_estimation.hpp, doc/measurement.md
// step 5), evaluated at noise-free features (the projected target points) whose covariance of
// the mean is the one the images will give:
//   σ_f² = σ_px² / images + σ_sys²  per feature and axis,
// σ_px the detector's random noise per feature in one image (averages over the images of a
// pose), σ_sys its systematic part (sub-pixel bias of the corner model, target print errors:
// the same in every image of the pose, so it does not average; `measure` accounts for it
// through its reduced-χ² inflation). Then
//   (a) features:   Σ_a = (J_pᵀ W J_p)⁻¹,  W = σ_f⁻² I (reprojectionJacobians' whitening);
//   (b) intrinsics: Σ_b = A Σ_k Aᵀ, A = −(J_pᵀ W J_p)⁻¹ J_pᵀ W J_k, Σ_k = Camera::covariance;
//   Σ = Σ_a + Σ_b.
#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/pose_types.hpp"
#include "mire/metrology/target.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace mire::metrology {

struct VisibilityOptions {
  // Every feature at least this far inside the image (px): the detector's refinement window
  // and the chessboard detector's need of the corner's neighbourhood.
  double margin_px = 10.0;
  // Largest angle between the target's normal and the line of sight to its centre (deg):
  // beyond it the features' foreshortening makes detection unreliable.
  double max_tilt_deg = 60.0;
};

struct Visibility {
  bool visible = false;
  std::string reason;           // why not visible (empty when visible)
  double tilt_deg = 0.0;        // angle between the target normal and the line of sight
  double min_margin_px = 0.0;   // smallest distance of a feature (or the board outline) to the image border
};

// Whether the whole target is seen at `cTm`: every feature in front of the camera, inside the
// lens's valid field (its projection unprojects to the same ray), at least margin_px inside
// the image; the board's outline (the features' bounding box grown by one square for a
// chessboard or a ChArUco board: their outer squares) inside the image; tilt ≤ max_tilt_deg.
Visibility targetVisibility(const calibration::Camera& camera, const Target& target, const Eigen::Isometry3d& cTm,
                            const VisibilityOptions& options = {});

// Defaults: mire's chessboard detector on the demo's rendered images (reference camera, blur
// 0.6 px, read noise 1.5 grey levels + shot noise), measured by benchmarks/bench_plan_camera on
// 10 poses: random 0.0139 px, systematic 0.0313 px (medians; doc/plan-and-select.md).
struct PredictionOptions {
  double pixel_sigma = 0.014;     // σ_px: random detector noise per feature per image and axis [px]
  int images = 10;                // images per pose (paper §5)
  double systematic_px = 0.031;   // σ_sys: per feature and axis, does not average [px]
  double featureSigma() const;    // σ_f = sqrt(σ_px² / images + σ_sys²)
};

struct PosePrediction {
  bool valid = false;
  std::string reason;
  Matrix6d covariance_noise = Matrix6d::Zero();       // (a)
  Matrix6d covariance_intrinsics = Matrix6d::Zero();  // (b), zero without a camera covariance
  Matrix6d covariance = Matrix6d::Zero();             // (a) + (b), order tx ty tz rx ry rz
};

// The covariance estimatePose would report for features at the projections of `points`
// (Target::points()) at `cTm`, with the noise of `options`. Points that do not project
// (behind the camera) carry no information. Invalid when the pose is not observable.
PosePrediction predictPoseCovariance(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                     const Eigen::Isometry3d& cTm, const PredictionOptions& options = {});

}  // namespace mire::metrology
