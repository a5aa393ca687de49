#pragma once
// A leg seen by the camera (doc/legs.md): the axis of one leg's rod as a 3D line in the camera
// frame at one pose, with its 4×4 covariance in the line perturbation of support/line_3d.hpp, and
// the line the model predicts for it through the mounting.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "mire/mechanism/external.hpp"
#include "mire/mechanism/mechanism.hpp"
#include "mire/support/line_3d.hpp"

namespace mire::mechanism {

struct LegObservation {
  std::string pose_id;
  int leg = 0;                                               // 0-based, in joint order
  support::Line3d line;                                      // the leg's axis in the camera frame
  Eigen::Matrix4d covariance = Eigen::Matrix4d::Identity();  // δ = (a1, a2 [rad], b1, b2 [m])
};

// The leg's axis in the camera frame predicted for the effector transform bTe through the mounting:
// cTb · (segment of `leg`). Throws std::runtime_error when the pose is unreachable.
support::Line3d predictedLegLine(const Mechanism& mechanism, const ExternalParameterization& external,
                                 const Eigen::VectorXd& geometric, const Eigen::VectorXd& external_values,
                                 const Eigen::Isometry3d& bTe, int leg);

// Throws std::invalid_argument naming the pose id and leg when a leg index is out of range, a value
// non-finite, a direction not unit, a moment not ⟂ its direction, or a covariance not symmetric
// positive definite.
void validateLegObservations(const std::vector<LegObservation>& legs, int leg_count);

}  // namespace mire::mechanism
