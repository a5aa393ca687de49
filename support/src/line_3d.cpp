#include "mire/support/line_3d.hpp"

#include <cmath>

namespace mire::support {

Line3d Line3d::fromPointAndDirection(const Eigen::Vector3d& point, const Eigen::Vector3d& direction) {
  const Eigen::Vector3d d = direction.normalized();
  return {d, point.cross(d)};
}

Line3d Line3d::throughPoints(const Eigen::Vector3d& from, const Eigen::Vector3d& to) {
  return fromPointAndDirection(from, to - from);
}

Line3d Line3d::transformed(const Eigen::Isometry3d& a_T_b) const {
  const Eigen::Vector3d d = a_T_b.linear() * direction;
  return fromPointAndDirection(a_T_b * closestPointToOrigin(), d);
}

double Line3d::distanceTo(const Eigen::Vector3d& point) const { return (point.cross(direction) - moment).norm(); }

std::pair<Eigen::Vector3d, Eigen::Vector3d> lineTangentBasis(const Eigen::Vector3d& direction) {
  const Eigen::Vector3d d = direction.normalized();
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(d[i]) < std::abs(d[axis])) axis = i;
  const Eigen::Vector3d e1 = Eigen::Vector3d::Unit(axis).cross(d).normalized();
  return {e1, d.cross(e1)};
}

Line3d perturbLine(const Line3d& line, const Eigen::Vector4d& delta) {
  const auto [e1, e2] = lineTangentBasis(line.direction);
  const Eigen::Vector3d d = (line.direction + delta[0] * e1 + delta[1] * e2).normalized();
  Eigen::Vector3d c = line.closestPointToOrigin() + delta[2] * e1 + delta[3] * e2;
  c -= c.dot(d) * d;
  return {d, c.cross(d)};
}

Eigen::Vector4d lineDifference(const Line3d& line, const Line3d& reference) {
  const Line3d aligned = line.direction.dot(reference.direction) < 0 ? line.reversed() : line;
  const auto [e1, e2] = lineTangentBasis(reference.direction);
  // a: the direction's components in the tangent plane once scaled to unit length along the
  // reference (exactly perturbLine's a); b: the closest point's move within the normal plane
  // (perturbLine's b to first order: its re-projection onto the plane ⟂ d' is of second order).
  const Eigen::Vector3d d = aligned.direction / aligned.direction.dot(reference.direction);
  const Eigen::Vector3d c = aligned.closestPointToOrigin();
  return {d.dot(e1), d.dot(e2), c.dot(e1) - reference.closestPointToOrigin().dot(e1),
          c.dot(e2) - reference.closestPointToOrigin().dot(e2)};
}

}  // namespace mire::support
