// The detector's shared bias (detector_bias.hpp): residuals in the target's local image axes,
// the moment estimate of σ_b, then the leading modes of the poses' joint covariance.
#include "mire/metrology/detector_bias.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace mire::metrology {
namespace {

// The target's local image axes at point X: the image directions of its x and y axes,
// orthonormalised (a rotation, or a reflection when the target is seen from behind).
Eigen::Matrix2d localAxes(const calibration::Camera& camera, const Eigen::Isometry3d& cTm, const Eigen::Vector3d& X) {
  constexpr double kStep = 1e-3;  // m: small against any target, large against rounding
  Eigen::Vector2d at, along_x, along_y;
  if (!camera.project(cTm * X, &at) || !camera.project(cTm * (X + kStep * Eigen::Vector3d::UnitX()), &along_x) ||
      !camera.project(cTm * (X + kStep * Eigen::Vector3d::UnitY()), &along_y))
    return Eigen::Matrix2d::Identity();
  const Eigen::Vector2d x = (along_x - at).normalized();
  Eigen::Vector2d y(-x.y(), x.x());
  if (y.dot(along_y - at) < 0.0) y = -y;
  Eigen::Matrix2d axes;
  axes << x, y;
  return axes;
}

// Per pose: each feature's residual (observed − projected) in its local axes, and those axes.
struct PoseResiduals {
  std::vector<Eigen::Vector2d> residual;
  std::vector<Eigen::Matrix2d> axes;
};

PoseResiduals poseResiduals(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                            const PoseFeatures& pose) {
  const AveragedFeatures& f = *pose.features;
  PoseResiduals out;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const Eigen::Vector3d& X = points[static_cast<std::size_t>(f.ids[i])];
    Eigen::Vector2d projected;
    const bool ok = camera.project(pose.cTm * X, &projected);
    out.axes.push_back(localAxes(camera, pose.cTm, X));
    out.residual.push_back(ok ? Eigen::Vector2d(out.axes.back().transpose() * (f.pixels[i] - projected))
                              : Eigen::Vector2d(Eigen::Vector2d::Constant(std::nan(""))));
  }
  return out;
}

// σ_b² by moments: Σ_c (|m_c|² − s_c²/n_c) / (2 × features), scaled by 2N/(2N − 6) for the part
// of b the pose fits absorb; 0 unless the sum stands out from its sampling noise. Also the
// residuals' RMS per axis.
void estimateSharedVariance(const std::vector<PoseFeatures>& poses, const std::vector<PoseResiduals>& residuals,
                            int min_poses_per_feature, double significance, DetectorBiasTerm* term) {
  std::map<int, std::vector<Eigen::Vector2d>> by_feature;
  double squares = 0.0, features_per_pose = 0.0;
  int count = 0;
  for (std::size_t j = 0; j < poses.size(); ++j) {
    features_per_pose += static_cast<double>(residuals[j].residual.size()) / static_cast<double>(poses.size());
    for (std::size_t i = 0; i < residuals[j].residual.size(); ++i) {
      const Eigen::Vector2d& u = residuals[j].residual[i];
      if (!u.allFinite()) continue;
      by_feature[poses[j].features->ids[i]].push_back(u);
      squares += u.squaredNorm();
      ++count;
    }
  }
  term->feature_error_rms_px = count > 0 ? std::sqrt(squares / (2.0 * count)) : 0.0;
  // Without a shared bias |m_c|² has mean s_c²/n_c and standard deviation s_c²/n_c (2 axes):
  // the sum must stand out by `significance` of its own standard deviations.
  double shared = 0.0, null_variance = 0.0;
  int used = 0;
  for (const auto& [id, u] : by_feature) {
    const auto n = static_cast<double>(u.size());
    if (static_cast<int>(u.size()) < min_poses_per_feature) continue;
    Eigen::Vector2d mean = Eigen::Vector2d::Zero();
    for (const auto& v : u) mean += v / n;
    double spread = 0.0;
    for (const auto& v : u) spread += (v - mean).squaredNorm() / (n - 1.0);
    shared += mean.squaredNorm() - spread / n;
    null_variance += (spread / n) * (spread / n);
    ++used;
  }
  term->features = used;
  const double dimensions = 2.0 * features_per_pose;
  term->significance = null_variance > 0.0 ? shared / std::sqrt(null_variance) : 0.0;
  if (used == 0 || !(dimensions > 6.0) || term->significance < significance) return;
  const double variance = shared / (2.0 * used) * dimensions / (dimensions - 6.0);
  term->sigma_px = variance > 0.0 ? std::sqrt(variance) : 0.0;
}

