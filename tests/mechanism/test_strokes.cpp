// Gough–Stewart leg strokes and a description's `stroke` (doc/mechanisms.md): the IKM reports legs
// outside [leg_min, leg_max] without calling the pose unreachable; the simulated protocol, the
// true-robot simulator and `mire plan`'s candidates stay inside; mechanisms without strokes never
// report one.
#include <gtest/gtest.h>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/datasets/mechanism_true_robots.hpp"
#include "mire/mechanism/described.hpp"
#include "mire/mechanism/experiment_design.hpp"
#include "mire/mechanism/gough_stewart.hpp"
#include "mire/mechanism/registry.hpp"
#include "test_support.hpp"

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
  const datasets::TrueRobot robot = datasets::makeDefectiveHexapod(1);
  Eigen::VectorXd X = robot.mechanism().referencePose(robot.geometry.values());
  EXPECT_EQ(robot.joints(X).size(), 6);
  X[2] += 0.2;  // past the strokes: the true robot does not go there
  EXPECT_EQ(robot.joints(X).size(), 0);
}

// The readings' range over a campaign's poses, leg by leg.
std::pair<Eigen::VectorXd, Eigen::VectorXd> readingRange(const datasets::Campaign& c) {
  Eigen::VectorXd lo = c.poses.front().joints, hi = lo;
  for (const PoseObservation& p : c.poses) {
    lo = lo.cwiseMin(p.joints);
    hi = hi.cwiseMax(p.joints);
  }
  return {lo, hi};
}

// A described 6-RUS whose legs declare the middle half of the readings its protocol uses: the
// protocol shrinks until it fits; with the middle 80 %, every plan candidate is inside the strokes.
TEST(Strokes, DescribedStrokesKeepTheProtocolAndThePlanInside) {
  const MechanismDescription d = readMechanismDescription(test::sourceDir() / "examples" / "mechanisms" / "6-rus.yaml");
  const datasets::Campaign free = datasets::simulateCampaign(makeDescribedModel(d), 3, 0.0, 0.0);
  const auto [lo, hi] = readingRange(free);
  const auto withStrokes = [&, lo = lo, hi = hi](double middle) {
    MechanismDescription out = d;
    for (std::size_t i = 0; i < out.legs.size(); ++i) {
      const auto k = static_cast<Eigen::Index>(i);
      const double centre = 0.5 * (lo[k] + hi[k]), half = 0.5 * middle * (hi[k] - lo[k]);
      out.legs[i].stroke = Eigen::Vector2d(centre - half, centre + half);
    }
    return makeDescribedModel(out);
  };
  const RegisteredModel model = withStrokes(0.5);
  const datasets::Campaign c = datasets::simulateCampaign(model, 3, 0.0, 0.0);  // throws if a pose is outside
  ASSERT_EQ(c.bTe.size(), free.bTe.size());
  for (const Eigen::Isometry3d& bTe : c.bTe)
    EXPECT_TRUE(model.mechanism->inverseKinematics(c.truth.values(), bTe).withinStroke());
  const Eigen::Vector3d centre = free.bTe[40].translation();  // home: the grid's middle, untilted
  EXPECT_LT((c.bTe.front().translation() - centre).norm(), 0.6 * (free.bTe.front().translation() - centre).norm());

  const RegisteredModel planned = withStrokes(0.8);
  const Eigen::VectorXd g = planned.nominal.values();
  const std::vector<Eigen::VectorXd> candidates =
      generateCandidatePoses(*planned.mechanism, g, protocolWorkspace(*planned.mechanism, g), 40, 7);
  ASSERT_EQ(candidates.size(), 40u);
  for (const Eigen::VectorXd& X : candidates)
    EXPECT_TRUE(planned.mechanism->inverseKinematics(g, planned.mechanism->poseToTransform(X)).withinStroke());
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
