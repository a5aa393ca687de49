// Experiment design for hand-eye calibration: the information each candidate robot pose brings
// and a greedy choice of poses (see hand_eye.hpp).
#include <ceres/ceres.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <limits>
#include <stdexcept>

#include "hand_eye_cost.hpp"
#include "mire/mechanism/hand_eye.hpp"

namespace mire::mechanism {

namespace {

using Matrix12 = Eigen::Matrix<double, 12, 12>;

// Σ σ²/σ_ref² over the first transform's six values; infinite while the set is singular.
double designCost(const Matrix12& information, const RobotPoseSigma& reference) {
  const Eigen::FullPivLU<Matrix12> lu(information);
  if (!lu.isInvertible()) return std::numeric_limits<double>::infinity();
  const Matrix12 covariance = lu.inverse();
  double cost = 0.0;
  for (int k = 0; k < 6; ++k) {
    const double sigma_ref = k < 3 ? reference.translation_m : reference.rotation_rad;
    cost += covariance(k, k) / (sigma_ref * sigma_ref);
  }
  return cost;
}

}  // namespace

Matrix12 handEyePoseInformation(const HandEyeDesignModel& model, const Eigen::Isometry3d& bTe) {
  // The noise-free measurement of this pose: the residuals' Jacobian at the truth.
  const Eigen::Isometry3d cTm = handEyePredictedTarget(model.mounting, model.X, model.Z, bTe);
  HandEyeObservation pose;
  pose.bTe = toPoseVector(bTe);
  pose.cTm = toPoseVector(cTm);
  pose.cTm_covariance = model.camera_covariance;
  pose.robot_sigma = model.robot_sigma;
  const detail::CameraCost camera{model.mounting,    bTe.linear(),      cTm.linear(),
                                  bTe.translation(), cTm.translation(), detail::cameraWhitening(pose)};
  const ceres::AutoDiffCostFunction<detail::CameraCost, 6, 6, 6, 6> cost(new detail::CameraCost(camera));
  const PoseVector x = toPoseVector(model.X), z = toPoseVector(model.Z), d = PoseVector::Zero();
  const double* parameters[] = {x.data(), z.data(), d.data()};
  Eigen::Matrix<double, 6, 6, Eigen::RowMajor> Jx, Jz, Jd;
  double* jacobians[] = {Jx.data(), Jz.data(), Jd.data()};
  double residual[6];
  cost.Evaluate(parameters, residual, jacobians);
  Eigen::Matrix<double, 6, 12> Jg;
  Jg << Jx, Jz;
  // The prior on the nuisance pose d adds diag(1/σ²) to its information.
  Eigen::Matrix<double, 6, 6> Hdd = Jd.transpose() * Jd;
  Hdd.diagonal().head<3>().array() += 1.0 / (model.robot_sigma.translation_m * model.robot_sigma.translation_m);
  Hdd.diagonal().tail<3>().array() += 1.0 / (model.robot_sigma.rotation_rad * model.robot_sigma.rotation_rad);
  const Eigen::Matrix<double, 12, 6> Hgd = Jg.transpose() * Jd;
  return Jg.transpose() * Jg - Hgd * Hdd.ldlt().solve(Hgd.transpose());
}

HandEyePlan planHandEye(const HandEyeDesignModel& model, const std::vector<Eigen::Isometry3d>& candidates,
                        std::size_t count) {
  if (count < 3 || count > candidates.size())
    throw std::invalid_argument("hand-eye plan: choose between 3 and " + std::to_string(candidates.size()) +
                                " poses, not " + std::to_string(count));
  if (!(model.robot_sigma.translation_m > 0.0) || !(model.robot_sigma.rotation_rad > 0.0))
    throw std::invalid_argument("hand-eye plan: the robot's sigma must be > 0");
  std::vector<Matrix12> information;
  information.reserve(candidates.size());
  for (const Eigen::Isometry3d& bTe : candidates) information.push_back(handEyePoseInformation(model, bTe));
  // A tiny ridge keeps the first picks comparable while the set is still singular.
  const Matrix12 ridge = 1e-9 * Matrix12::Identity() * information.front().diagonal().maxCoeff();
  Matrix12 total = Matrix12::Zero();
  std::vector<bool> taken(candidates.size(), false);
  HandEyePlan plan;
  while (plan.chosen.size() < count) {
    std::size_t best = candidates.size();
    double best_cost = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      if (taken[i]) continue;
      const double cost = designCost(total + information[i] + ridge, model.robot_sigma);
      if (best == candidates.size() || cost < best_cost) {
        best = i;
        best_cost = cost;
      }
    }
    taken[best] = true;
    total += information[best];
    plan.chosen.push_back(best);
  }
  const Eigen::FullPivLU<Matrix12> lu(total);
  if (!lu.isInvertible())
    throw std::invalid_argument(
        "hand-eye plan: the candidates do not determine the transforms (rotations about "
        "one axis only?)");
  plan.covariance = lu.inverse();
  plan.sigma = plan.covariance.diagonal().cwiseSqrt();
  return plan;
}

}  // namespace mire::mechanism