// The modes: S̃ = blocks L_j⁻¹ S_j R_j over the feature ids (Σ_j = L_j L_jᵀ), thin SVD, the leading
// σ_b s_i u_i kept, each pose's block mapped back by L_j.
void sensitivityModes(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                      const std::vector<PoseFeatures>& poses, const std::vector<PoseResiduals>& residuals,
                      const DetectorBiasOptions& options, DetectorBiasTerm* term) {
  std::map<int, Eigen::Index> column;  // feature id → first of its two columns
  for (const PoseFeatures& p : poses)
    for (int id : p.features->ids) column.emplace(id, 0);
  Eigen::Index next = 0;
  for (auto& [id, c] : column) c = (next += 2) - 2;
  const auto P = static_cast<Eigen::Index>(poses.size());
  Eigen::MatrixXd whitened = Eigen::MatrixXd::Zero(6 * P, next);
  std::vector<Matrix6d> lower(poses.size());
  for (std::size_t j = 0; j < poses.size(); ++j) {
    // Any invertible L gives the same term; the pose's own covariance ranks the modes by what
    // they do to the pose relative to its precision (identity when that is not positive definite).
    const Eigen::LLT<Matrix6d> llt(poses[j].covariance);
    lower[j] = llt.info() == Eigen::Success ? Matrix6d(llt.matrixL()) : Matrix6d::Identity();
    const Eigen::MatrixXd S = featureSensitivity(camera, points, *poses[j].features, poses[j].cTm, options.pose);
    if (S.size() == 0) continue;
    const Eigen::MatrixXd L_inv_S = lower[j].triangularView<Eigen::Lower>().solve(S);
    const auto row = static_cast<Eigen::Index>(6 * j);
    for (std::size_t i = 0; i < poses[j].features->size(); ++i)
      whitened.block(row, column.at(poses[j].features->ids[i]), 6, 2) =
          L_inv_S.middleCols(static_cast<Eigen::Index>(2 * i), 2) * residuals[j].axes[i];
  }
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(whitened, Eigen::ComputeThinU);
  const Eigen::VectorXd power = svd.singularValues().array().square();
  const double total = power.sum();
  if (!(total > 0.0)) return;
  Eigen::Index modes = 0;
  double kept = 0.0;
  while (modes < power.size() && modes < options.max_modes && kept < options.retained_fraction * total)
    kept += power[modes++];
  term->retained = kept / total;
  for (Eigen::Index m = 0; m < modes; ++m) term->names.push_back("detector_bias_" + std::to_string(m + 1));
  const Eigen::MatrixXd scaled =
      svd.matrixU().leftCols(modes) * (term->sigma_px * svd.singularValues().head(modes)).asDiagonal();
  for (std::size_t j = 0; j < poses.size(); ++j)
    term->sensitivity[poses[j].pose_id] = lower[j] * scaled.middleRows(static_cast<Eigen::Index>(6 * j), 6);
}

}  // namespace

DetectorBiasTerm estimateDetectorBias(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                      const std::vector<PoseFeatures>& poses, const DetectorBiasOptions& options) {
  DetectorBiasTerm term;
  if (static_cast<int>(poses.size()) < options.min_poses) return term;
  std::vector<PoseResiduals> residuals;
  residuals.reserve(poses.size());
  for (const PoseFeatures& pose : poses) residuals.push_back(poseResiduals(camera, points, pose));
  estimateSharedVariance(poses, residuals, options.min_poses_per_feature, options.significance, &term);
  if (!(term.sigma_px > 0.0)) return term;
  term.poses = static_cast<int>(poses.size());
  sensitivityModes(camera, points, poses, residuals, options, &term);
  return term;
}

DetectorBiasTerm estimateDetectorBias(const calibration::Camera& camera, const Target& target,
                                      const std::vector<std::string>& pose_ids,
                                      const std::vector<const PoseMeasurement*>& measurements, const PoseOptions& pose) {
  if (pose_ids.size() != measurements.size())
    throw std::invalid_argument("estimateDetectorBias: pose_ids and measurements differ in length");
  std::vector<PoseFeatures> poses;
  for (std::size_t j = 0; j < measurements.size(); ++j) {
    const PoseMeasurement& m = *measurements[j];
    if (m.ok) poses.push_back({pose_ids[j], &m.features, m.estimate.cTm, m.estimate.covariance});
  }
  DetectorBiasOptions options;
  options.pose = pose;
  return estimateDetectorBias(camera, target.points(), poses, options);
}

std::string DetectorBiasTerm::text() const {
  char line[200];
  if (features == 0)
    std::snprintf(line, sizeof line, "not estimated (it needs 6 poses, each feature in 3)");
  else if (empty())
    std::snprintf(line, sizeof line,
                  "not seen (the shared part of the features' mean residuals is %.1f standard deviations of noise, "
                  "3 needed)",
                  significance);
  else
    std::snprintf(line, sizeof line,
                  "%.4f px per feature and axis (feature error %.4f px RMS), %zu modes in the shared-term file "
                  "(%.1f %% of its effect)",
                  sigma_px, feature_error_rms_px, names.size(), 100.0 * retained);
  return line;
}

}  // namespace mire::metrology
