#include "mire/metrology/cylinder_axis.hpp"

#include <cmath>
#include <stdexcept>

namespace mire::metrology {

Eigen::Vector3d ContourLine::planeNormal() const {
  return Eigen::Vector3d(std::cos(theta), std::sin(theta), -rho).normalized();
}

ContourLine ContourLine::fromPlaneNormal(const Eigen::Vector3d& normal) {
  const double k = std::hypot(normal.x(), normal.y());
  return {std::atan2(normal.y(), normal.x()), -normal.z() / k};
}

std::array<ContourLine, 2> cylinderContours(const support::Line3d& axis, double radius) {
  const Eigen::Vector3d closest = axis.closestPointToOrigin();
  const double distance = closest.norm();
  if (!(distance > radius)) throw std::invalid_argument("the optical centre is inside the cylinder");
  // A tangent plane through the origin contains the direction d; its normal n = α·u ± β·w in the
  // plane ⟂ d (u towards the axis, w = d × u) has n·closest = r, hence α = r / distance.
  const Eigen::Vector3d u = closest / distance;
  const Eigen::Vector3d w = axis.direction.cross(u);
  const double alpha = radius / distance;
  const double beta = std::sqrt(1.0 - alpha * alpha);
  return {ContourLine::fromPlaneNormal(alpha * u + beta * w), ContourLine::fromPlaneNormal(alpha * u - beta * w)};
}

support::Line3d cylinderAxis(const std::array<ContourLine, 2>& contours, double radius) {
  const Eigen::Vector3d n1 = contours[0].planeNormal();
  const Eigen::Vector3d n2 = contours[1].planeNormal();
  const Eigen::Vector3d direction = n1.cross(n2);
  const double c = n1.dot(n2);
  if (direction.norm() < 1e-12 || !(1.0 + c > 1e-15))
    throw std::invalid_argument("the two contours do not bound a cylinder (parallel tangent planes)");
  // n1·p = n2·p = r with p in the span of n1 and n2 (⟂ the direction): p = r·(n1 + n2)/(1 + c).
  const Eigen::Vector3d closest = radius * (n1 + n2) / (1.0 + c);
  if (!(closest.z() > 0.0)) throw std::invalid_argument("the two contours bound a cylinder behind the camera");
  return support::Line3d::fromPointAndDirection(closest, direction);
}

Eigen::Matrix4d cylinderAxisJacobian(const std::array<ContourLine, 2>& contours, double radius) {
  const support::Line3d axis = cylinderAxis(contours, radius);
  Eigen::Matrix4d jacobian;
  for (int k = 0; k < 4; ++k) {
    // Steps a million times smaller than the contours' own scale: the axis is smooth in them.
    const double step = 1e-7;
    std::array<ContourLine, 2> plus = contours, minus = contours;
    double* p = k % 2 == 0 ? &plus[k / 2].theta : &plus[k / 2].rho;
    double* m = k % 2 == 0 ? &minus[k / 2].theta : &minus[k / 2].rho;
    *p += step;
    *m -= step;
    jacobian.col(k) = (support::lineDifference(cylinderAxis(plus, radius), axis) -
                       support::lineDifference(cylinderAxis(minus, radius), axis)) /
                      (2.0 * step);
  }
  return jacobian;
}

}  // namespace mire::metrology
