#include "mire/pipeline/pose_scores.hpp"

#include <Eigen/Cholesky>

#include <cmath>
#include <stdexcept>

namespace mire::pipeline {
namespace {

bool hasSharedTerm(const std::vector<PoseErrorSample>& samples, const Eigen::MatrixXd& camera_covariance) {
  if (camera_covariance.size() == 0) return false;
  for (const auto& s : samples)
    if (s.sensitivity.rows() != 6 || s.sensitivity.cols() != camera_covariance.rows()) return false;
  return true;
}

// RMS of L⁻¹e for C = L Lᵀ (the errors whitened with their joint covariance).
double whitenedRms(const Eigen::VectorXd& error, const Eigen::MatrixXd& covariance) {
  const Eigen::LLT<Eigen::MatrixXd> llt(covariance);
  if (llt.info() != Eigen::Success) throw std::runtime_error("pose error covariance is not positive definite");
  const Eigen::VectorXd z = llt.matrixL().solve(error);
  return std::sqrt(z.squaredNorm() / static_cast<double>(error.size()));
}

// The rows `rows` of every pose stacked: errors, and their covariance blockdiag(Σ_noise) + D Σ_k Dᵀ.
double whitenedRmsOfRows(const std::vector<PoseErrorSample>& samples, const Eigen::MatrixXd& camera_covariance,
                         const std::vector<int>& rows, bool shared) {
  const Eigen::Index r = static_cast<Eigen::Index>(rows.size());
  const Eigen::Index n = static_cast<Eigen::Index>(samples.size()) * r;
  Eigen::VectorXd error(n);
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd sensitivity(n, shared ? camera_covariance.rows() : 0);
  for (std::size_t j = 0; j < samples.size(); ++j) {
    const Eigen::Index base = static_cast<Eigen::Index>(j) * r;
    for (Eigen::Index a = 0; a < r; ++a) {
      error[base + a] = samples[j].error[rows[a]];
      for (Eigen::Index b = 0; b < r; ++b) covariance(base + a, base + b) = samples[j].independent(rows[a], rows[b]);
      if (shared) sensitivity.row(base + a) = samples[j].sensitivity.row(rows[a]);
    }
  }
  if (shared) covariance += sensitivity * camera_covariance * sensitivity.transpose();
  return whitenedRms(error, covariance);
}

}  // namespace

PoseErrorScores scorePoseErrors(const std::vector<PoseErrorSample>& samples, const Eigen::MatrixXd& camera_covariance) {
  PoseErrorScores scores;
  if (samples.empty()) return scores;
  const bool shared = hasSharedTerm(samples, camera_covariance);
  double all = 0.0;
  for (int k = 0; k < 6; ++k) {
    double sum = 0.0;
    for (const auto& s : samples) sum += std::pow(s.error[k] / s.sigma[k], 2);
    all += sum;
    scores.rms_per_pose[k] = std::sqrt(sum / static_cast<double>(samples.size()));
    scores.rms_whitened[k] = whitenedRmsOfRows(samples, camera_covariance, {k}, shared);
  }
  scores.rms_per_pose_all = std::sqrt(all / (6.0 * static_cast<double>(samples.size())));
  scores.rms_whitened_all = whitenedRmsOfRows(samples, camera_covariance, {0, 1, 2, 3, 4, 5}, shared);
  return scores;
}

}  // namespace mire::pipeline
