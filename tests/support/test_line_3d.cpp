// The Plücker line shared by legs.csv's writer and reader: the local perturbation and the
// difference are inverse to first order, the basis is the documented one, a line has no sign.
#include <gtest/gtest.h>

#include "mire/support/line_3d.hpp"

#include <random>

namespace mire::support {
namespace {

Line3d someLine() { return Line3d::throughPoints({0.1, -0.2, 0.9}, {0.15, 0.1, 1.1}); }

TEST(Line3d, MomentIsOrthogonalAndGivesTheDistanceToTheOrigin) {
  const Line3d line = someLine();
  EXPECT_NEAR(line.direction.norm(), 1.0, 1e-15);
  EXPECT_NEAR(line.direction.dot(line.moment), 0.0, 1e-15);
  EXPECT_NEAR(line.distanceTo(Eigen::Vector3d::Zero()), line.moment.norm(), 1e-15);
  EXPECT_NEAR(line.distanceTo({0.15, 0.1, 1.1}), 0.0, 1e-15);
  EXPECT_NEAR(line.closestPointToOrigin().dot(line.direction), 0.0, 1e-15);
}

TEST(Line3d, TangentBasisIsRightHandedAndUsesTheLeastAlignedAxis) {
  for (const Eigen::Vector3d& d : {Eigen::Vector3d(0.1, 0.2, 0.97), Eigen::Vector3d(-0.9, 0.1, 0.2),
                                   Eigen::Vector3d(0.0, 0.0, 1.0), Eigen::Vector3d(0.3, -0.95, 0.0)}) {
    const auto [e1, e2] = lineTangentBasis(d);
    const Eigen::Vector3d u = d.normalized();
    EXPECT_NEAR(e1.norm(), 1.0, 1e-15);
    EXPECT_NEAR(e1.dot(u), 0.0, 1e-15);
    EXPECT_LT((e1.cross(e2) - u).norm(), 1e-15);
  }
  const auto [e1, e2] = lineTangentBasis({0.0, 0.0, 1.0});  // x is the first least aligned axis
  EXPECT_LT((e1 - Eigen::Vector3d(0, -1, 0)).norm(), 1e-15);
  EXPECT_LT((e2 - Eigen::Vector3d(1, 0, 0)).norm(), 1e-15);
}

TEST(Line3d, DifferenceInvertsThePerturbationToFirstOrder) {
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  const Line3d line = someLine();
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Vector4d delta(1e-4 * normal(random), 1e-4 * normal(random), 1e-4 * normal(random),
                                1e-4 * normal(random));
    const Eigen::Vector4d back = lineDifference(perturbLine(line, delta), line);
    // Second order in δ: the closest point moves with the direction (|c| ≈ 1 m here).
    EXPECT_LT((back - delta).norm(), 5.0 * delta.squaredNorm()) << trial;
    EXPECT_LT((back - delta).norm(), 1e-3 * delta.norm()) << trial;
  }
  EXPECT_LT(lineDifference(line, line).norm(), 1e-15);
}

TEST(Line3d, HasNoSign) {
  const Line3d line = someLine();
  const Eigen::Vector4d delta(2e-4, -1e-4, 3e-4, 1e-4);
  EXPECT_LT((lineDifference(perturbLine(line, delta).reversed(), line) - delta).norm(), 5.0 * delta.squaredNorm());
}

TEST(Line3d, TransformMovesTheLineRigidly) {
  const Eigen::Vector3d p(0.1, -0.2, 0.9), q(0.15, 0.1, 1.1);
  Eigen::Isometry3d a_T_b = Eigen::Isometry3d::Identity();
  a_T_b.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  a_T_b.translation() = Eigen::Vector3d(0.3, -0.1, 0.5);
  const Line3d moved = Line3d::throughPoints(p, q).transformed(a_T_b);
  const Line3d expected = Line3d::throughPoints(a_T_b * p, a_T_b * q);
  EXPECT_LT((moved.direction - expected.direction).norm(), 1e-14);
  EXPECT_LT((moved.moment - expected.moment).norm(), 1e-14);
}

}  // namespace
}  // namespace mire::support
