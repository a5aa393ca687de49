#include "pose_chunk_cost.hpp"

#include <Eigen/Core>
#include <Eigen/QR>

#include <algorithm>
#include <cmath>

namespace mire::mechanism::detail {

namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// ρ(s) and the rescaling Ceres applies to a block's residual r and Jacobian J under a loss
// (Triggs et al., as in Ceres' Corrector): r̃ = r·√ρ′/(1 − α), J̃ = √ρ′ (J − α/s · r rᵀJ),
// with α the root of ½α² − α − ρ″s/ρ′ = 0; α = 0 where ρ″ ≤ 0 (Huber, Cauchy).
double applyLoss(const ceres::LossFunction* loss, Eigen::Ref<Eigen::VectorXd> r, Eigen::Ref<Eigen::MatrixXd> J) {
  const double s = r.squaredNorm();
  if (loss == nullptr) return s;
  double rho[3];
  loss->Evaluate(s, rho);
  const double sqrt_rho1 = std::sqrt(rho[1]);
  if (s == 0.0 || rho[2] <= 0.0) {
    r *= sqrt_rho1;
    J *= sqrt_rho1;
    return rho[0];
  }
  const double alpha = 1.0 - std::sqrt(std::max(0.0, 1.0 + 2.0 * s * rho[2] / rho[1]));
  const Eigen::RowVectorXd rtJ = r.transpose() * J;
  J = sqrt_rho1 * (J - (alpha / s) * r * rtJ);
  r *= sqrt_rho1 / (1.0 - alpha);
  return rho[0];
}

}  // namespace

PoseChunkCost::PoseChunkCost(std::vector<std::unique_ptr<ceres::CostFunction>> poses,
                             std::shared_ptr<const ceres::LossFunction> loss, int joints, int geometric, int external)
    : poses_(std::move(poses)), loss_(std::move(loss)), joints_(joints), geometric_(geometric), external_(external) {
  set_num_residuals(geometric + external + 1);
  mutable_parameter_block_sizes()->push_back(geometric);
  mutable_parameter_block_sizes()->push_back(external);
}

bool PoseChunkCost::costOnly(double const* const* parameters, double* rho_sum) const {
  *rho_sum = 0.0;
  Eigen::VectorXd r(joints_);
  Eigen::MatrixXd none(joints_, 0);
  for (const auto& pose : poses_) {
    if (!pose->Evaluate(parameters, r.data(), nullptr)) return false;
    *rho_sum += applyLoss(loss_.get(), r, none);
  }
  return true;
}

bool PoseChunkCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const int P = geometric_ + external_, M = P + 1;
  Eigen::Map<Eigen::VectorXd> out(residuals, M);
  double rho_sum = 0.0;
  if (jacobians == nullptr) {
    // The cost alone (a trial step): a residual of the same norm.
    if (!costOnly(parameters, &rho_sum)) return false;
    out.setZero();
    out[0] = std::sqrt(rho_sum);
    return true;
  }
  // [J̃ r̃] of every pose, at least M rows (zero rows pad a small chunk).
  const auto rows = std::max<Eigen::Index>(M, static_cast<Eigen::Index>(poses_.size()) * joints_);
  Eigen::MatrixXd stacked = Eigen::MatrixXd::Zero(rows, M);
  RowMajor Jg(joints_, geometric_), Je(joints_, external_);
  double* pose_jacobians[2] = {Jg.data(), Je.data()};
  Eigen::VectorXd r(joints_);
  for (std::size_t j = 0; j < poses_.size(); ++j) {
    if (!poses_[j]->Evaluate(parameters, r.data(), pose_jacobians)) return false;
    auto block = stacked.middleRows(static_cast<Eigen::Index>(j) * joints_, joints_);
    block.leftCols(geometric_) = Jg;
    block.middleCols(geometric_, external_) = Je;
    block.col(P) = r;
    rho_sum += applyLoss(loss_.get(), block.col(P), block.leftCols(P));
  }
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(stacked);
  const Eigen::MatrixXd R = qr.matrixQR().topRows(M).triangularView<Eigen::Upper>();
  // (c, d): c from the QR, d completes the cost to ½Σρ (ρ(s) ≥ ρ′(s)·s for these losses, so
  // the difference is the orthogonal part's norm², up to rounding).
  out.head(P) = R.col(P).head(P);
  out[P] = std::sqrt(std::max(0.0, rho_sum - out.head(P).squaredNorm()));
  if (jacobians[0] != nullptr) Eigen::Map<RowMajor>(jacobians[0], M, geometric_) = R.leftCols(geometric_);
  if (jacobians[1] != nullptr) Eigen::Map<RowMajor>(jacobians[1], M, external_) = R.middleCols(geometric_, external_);
  return true;
}

}  // namespace mire::mechanism::detail
