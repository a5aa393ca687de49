#pragma once
// A measured rigid transform with its uncertainty. Translation in metres; rotation as a
// rotation vector (as cv::Rodrigues uses). Covariance order: tx ty tz rx ry rz.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace mire::metrology {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

inline Eigen::Isometry3d isometryFromVectors(const Eigen::Vector3d& translation, const Eigen::Vector3d& rotation_vector) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const double angle = rotation_vector.norm();
  if (angle > 0.0) pose.linear() = Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
  pose.translation() = translation;
  return pose;
}

inline Eigen::Vector3d rotationVector(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd axis_angle(rotation);
  return axis_angle.axis() * axis_angle.angle();
}

}  // namespace mire::metrology
