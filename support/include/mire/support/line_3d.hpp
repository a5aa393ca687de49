#pragma once
// A 3D line in Plücker coordinates and its 4-parameter local perturbation: the one definition the
// leg measurement (metrology, writes legs.csv) and the leg identification (mechanism, reads it)
// share, so that a covariance written by one means the same thing to the other
// (doc/file-formats.md, "legs.csv").
//
// A line is (d, m): d a unit direction, m = p × d its moment for any point p on it (m ⟂ d, |m| is
// the line's distance to the origin). Its closest point to the origin is d × m. Its 4 degrees of
// freedom are perturbed in the tangent basis (e1, e2) of d (lineTangentBasis):
//   δ = (a1, a2, b1, b2):  d' = normalise(d + a1 e1 + a2 e2),  c' = d × m + b1 e1 + b2 e2,
//   then m' = c' × d' (c' is projected onto the plane ⟂ d' first).
// a in radians (small rotations of the direction), b in metres (displacements of the closest
// point). A line has no orientation: d and −d are the same line; lineDifference aligns the signs.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <utility>

namespace mire::support {

struct Line3d {
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();  // unit
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();      // p × d [m], ⟂ direction

  static Line3d throughPoints(const Eigen::Vector3d& from, const Eigen::Vector3d& to);
  static Line3d fromPointAndDirection(const Eigen::Vector3d& point, const Eigen::Vector3d& direction);
  Eigen::Vector3d closestPointToOrigin() const { return direction.cross(moment); }
  // The same line with the direction reversed (moment reversed too).
  Line3d reversed() const { return {-direction, -moment}; }
  // The line moved by the rigid transform aTb (this line given in frame b, the result in frame a).
  Line3d transformed(const Eigen::Isometry3d& a_T_b) const;
  // Distance from a point to the line.
  double distanceTo(const Eigen::Vector3d& point) const;
};

// (e1, e2): a right-handed orthonormal basis of the plane ⟂ d with e1 × e2 = d, built from the
// coordinate axis least aligned with d (the first of x, y, z on ties): e1 = normalise(axis × d),
// e2 = d × e1. Deterministic, so a writer and a reader of legs.csv build the same basis from d.
std::pair<Eigen::Vector3d, Eigen::Vector3d> lineTangentBasis(const Eigen::Vector3d& direction);

// The line perturbed by δ = (a1, a2, b1, b2) in its own tangent basis (header comment).
Line3d perturbLine(const Line3d& line, const Eigen::Vector4d& delta);

// The δ, in the tangent basis of `reference`, that takes `reference` to `line` to first order
// (the inverse of perturbLine for small δ): the residual of a predicted line against a measured
// one, with the measured line as the reference. `line`'s sign is first aligned with the
// reference's direction.
Eigen::Vector4d lineDifference(const Line3d& line, const Line3d& reference);

}  // namespace mire::support
