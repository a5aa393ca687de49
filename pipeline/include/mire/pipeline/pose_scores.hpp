#pragma once
// Scores of the demo's measured poses against the simulator's truth (doc/uncertainty.md
// "Pose errors share the calibration's error"). Every pose's error carries the same
// calibration error D_j Δk, so error/σ of one component is correlated from pose to pose: its RMS
// over the campaign is one draw of the shared term, not an average of independent draws. The
// whitened RMS uses the whole cross-pose covariance blockdiag(Σ_noise,j) + D Σ_k Dᵀ instead;
// it is ≈ 1 when the printed σ and the shared term are both right.
#include <Eigen/Core>

#include <vector>

namespace mire::pipeline {

struct PoseErrorSample {
  Eigen::Matrix<double, 6, 1> error;        // estimate − truth (t [m], r [rad])
  Eigen::Matrix<double, 6, 6> independent;  // Σ_noise of the pose (varies per pose)
  Eigen::MatrixXd sensitivity;              // D_j = ∂pose/∂k (6 × n), empty without Σ_k
  Eigen::Matrix<double, 6, 1> sigma;        // printed σ (independent + shared, diagonal)
};

struct PoseErrorScores {
  Eigen::Matrix<double, 6, 1> rms_per_pose = Eigen::Matrix<double, 6, 1>::Zero();  // RMS of error/σ per component
  Eigen::Matrix<double, 6, 1> rms_whitened = Eigen::Matrix<double, 6, 1>::Zero();  // per component, cross-pose
  double rms_per_pose_all = 0.0;                                                   // over all components
  double rms_whitened_all = 0.0;  // the whole 6N-vector whitened with its full covariance
};

// `camera_covariance` is Σ_k (n × n; empty when the camera has none: then only the independent parts).
PoseErrorScores scorePoseErrors(const std::vector<PoseErrorSample>& samples, const Eigen::MatrixXd& camera_covariance);

}  // namespace mire::pipeline
