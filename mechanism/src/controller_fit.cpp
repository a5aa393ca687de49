// A controller model's parameters fitted to an identified robot (controller_fit.hpp).
#include "mire/mechanism/controller_fit.hpp"

#include <ceres/ceres.h>

#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>

#include "mire/support/constants.hpp"

namespace mire::mechanism {
namespace {

// F from (rx, ry, rz, tx, ty, tz).
Eigen::Isometry3d frameOf(const double* f) {
  PoseVector v;
  v << f[3], f[4], f[5], f[0], f[1], f[2];
  return toIsometry(v);
}

// F·X as the controller can command it: its own pose components (a Delta keeps the identity
// orientation, an H4 its rotation about z).
Eigen::Isometry3d controllerPose(const Mechanism& controller, const Eigen::Isometry3d& frame,
                                 const Eigen::Isometry3d& pose) {
  return controller.poseToTransform(controller.transformToPose(frame * pose));
}

// IKM_controller(F·X, ξc) − IKM_identified(X) at one pose, over the controller's free parameters
// and the frame F.
struct JointMismatch {
  const Mechanism* mechanism;
  ParameterSet parameters;  // the controller's, fixed values kept
  std::vector<std::size_t> free;
  Eigen::Isometry3d pose;
  Eigen::VectorXd target;
  std::vector<bool> revolute;

  bool operator()(double const* const* blocks, double* residual) const {
    const Eigen::Isometry3d frame = frameOf(blocks[1]);
    Eigen::VectorXd values = parameters.values();
    for (std::size_t k = 0; k < free.size(); ++k) values[static_cast<Eigen::Index>(free[k])] = blocks[0][k];
    ParameterSet p = parameters;
    p.setValues(values);  // re-synchronises tied parameters
    const IkmResult q = mechanism->inverseKinematics(p.values(), controllerPose(*mechanism, frame, pose));
    if (!q.reachable()) return false;
    // Revolute joints agree modulo 2π (the models may take their angles on different branches).
    for (Eigen::Index k = 0; k < target.size(); ++k) {
      const double difference = q.joints[k] - target[k];
      residual[k] = revolute[static_cast<std::size_t>(k)] ? std::remainder(difference, 2.0 * support::kPi) : difference;
    }
    return true;
  }
};

}  // namespace

Eigen::VectorXd controllerCommand(const Mechanism& controller, const Eigen::Isometry3d& frame,
                                  const Eigen::Isometry3d& pose) {
  return controller.transformToPose(frame * pose);
}

ControllerFit fitControllerModel(const PredictionModel& identified, const RegisteredModel& controller,
                                 const std::vector<Eigen::VectorXd>& workspace) {
  const Mechanism& id = *identified.mechanism;
  const Mechanism& c = *controller.mechanism;
  if (id.jointCount() != c.jointCount() || id.poseComponentNames() != c.poseComponentNames())
    throw std::invalid_argument("the controller model " + controller.name + " does not drive the same joints and pose " +
                                "components as the identified " + identified.model_name);
  ControllerFit fit;
  fit.parameters = controller.nominal;
  const std::vector<std::size_t> free = fit.parameters.freeIndices();
  std::vector<double> x;
  for (std::size_t k : free) x.push_back(fit.parameters[k].value);
  std::array<double, 6> frame{};  // rx, ry, rz, tx, ty, tz
  ceres::Problem problem;
  std::vector<Eigen::VectorXd> used;
  std::vector<bool> revolute;
  for (Unit u : c.jointUnits()) revolute.push_back(u == Unit::Radian);
  for (const Eigen::VectorXd& pose : workspace) {
    const Eigen::Isometry3d T = id.poseToTransform(pose);
    const IkmResult target = id.inverseKinematics(identified.geometric.values(), T);
    if (!target.reachable() || !c.inverseKinematics(fit.parameters.values(), T).reachable()) continue;
    auto cost = std::make_unique<ceres::DynamicNumericDiffCostFunction<JointMismatch, ceres::CENTRAL>>(
        new JointMismatch{&c, fit.parameters, free, T, target.joints, revolute});
    cost->AddParameterBlock(static_cast<int>(x.size()));
    cost->AddParameterBlock(6);
    cost->SetNumResiduals(c.jointCount());
    problem.AddResidualBlock(cost.release(), nullptr, x.data(), frame.data());
    used.push_back(pose);
  }
  if (used.empty()) throw std::invalid_argument("no workspace pose is reachable by both models");
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 200;
  options.function_tolerance = 1e-14;
  options.parameter_tolerance = 1e-12;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  fit.converged = summary.IsSolutionUsable();
  Eigen::VectorXd values = fit.parameters.values();
  for (std::size_t k = 0; k < free.size(); ++k) values[static_cast<Eigen::Index>(free[k])] = x[k];
  fit.parameters.setValues(values);
  fit.frame = frameOf(frame.data());
  fit.poses = static_cast<int>(used.size());
  fit.rms_joint_residual = std::sqrt(2.0 * summary.final_cost / (static_cast<double>(used.size()) * c.jointCount()));
  // Where the identified robot goes with the fitted controller's commands.
  double sum_sq = 0.0;
  int counted = 0;
  for (const Eigen::VectorXd& pose : used) {
    const IkmResult q =
        c.inverseKinematics(fit.parameters.values(), controllerPose(c, fit.frame, id.poseToTransform(pose)));
    if (!q.reachable()) continue;
    const FkmResult f = id.forwardKinematics(identified.geometric.values(), q.joints, pose);
    if (!f.converged) continue;
    const double e = (f.bTe.translation() - id.poseToTransform(pose).translation()).norm();
    sum_sq += e * e;
    ++counted;
    if (e >= fit.max_position_error) {
      fit.max_position_error = e;
      fit.worst_pose = pose;
    }
  }
  fit.rms_position_error = counted > 0 ? std::sqrt(sum_sq / counted) : 0.0;
  return fit;
}

}  // namespace mire::mechanism
