#pragma once
// A cylinder's axis from its two apparent contours (doc/legs.md, "Measuring a leg"): each contour
// and the optical centre span a plane tangent to the cylinder; the axis is parallel to both planes
// at the radius from each. The contours are image lines in normalised coordinates (after
// undistortion), the axis a line of support/line_3d.hpp in the camera frame.
#include <Eigen/Core>

#include <array>

#include "mire/support/line_3d.hpp"

namespace mire::metrology {

// The image line cos θ·x + sin θ·y = ρ in normalised coordinates, oriented: the rod's inside is
// where cos θ·x + sin θ·y − ρ > 0. Its plane through the optical centre has the normal
// (cos θ, sin θ, −ρ), and the rod's inside (its axis) is on the positive side of that plane.
struct ContourLine {
  double theta = 0.0;                   // rad
  double rho = 0.0;                     // normalised image units
  Eigen::Vector3d planeNormal() const;  // unit
  static ContourLine fromPlaneNormal(const Eigen::Vector3d& normal);
};

// The two contours of a cylinder of radius r whose axis is `axis` (camera frame, m), each oriented
// towards the axis. Throws std::invalid_argument when the optical centre is inside the cylinder.
std::array<ContourLine, 2> cylinderContours(const support::Line3d& axis, double radius);

// The axis from the two contours: direction n1 × n2, closest point r·(n1 + n2)/(1 + n1·n2) for the
// unit plane normals n1, n2. Throws std::invalid_argument when the contours do not bound a
// cylinder in front of the camera (parallel planes or a closest point behind the camera).
support::Line3d cylinderAxis(const std::array<ContourLine, 2>& contours, double radius);

// ∂δ/∂(θ1, ρ1, θ2, ρ2): δ of the axis (support/line_3d.hpp, in the axis's own tangent basis) for
// small changes of the contours' parameters, by central differences of cylinderAxis.
Eigen::Matrix4d cylinderAxisJacobian(const std::array<ContourLine, 2>& contours, double radius);

}  // namespace mire::metrology
