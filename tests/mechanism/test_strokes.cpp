// Gough–Stewart leg strokes (doc/mechanisms.md): the IKM reports legs outside
// [leg_min, leg_max] without calling the pose unreachable; the simulated protocol and the
// true-robot simulator stay inside; mechanisms without strokes never report one.
#include <gtest/gtest.h>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/datasets/mechanism_true_robots.hpp"
#include "mire/mechanism/gough_stewart.hpp"
#include "mire/mechanism/registry.hpp"

namespace mire::mechanism {
namespace {

Eigen::Isometry3d lifted(double dz) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0, 0, 0.40 + dz);
  return T;
}

TEST(Strokes, GoughStewartIkmFlagsLegsOutsideTheirStroke) {
  const RegisteredModel model = makeRegisteredModel("gough-stewart");
  const Eigen::VectorXd g = model.nominal.values();
  const IkmResult home = model.mechanism->inverseKinematics(g, lifted(0.0));
  EXPECT_TRUE(home.reachable());
  EXPECT_TRUE(home.withinStroke());
  // Home legs are 0.451 m; 200 mm higher every leg is longer than leg_max = 0.55 m (0.635 m),
  // 200 mm lower every leg is shorter than leg_min = 0.35 m (0.289 m); the readings are still given.
  for (double dz : {0.2, -0.2}) {
    const IkmResult far = model.mechanism->inverseKinematics(g, lifted(dz));
    EXPECT_TRUE(far.reachable());
    EXPECT_EQ(far.out_of_stroke_joints, (std::vector<int>{0, 1, 2, 3, 4, 5})) << dz;
    EXPECT_TRUE(far.joints.allFinite());
  }
  // 80 mm up: inside (legs ≈ 0.52 m).
  EXPECT_TRUE(model.mechanism->inverseKinematics(g, lifted(0.08)).withinStroke());
}

TEST(Strokes, SimulatorsStayInsideTheStrokes) {
  const datasets::Campaign c = datasets::simulateCampaign("gough-stewart", 5, 0.2e-3, 0.03 * datasets::kCampaignDeg, 20);
  for (const Eigen::Isometry3d& bTe : c.bTe)
    EXPECT_TRUE(c.model.mechanism->inverseKinematics(c.truth.values(), bTe).withinStroke());
  const datasets::DefectiveRobot robot = datasets::makeDefectiveHexapod(1);
  Eigen::VectorXd X = robot.mechanism().referencePose(robot.geometry.values());
  EXPECT_EQ(robot.joints(X).size(), 6);
  X[2] += 0.2;  // past the strokes: the true robot does not go there
  EXPECT_EQ(robot.joints(X).size(), 0);
}

TEST(Strokes, MechanismsWithoutStrokesNeverReportOne) {
  for (const char* name : {"delta", "h4-12"}) {
    const datasets::Campaign c = datasets::simulateCampaign(name, 5, 0.0, 0.0);
    for (const Eigen::Isometry3d& bTe : c.bTe)
      EXPECT_TRUE(c.model.mechanism->inverseKinematics(c.truth.values(), bTe).withinStroke()) << name;
  }
}

}  // namespace
}  // namespace mire::mechanism
