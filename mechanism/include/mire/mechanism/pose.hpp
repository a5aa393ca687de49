#pragma once
// Measured poses and joint readings exchanged by the identification (doc/conventions.md, doc/file-formats.md).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <optional>
#include <string>
#include <vector>

namespace mire::mechanism {

// A rigid transform as in poses.csv: (tx, ty, tz) [m], then (rx, ry, rz) [rad], a rotation
// vector as cv::Rodrigues uses it.
using PoseVector = Eigen::Matrix<double, 6, 1>;
using PoseCovariance = Eigen::Matrix<double, 6, 6>;  // of a PoseVector, in (m, rad)

Eigen::Isometry3d toIsometry(const PoseVector& pose);
PoseVector toPoseVector(const Eigen::Isometry3d& transform);

// A rotation matrix's rotation vector (axis × angle, angle in [0, π]), and back.
Eigen::Vector3d rotationVector(const Eigen::Matrix3d& rotation);
Eigen::Matrix3d fromRotationVector(const Eigen::Vector3d& rotation_vector);

// One calibration pose: the measured target pose cTm and the encoder readings q̄.
struct PoseObservation {
  std::string id;                            // pose id, used in every message
  PoseVector cTm = PoseVector::Zero();       // camera <- target
  Eigen::VectorXd joints;                    // q̄ [rad], one per actuated joint
  std::optional<PoseCovariance> covariance;  // of cTm, when the measurement gives it
};

// Throws std::invalid_argument naming the pose id when a value is non-finite, the joint
// count differs from `joint_count`, a covariance is not symmetric positive definite, or
// ids repeat.
void validatePoses(const std::vector<PoseObservation>& poses, int joint_count);

}  // namespace mire::mechanism
