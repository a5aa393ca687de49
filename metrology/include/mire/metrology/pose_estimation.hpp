#pragma once
// The target pose cTm from averaged features, with its precision (doc/measurement.md).
//
//  1. Planar initialisation: IPPE (cv::solvePnPGeneric, SOLVEPNP_IPPE) on the undistorted rays
//     (Camera::unproject, exact), keeping both of its solutions.
//  2. Refinement of each solution by Ceres: the reprojection error through the full distortion
//     model (calibration::projectPoint, autodiff), whitened by each averaged feature's
//     covariance of the mean. The lower cost wins; when the other solution's cost is within
//     `ambiguity_ratio` of it, the pose is flagged ambiguous (planar pose flip).
//  3. Precision, as a 6×6 covariance of (tx ty tz rx ry rz), r the rotation vector
//     (cv::Rodrigues convention):
//       (a) features:       Σ_a = max(1, χ²/dof) (J_pᵀ W J_p)⁻¹, W = the features' covariance of
//           the mean⁻¹. Without the factor this is the pixel noise alone (covariance_pixel_noise):
//           averaging 10 images shrinks it, but not the detector's and the target's own
//           systematic errors, which show up as a reduced χ² ≫ 1 of the fit (Birge ratio);
//           inflating by it keeps the σ honest when they dominate;
//       (b) intrinsics:     Σ_b = A Σ_k Aᵀ, A = ∂pose/∂k = −(J_pᵀ W J_p)⁻¹ J_pᵀ W J_k
//           (implicit function theorem at the optimum), Σ_k = Camera::covariance;
//       combined Σ = Σ_a + Σ_b (independent sources).
#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/feature_averaging.hpp"
#include "mire/metrology/pose_types.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace mire::metrology {

struct PoseOptions {
  // The pose is flagged ambiguous when cost(second minimum) < ambiguity_ratio × cost(best).
  double ambiguity_ratio = 4.0;
  // Added to every feature's covariance of the mean (px): keeps the weights finite on
  // noiseless (synthetic) data; negligible on real images (σ of a mean ≈ 0.01–0.05 px).
  double covariance_floor_px = 1e-4;
  // Inflate (a) by the reduced χ² of the fit when it exceeds 1 (see above).
  bool inflate_by_residuals = true;
  // When the features carry no scatter (a single image) the noise covariance is estimated from
  // the fit's residuals: σ² = Σ r² / (2N − 6), isotropic.
  int max_iterations = 100;
};

struct PoseEstimate {
  bool valid = false;
  std::string reason;  // why not valid
  Eigen::Isometry3d cTm = Eigen::Isometry3d::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();      // m
  Eigen::Vector3d rotation_vector = Eigen::Vector3d::Zero();  // rad, cv::Rodrigues convention
  Matrix6d covariance_pixel_noise = Matrix6d::Zero();         // from the feature scatter alone
  Matrix6d covariance_noise = Matrix6d::Zero();               // (a) = pixel noise × max(1, reduced χ²)
  Matrix6d covariance_intrinsics = Matrix6d::Zero();          // (b) from Camera::covariance
  // ∂(t, r)/∂k, 6 × n over Camera::params (the implicit-function sensitivity behind (b)); the
  // same calibration error k enters every pose, so `identify` needs it (shared_term_csv.hpp).
  // Empty without a camera covariance.
  Eigen::MatrixXd intrinsics_sensitivity;
  Matrix6d covariance = Matrix6d::Zero();  // (a) + (b)
  double rms_px = 0.0;                     // RMS reprojection residual of the averaged features (px)
  // Σ of the whitened residuals² / (2N − 6), whitened with the covariance actually used: the
  // features' covariance of the mean (several images), or for one image (or copies of one)
  // the isotropic σ² estimated from these same residuals, which makes it 1 by construction
  // (no independent noise estimate; doc/measurement.md, "Imperfect campaigns"). ≈ 1 when the model fits to
  // the noise; ≫ 1: systematic feature errors.
  double reduced_chi2 = 0.0;
  int feature_count = 0;
  bool scatter_from_residuals = false;  // no multi-image scatter: (a) uses the residuals
  bool ambiguous = false;
  double ambiguity_cost_ratio = 0.0;  // cost(second) / cost(best); +inf when a single minimum
  Eigen::Isometry3d alternative_cTm = Eigen::Isometry3d::Identity();  // the second minimum

  // One-sigma of each component (sqrt of the diagonal) of a covariance, in its units.
  static Eigen::Matrix<double, 6, 1> sigmas(const Matrix6d& covariance);
};

// Estimates cTm. `points` = Target::points() (frame M, z = 0); `features` indexes into it.
PoseEstimate estimatePose(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                          const AveragedFeatures& features, const PoseOptions& options = {});

// Whitened Jacobians of the reprojection residuals at `cTm`, with the same weighting as
// estimatePose (each feature's covariance of the mean plus the floor; identity when the
// features carry no scatter): J_p is 2N×6 in (tx ty tz rx ry rz) order, J_k is 2N×params.
// (J_pᵀ J_p)⁻¹ is then the Cramér–Rao bound of the pose for that feature noise.
void reprojectionJacobians(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                           const AveragedFeatures& features, const Eigen::Isometry3d& cTm, Eigen::MatrixXd* jacobian_pose,
                           Eigen::MatrixXd* jacobian_intrinsics, const PoseOptions& options = {});

// ∂(t, r)/∂x at `cTm`: the pose's first-order change per feature pixel error, 6 × 2N with
// columns (x₀ y₀ x₁ y₁ …) in `features` order, (J_pᵀ J_p)⁻¹ J_pᵀ L⁻¹ with estimatePose's
// weighting (detector_bias.hpp). Empty when the pose is not observable.
Eigen::MatrixXd featureSensitivity(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                   const AveragedFeatures& features, const Eigen::Isometry3d& cTm,
                                   const PoseOptions& options = {});

// Step 3 of estimatePose from whitened Jacobians at the pose (J_p 2N×6, J_k 2N×params, as
// reprojectionJacobians gives them): the inverse Fisher information (J_pᵀ J_p)⁻¹ and, when the
// camera carries a covariance, the intrinsics part A Σ_k Aᵀ with A = −(J_pᵀ J_p)⁻¹ J_pᵀ J_k.
// estimatePose and the planner's predictPoseCovariance share it.
struct PosePrecision {
  bool observable = false;                            // false: J_pᵀ J_p is singular
  Matrix6d information_inverse = Matrix6d::Zero();    // (J_pᵀ J_p)⁻¹, as computed (not symmetrised)
  Matrix6d covariance_intrinsics = Matrix6d::Zero();  // symmetrised; zero without a camera covariance
  Eigen::MatrixXd intrinsics_sensitivity;             // A; empty without a camera covariance
};
PosePrecision posePrecision(const calibration::Camera& camera, const Eigen::MatrixXd& jacobian_pose,
                            const Eigen::MatrixXd& jacobian_intrinsics);

}  // namespace mire::metrology
