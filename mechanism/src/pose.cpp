#include "mire/mechanism/pose.hpp"

#include <stdexcept>
#include <string_view>
#include <unordered_set>

#include <Eigen/Cholesky>

namespace mire::mechanism {

Eigen::Vector3d rotationVector(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd aa(rotation);
  return aa.axis() * aa.angle();
}

Eigen::Matrix3d fromRotationVector(const Eigen::Vector3d& rotation_vector) {
  const double angle = rotation_vector.norm();
  return angle > 0.0 ? Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
}

Eigen::Isometry3d toIsometry(const PoseVector& pose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = fromRotationVector(pose.tail<3>());
  T.translation() = pose.head<3>();
  return T;
}

PoseVector toPoseVector(const Eigen::Isometry3d& transform) {
  PoseVector pose;
  pose << transform.translation(), rotationVector(transform.linear());
  return pose;
}

void validatePoses(const std::vector<PoseObservation>& poses, int joint_count) {
  // Hashed views (no copies): linear in the pose count and small enough for the caches at
  // 10⁵ poses, unlike a tree of copied strings (doc/studies/2026-11-24-identify-scaling.md).
  std::unordered_set<std::string_view> ids(poses.size());
  for (const PoseObservation& p : poses) {
    const auto where = [&p] { return "pose '" + p.id + "': "; };
    if (!ids.insert(p.id).second) throw std::invalid_argument(where() + "id appears twice");
    if (!p.cTm.allFinite()) throw std::invalid_argument(where() + "cTm has a non-finite value");
    if (p.joints.size() != joint_count)
      throw std::invalid_argument(where() + std::to_string(p.joints.size()) + " joint values, expected " +
                                  std::to_string(joint_count));
    if (!p.joints.allFinite()) throw std::invalid_argument(where() + "a joint value is not finite");
    if (p.covariance) {
      const PoseCovariance& c = *p.covariance;
      if (!c.allFinite()) throw std::invalid_argument(where() + "covariance has a non-finite value");
      if (!c.isApprox(c.transpose(), 1e-9) && (c - c.transpose()).norm() > 1e-20)
        throw std::invalid_argument(where() + "covariance is not symmetric");
      if (Eigen::LLT<PoseCovariance>(c).info() != Eigen::Success)
        throw std::invalid_argument(where() + "covariance is not positive definite");
    }
  }
}

}  // namespace mire::mechanism
