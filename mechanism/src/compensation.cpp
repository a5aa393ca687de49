// Corrected commands for a controller running another geometry (compensation.hpp).
#include "mire/mechanism/compensation.hpp"

#include <Eigen/QR>

#include <cmath>
#include <stdexcept>

namespace mire::mechanism {
namespace {

// ∂q/∂X of `geometric`'s IKM at `pose` (central differences, 1 µm / 1 µrad).
Eigen::MatrixXd jointsWrtPose(const Mechanism& m, const Eigen::VectorXd& geometric, const Eigen::VectorXd& pose) {
  Eigen::MatrixXd J(m.jointCount(), pose.size());
  for (Eigen::Index k = 0; k < pose.size(); ++k) {
    const double h = 1e-6;
    Eigen::VectorXd plus = pose, minus = pose;
    plus[k] += h;
    minus[k] -= h;
    J.col(k) = (m.inverseKinematics(geometric, m.poseToTransform(plus)).joints -
                m.inverseKinematics(geometric, m.poseToTransform(minus)).joints) /
               (2.0 * h);
  }
  return J;
}

std::string jointList(const std::vector<int>& joints) {
  std::string out;
  for (int j : joints) out += (out.empty() ? "" : ", ") + std::to_string(j + 1);
  return out;
}

}  // namespace

PoseCorrection correctedCommand(const PredictionModel& identified, const Eigen::VectorXd& controller_geometric,
                                const Eigen::VectorXd& desired_pose) {
  const Mechanism& m = *identified.mechanism;
  PoseCorrection out;
  const JointPrediction q = predictJointCommands(identified, m.poseToTransform(desired_pose));
  if (!q.ikm.reachable()) {
    out.message = "unreachable (joint(s) " + jointList(q.ikm.unreachable_joints) + ")";
    return out;
  }
  if (!q.ikm.withinStroke()) {
    out.message = "outside the stroke of joint(s) " + jointList(q.ikm.out_of_stroke_joints);
    return out;
  }
  const FkmResult f = m.forwardKinematics(controller_geometric, q.ikm.joints, desired_pose);
  if (!f.converged) {
    out.message = "the controller model's FKM did not converge (" + f.message + ")";
    return out;
  }
  out.ok = true;
  out.command = f.pose;
  const Eigen::MatrixXd J = jointsWrtPose(m, controller_geometric, f.pose);
  const Eigen::MatrixXd dXdq = J.colPivHouseholderQr().solve(Eigen::MatrixXd::Identity(J.rows(), J.rows()));
  out.command_covariance = dXdq * q.covariance * dXdq.transpose();
  return out;
}

std::vector<Eigen::VectorXd> workspaceGrid(const Mechanism& mechanism, const Eigen::Vector3d& low,
                                           const Eigen::Vector3d& high, double step, std::size_t max_points) {
  if (!(step > 0.0)) throw std::invalid_argument("grid step must be > 0");
  if ((high - low).minCoeff() < 0.0) throw std::invalid_argument("empty workspace box (a maximum below its minimum)");
  Eigen::Vector3i counts;
  for (int k = 0; k < 3; ++k) counts[k] = static_cast<int>(std::floor((high[k] - low[k]) / step + 1e-9)) + 1;
  const double total = static_cast<double>(counts[0]) * counts[1] * counts[2];
  if (total > static_cast<double>(max_points))
    throw std::invalid_argument("the grid has " + std::to_string(static_cast<long long>(total)) +
                                " points (more than " + std::to_string(max_points) + "): take a larger step");
  std::vector<Eigen::VectorXd> out;
  for (int i = 0; i < counts[0]; ++i)
    for (int j = 0; j < counts[1]; ++j)
      for (int k = 0; k < counts[2]; ++k) {
        Eigen::VectorXd pose = Eigen::VectorXd::Zero(mechanism.poseDof());
        pose.head<3>() = low + step * Eigen::Vector3d(i, j, k);
        out.push_back(pose);
      }
  return out;
}

}  // namespace mire::mechanism
