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
  std::string reason;          // why not visible (empty when visible)
  double tilt_deg = 0.0;       // angle between the target normal and the line of sight
  double min_margin_px = 0.0;  // smallest distance of a feature (or the board outline) to the image border
};

// Whether the whole target is seen at `cTm`: every feature in front of the camera, inside the
// lens's valid field (its projection unprojects to the same ray), at least margin_px inside
// the image; the board's outline (the features' bounding box grown by one square for a
// chessboard or a ChArUco board: their outer squares) inside the image; tilt ≤ max_tilt_deg.
Visibility targetVisibility(const calibration::Camera& camera, const Target& target, const Eigen::Isometry3d& cTm,
                            const VisibilityOptions& options = {});

// How the detector's systematic error σ_sys is predicted per pose.
//   Constant:  σ_sys = systematic_px at every pose.
//   BoardImage (default): σ_sys = (reference_square_px / s) · (a + b · cos 4φ), s the projected
//     square size in pixels at the board's centre, φ the angle of the board's edges to the pixel
//     rows (boardImageGeometry). Why (doc/plan-and-select.md, "--camera"): the corner model's
//     sub-pixel bias comes from the lens blur and the pixels' integration, whose extent is fixed
//     in pixels, so it is a fixed fraction of the blurred saddle's width and grows as the squares
//     shrink (1/s, i.e. with the distance); it is largest when the edges lie along the pixel rows
//     and columns (each edge sampled at the same sub-pixel phase along its length, so the
//     sampling bias does not average out: φ = 0°, cos 4φ = 1) and smallest at 45° (cos 4φ = −1).
enum class SystematicModel { Constant, BoardImage };

// Defaults: mire's chessboard detector on the demo's rendered images (reference camera, blur
// 0.6 px, read noise 1.5 grey levels + shot noise), measured by benchmarks/bench_plan_camera on
// 10 poses that are not planned (doc/plan-and-select.md): random 0.0139 px; systematic 0.0313 px
// (median, Constant), or the BoardImage fit a, b below.
struct PredictionOptions {
  double pixel_sigma = 0.014;  // σ_px: random detector noise per feature per image and axis [px]
  int images = 10;             // images per pose (paper §5)
  SystematicModel systematic_model = SystematicModel::BoardImage;
  double systematic_px = 0.031;        // Constant: σ_sys per feature and axis, does not average [px]
  double reference_square_px = 20.0;   // BoardImage: s at which σ_sys = a + b cos 4φ [px]
  double systematic_mean_px = 0.0278;  // BoardImage: a [px]
  double systematic_grid_px = 0.0045;  // BoardImage: b [px]
  // σ_sys at a pose whose squares are `square_px` wide at edge angle `edge_angle_rad`.
  double systematicSigma(double square_px, double edge_angle_rad) const;
  double featureSigma() const;                   // σ_f = sqrt(σ_px² / images + σ_sys²), σ_sys = systematic_px
  double featureSigma(double systematic) const;  // the same with the given σ_sys
};

// The board as the image shows it at its centre: the feature spacing (nearest neighbour of the
// first feature, e.g. a chessboard's square) projected, s = √(area of the projected square), and
// the angle of the projected edge (first feature → its nearest neighbour) to the pixel rows.
struct BoardImageGeometry {
  bool valid = false;
  double square_px = 0.0;
  double edge_angle_rad = 0.0;
};
BoardImageGeometry boardImageGeometry(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                      const Eigen::Isometry3d& cTm);

struct PosePrediction {
  bool valid = false;
  std::string reason;
  Matrix6d covariance_noise = Matrix6d::Zero();       // (a)
  Matrix6d covariance_intrinsics = Matrix6d::Zero();  // (b), zero without a camera covariance
  // A = ∂(t, r)/∂k (6 × n over Camera::params): the calibration error this pose shares with
  // every other pose (SharedPoseTerm of `mire identify`); empty without a camera covariance.
  Eigen::MatrixXd intrinsics_sensitivity;
  Matrix6d covariance = Matrix6d::Zero();  // (a) + (b), order tx ty tz rx ry rz
  double systematic_px = 0.0;              // σ_sys used at this pose
};

// The covariance estimatePose would report for features at the projections of `points`
// (Target::points()) at `cTm`, with the noise of `options`. Points that do not project
// (behind the camera) carry no information. Invalid when the pose is not observable.
PosePrediction predictPoseCovariance(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                     const Eigen::Isometry3d& cTm, const PredictionOptions& options = {});

}  // namespace mire::metrology
