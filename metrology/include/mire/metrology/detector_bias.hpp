#pragma once
// The detector's systematic feature error that every pose shares (doc/uncertainty.md "Shared
// terms").
//
// A corner detector's sub-pixel bias depends on how the corner looks (its neighbourhood, the
// blur, the sampling). That changes little from pose to pose, above all on a translating target,
// so part of each feature's error is the same in every pose. The pose errors it causes are
// correlated across poses: they do not average out over the campaign, and an identification that
// treats them as independent prints σ too small.
//   Model: b_c ~ N(0, σ_b² I₂) per target feature c, fixed in the target's local image axes (it
//     turns with the target in the image); pose j's error from it is S_j R_j b, S_j the pose's
//     feature sensitivity (pose_estimation.hpp featureSensitivity), R_j the local axes.
//   Estimate, from the data: feature c's pose-fit residual in those axes, u_jc, has over the poses
//     a mean m_c and a spread s_c²; E|m_c|² = |b_c⊥|² + E[s_c²]/n_c, b⊥ the part of b the pose fit
//     cannot absorb (2N − 6 of 2N dimensions). Kept when Σ_c (|m_c|² − s_c²/n_c) exceeds 3 of its
//     standard deviations without a bias. Camera calibration errors that look the same in every
//     pose are counted here too (conservative). A bias that only moves the whole pose (a pattern
//     inside the pose's 6 dimensions, not random per feature) leaves no residual and is not seen.
//   Propagation: the poses' joint covariance σ_b² S R (S R)ᵀ, written as its leading modes (unit
//     covariance each; ranked in units of each pose's own covariance) beside the camera's
//     parameters in the shared-term file (shared_term_csv.hpp), which `mire identify` carries
//     through its estimator as it carries the calibration error.
#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/feature_averaging.hpp"
#include "mire/metrology/pose_estimation.hpp"
#include "mire/metrology/pose_measurement.hpp"
#include "mire/metrology/target.hpp"

#include <Eigen/Geometry>

#include <map>
#include <string>
#include <vector>

namespace mire::metrology {

// One measured pose as the estimate needs it.
struct PoseFeatures {
  std::string pose_id;
  const AveragedFeatures* features = nullptr;  // not owned
  Eigen::Isometry3d cTm = Eigen::Isometry3d::Identity();
  Matrix6d covariance = Matrix6d::Identity();  // the pose's full covariance (ranks the modes)
};

struct DetectorBiasOptions {
  int min_poses = 6;                // fewer poses: no term (a shared bias cannot be told from noise)
  int min_poses_per_feature = 3;    // features seen in fewer poses do not enter the estimate of σ_b
  double significance = 3.0;        // the shared part must exceed this many of its null std
  int max_modes = 24;               // modes written at most
  double retained_fraction = 0.99;  // of the whitened trace of σ_b² S R (S R)ᵀ
  PoseOptions pose;                 // estimatePose's weighting
};

struct DetectorBiasTerm {
  double sigma_px = 0.0;                               // σ_b per feature and axis, estimated
  double feature_error_rms_px = 0.0;                   // RMS of the residuals per axis over every feature and pose
  double significance = 0.0;                           // the shared part over its standard deviation without a bias
  int features = 0, poses = 0;                         // features in the estimate, poses in the term
  double retained = 0.0;                               // fraction of the whitened trace the modes keep
  std::vector<std::string> names;                      // detector_bias_1 … : unit covariance each
  std::map<std::string, Eigen::MatrixXd> sensitivity;  // by pose id, 6 × modes, rows tx ty tz rx ry rz
  bool empty() const { return names.empty(); }
  // One line for reports: σ_b and the modes, "not seen" with the significance, or "not estimated".
  std::string text() const;
};

// Empty (sigma_px 0, no modes) with fewer than options.min_poses poses or when the residual means
// show no significant shared part. `points` = Target::points().
DetectorBiasTerm estimateDetectorBias(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                      const std::vector<PoseFeatures>& poses, const DetectorBiasOptions& options = {});

// As `mire measure` does: over the measured poses that succeeded, `measurements[j]` being pose
// `pose_ids[j]`, with the pose fit's weighting `pose`.
DetectorBiasTerm estimateDetectorBias(const calibration::Camera& camera, const Target& target,
                                      const std::vector<std::string>& pose_ids,
                                      const std::vector<const PoseMeasurement*>& measurements, const PoseOptions& pose);

}  // namespace mire::metrology
