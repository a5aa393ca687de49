#pragma once
// Compensation for a controller that runs another geometry than the identified one (doc/accuracy.md,
// "Compensation"): the pose to command so that the identified robot reaches a desired pose,
//   command = FKM_controller(IKM_identified(desired)),
// and its σ from the identified parameters' covariance (Σq of predictJointCommands, mapped through
// the controller's ∂X/∂q = (∂q/∂X)⁻¹, central differences of its IKM).
#include <Eigen/Core>

#include <string>
#include <vector>

#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/prediction.hpp"

namespace mire::mechanism {

struct PoseCorrection {
  bool ok = false;
  std::string message;                 // why not, when not ok
  Eigen::VectorXd command;             // pose components, controller's frame = identified base frame
  Eigen::MatrixXd command_covariance;  // of `command`
};

// `controller_geometric` in `identified.mechanism`'s parameter order (the controller runs the same
// kinematic model, e.g. its nominal geometry). Unreachable or out-of-stroke poses, and an FKM
// that does not converge, give ok = false with the reason.
PoseCorrection correctedCommand(const PredictionModel& identified, const Eigen::VectorXd& controller_geometric,
                                const Eigen::VectorXd& desired_pose);

// The points of a box (pose components beyond x, y, z at 0), `step` apart, corners included.
// Throws std::invalid_argument for a step ≤ 0, an empty box, or more than `max_points` points.
std::vector<Eigen::VectorXd> workspaceGrid(const Mechanism& mechanism, const Eigen::Vector3d& low,
                                           const Eigen::Vector3d& high, double step, std::size_t max_points = 200000);

}  // namespace mire::mechanism
