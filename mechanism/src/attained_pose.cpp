// Attained effector poses from measured target poses and ISO 9283 angles (pose_accuracy.hpp).
#include <cmath>

#include "mire/mechanism/pose_accuracy.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {

Eigen::Vector3d isoAngles(const Eigen::Matrix3d& r) {
  // R = Rz(c)·Ry(b)·Rx(a): r20 = −sin b, r21 = cos b·sin a, r22 = cos b·cos a, r10 = sin c·cos b.
  const double b = std::atan2(-r(2, 0), std::hypot(r(2, 1), r(2, 2)));
  const double a = std::atan2(r(2, 1), r(2, 2));
  const double c = std::atan2(r(1, 0), r(0, 0));
  return {a, b, c};
}

IsoPose isoPose(const Eigen::Isometry3d& transform) {
  IsoPose out;
  out << transform.translation(), isoAngles(transform.linear());
  return out;
}

IsoPose isoDeviation(const Eigen::Isometry3d& commanded, const Eigen::Isometry3d& attained) {
  IsoPose d = isoPose(attained) - isoPose(commanded);
  for (int k = 3; k < 6; ++k) d[k] = std::remainder(d[k], 2.0 * support::kPi);
  return d;
}

AttainedPose attainedPose(const Eigen::Isometry3d& cTb, const Eigen::Isometry3d& eTm, const PoseVector& cTm,
                          const std::optional<PoseCovariance>& cTm_covariance) {
  const Eigen::Isometry3d bTc = cTb.inverse();
  const Eigen::Isometry3d mTe = eTm.inverse();
  const auto effector = [&](const PoseVector& x) { return Eigen::Isometry3d(bTc * toIsometry(x) * mTe); };
  AttainedPose out;
  out.bTe = effector(cTm);
  if (!cTm_covariance) return out;
  // ∂isoPose(bTe)/∂cTm by central differences (steps 1 µm / 1 µrad, far below any σ).
  Eigen::Matrix<double, 6, 6> jacobian;
  for (int k = 0; k < 6; ++k) {
    const double h = 1e-6;
    PoseVector plus = cTm, minus = cTm;
    plus[k] += h;
    minus[k] -= h;
    jacobian.col(k) = isoDeviation(effector(minus), effector(plus)) / (2.0 * h);
  }
  out.covariance = jacobian * *cTm_covariance * jacobian.transpose();
  return out;
}

}  // namespace mire::mechanism
