#pragma once
// The reference a held-out prediction is compared with: a plain least-squares fit of every
// geometric and mounting parameter (no gauge analysis, no weights, no shared term), Ceres'
// Levenberg–Marquardt from the initial model mire itself starts from. A ridge of 10⁻⁴ (residual
// units per parameter unit) toward that start pins the directions the data do not see, which
// would otherwise drift (a turn of the base frame is a gauge only to first order); it moves a
// determined parameter by far less than its σ. With `align_mean_orientation`, a plate that only
// translates gets the rotation its joints cannot see from the mean measured orientation
// (mechanism::alignTranslatingTarget), without which no fit predicts a camera that rides on it.
#include <ceres/ceres.h>
#include <ceres/normal_prior.h>

#include <memory>
#include <string>
#include <vector>

#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/mechanism/registry.hpp"

namespace mire::test {

inline mechanism::PredictionModel plainLeastSquares(const mechanism::RegisteredModel& registered,
                                                    const std::vector<mechanism::PoseObservation>& poses,
                                                    bool align_mean_orientation = false) {
  namespace mech = mire::mechanism;
  mech::IdentificationResult result;
  result.model = mech::makeInitialModel(registered.mechanism, registered.nominal, poses, registered.external_form);
  mech::IdentificationModel& model = result.model;
  Eigen::VectorXd geometric = model.geometricValues(), external = model.externalValues();
  ceres::Problem problem;
  const Eigen::MatrixXd identity =
      Eigen::MatrixXd::Identity(model.mechanism->jointCount(), model.mechanism->jointCount());
  for (const mech::PoseObservation& pose : poses)
    problem.AddResidualBlock(
        model.mechanism->makeJointResidual(model.external, pose.cTm, pose.joints, identity).release(), nullptr,
        geometric.data(), external.data());
  const auto ridge = [](const Eigen::VectorXd& start) {
    return new ceres::NormalPrior(1e-4 * Eigen::MatrixXd::Identity(start.size(), start.size()), start);
  };
  problem.AddResidualBlock(ridge(geometric), nullptr, geometric.data());
  problem.AddResidualBlock(ridge(external), nullptr, external.data());
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 500;
  options.function_tolerance = options.gradient_tolerance = options.parameter_tolerance = 1e-16;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  Eigen::VectorXd values(model.parameters.size());
  values << geometric, external;
  model.parameters.setValues(values);
  if (align_mean_orientation) mech::alignTranslatingTarget(*model.mechanism, model.external, model.parameters, poses);
  return mech::predictionModelFrom(registered.name, result);
}

}  // namespace mire::test
