#include "mire/mechanism/pose.hpp"

#include <set>
#include <stdexcept>

#include <Eigen/Cholesky>

namespace mire::mechanism {

Eigen::Isometry3d toIsometry(const PoseVector& pose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const Eigen::Vector3d r = pose.tail<3>();
  const double angle = r.norm();
  T.linear() = angle > 0.0 ? Eigen::AngleAxisd(angle, r / angle).toRotationMatrix()
                           : Eigen::Matrix3d::Identity();
  T.translation() = pose.head<3>();
  return T;
}

PoseVector toPoseVector(const Eigen::Isometry3d& transform) {
  const Eigen::AngleAxisd aa(transform.linear());
  PoseVector pose;
  pose << transform.translation(), aa.axis() * aa.angle();
  return pose;
}

void validatePoses(const std::vector<PoseObservation>& poses, int joint_count) {
  std::set<std::string> ids;
  for (const PoseObservation& p : poses) {
    const std::string where = "pose '" + p.id + "': ";
    if (!ids.insert(p.id).second) throw std::invalid_argument(where + "id appears twice");
    if (!p.cTm.allFinite()) throw std::invalid_argument(where + "cTm has a non-finite value");
    if (p.joints.size() != joint_count)
      throw std::invalid_argument(where + std::to_string(p.joints.size()) + " joint values, expected " +
                                  std::to_string(joint_count));
    if (!p.joints.allFinite()) throw std::invalid_argument(where + "a joint value is not finite");
    if (p.covariance) {
      const PoseCovariance& c = *p.covariance;
      if (!c.allFinite()) throw std::invalid_argument(where + "covariance has a non-finite value");
      if (!c.isApprox(c.transpose(), 1e-9) && (c - c.transpose()).norm() > 1e-20)
        throw std::invalid_argument(where + "covariance is not symmetric");
      if (Eigen::LLT<PoseCovariance>(c).info() != Eigen::Success)
        throw std::invalid_argument(where + "covariance is not positive definite");
    }
  }
}

}  // namespace mire::mechanism
