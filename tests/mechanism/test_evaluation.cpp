// Evaluation criteria of paper §6 (V1, V2, V3, square sides) and the Monte-Carlo study, on
// the model-12-exact test robot (the TRUE robot with unmodelled defects is exercised in
// tests/datasets/test_h4_evaluation.cpp).
#include <gtest/gtest.h>

#include "h4_test_robot.hpp"
#include "mire/mechanism/evaluation.hpp"

#include <cmath>

namespace mire::mechanism {
namespace {

using test::TestRobot;

TEST(Straightness, KnownDeviation) {
  // Offsets −a, 2a, −a across a line along x: the LSQ line is the x axis (Σ x·y = 0, mean y
  // = 0), distances a, 2a, a → RMS √2·a.
  const double a = 1e-4;
  const std::vector<Eigen::Vector3d> points{{-1.0, -a, 0.0}, {0.0, 2 * a, 0.0}, {1.0, -a, 0.0}};
  EXPECT_NEAR(straightness(points), std::sqrt(2.0) * a, 1e-12);
  // Invariant to a rigid motion.
  const Eigen::Isometry3d motion =
      Eigen::Translation3d(0.3, -0.2, 0.5) * Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
  std::vector<Eigen::Vector3d> moved;
  for (const auto& p : points) moved.push_back(motion * p);
  EXPECT_NEAR(straightness(moved), std::sqrt(2.0) * a, 1e-12);
  EXPECT_THROW(straightness({Eigen::Vector3d::Zero()}), std::invalid_argument);
}

TEST(JointResidualCriteria, ZeroAtTruthAndOffsetRecovered) {
  const TestRobot robot;
  const auto poses = robot.observe(TestRobot::protocolPoses(), nullptr);
  const auto model =
      makeIdentificationModel(robot.mechanism, robot.truth, ExternalParameterization(ExternalForm::Full), [&] {
        ExternalParameterization full(ExternalForm::Full);
        ParameterSet set = full.parameters();
        set.setValues(full.valuesFrom(robot.bTc, robot.mTe));
        return set;
      }());
  const auto exact = jointResidualCriteria(model, poses);
  EXPECT_EQ(exact.pose_count, 81);
  EXPECT_LT(std::abs(exact.v1_rad), 1e-10);
  EXPECT_LT(exact.v2_rad, 1e-10);
  // A constant joint error e gives V1 = e and V2 = |e| (eq. 27–28).
  auto shifted = poses;
  for (auto& p : shifted) p.joints.array() -= 1e-3;
  const auto offset = jointResidualCriteria(model, shifted);
  EXPECT_NEAR(offset.v1_rad, -1e-3, 1e-10);
  EXPECT_NEAR(offset.v2_rad, 1e-3, 1e-10);
}

TEST(StraightnessCriterion, ExactLineGivesZeroAndWrongGeometryBends) {
  const TestRobot robot;
  std::vector<std::vector<Eigen::VectorXd>> lines(2);
  for (int k = 0; k < 15; ++k) {
    const double s = -0.1 + 0.2 * k / 14.0;
    Eigen::Isometry3d a = Eigen::Isometry3d::Identity(), b = Eigen::Isometry3d::Identity();
    a.translation() << s, 0.0, -0.62;
    b.translation() << s, s, -0.62 + 0.75 * s;
    lines[0].push_back(robot.mechanism->inverseKinematics(robot.truth.values(), a).joints);
    lines[1].push_back(robot.mechanism->inverseKinematics(robot.truth.values(), b).joints);
  }
  const auto exact = straightnessCriterion(*robot.mechanism, robot.truth.values(), lines);
  ASSERT_TRUE(exact.ok) << exact.message;
  EXPECT_LT(exact.v3_m, 1e-9);
  const auto nominal = straightnessCriterion(*robot.mechanism, h4Model12Parameters(robot.nominal).values(), lines);
  ASSERT_TRUE(nominal.ok);
  EXPECT_GT(nominal.v3_m, 1e-6);
  EXPECT_NEAR(nominal.v3_m, 0.5 * (nominal.per_line_m[0] + nominal.per_line_m[1]), 1e-15);
}

TEST(SquareTest, CornersAndSides) {
  const auto corners = squareCorners(Eigen::Vector3d(0.01, 0.02, -0.6), 0.1);
  ASSERT_EQ(corners.size(), 4U);
  std::vector<Eigen::Vector3d> reached;
  for (const auto& c : corners) reached.push_back(c.head<3>());
  for (double e : squareSideErrors(reached, 0.1)) EXPECT_NEAR(e, 0.0, 1e-15);
  reached[1].x() += 1e-3;  // side 1 longer by 1 mm, side 2 by ≈0 (perpendicular)
  const auto errors = squareSideErrors(reached, 0.1);
  EXPECT_NEAR(errors[0], 1e-3, 1e-12);
  EXPECT_NEAR(errors[1], std::hypot(0.1, 1e-3) - 0.1, 1e-12);
  // The model's IKM at the truth commands exactly the truth's joints.
  const TestRobot robot;
  const auto joints = commandJoints(*robot.mechanism, robot.truth.values(), corners);
  for (std::size_t k = 0; k < 4; ++k) {
    const auto fkm = robot.mechanism->forwardKinematics(robot.truth.values(), joints[k], corners[k]);
    ASSERT_TRUE(fkm.converged);
    EXPECT_LT((fkm.pose - corners[k]).norm(), 1e-9);
  }
}

TEST(MonteCarloStudy, DeterministicWhateverTheThreadCount) {
  const TestRobot robot;
  std::mt19937 rng(4);
  const auto poses = robot.observe(TestRobot::protocolPoses(), &rng);
  const auto initial =
      makeInitialModel(robot.mechanism, h4Model12Parameters(robot.nominal), poses, ExternalForm::AxisAligned);
  MonteCarloOptions options;
  options.subset_sizes = {15, 40};
  options.repeats = 6;
  options.seed = 9;
  std::atomic<int> done{0};
  options.on_run_done = [&done] { ++done; };
  options.threads = 1;
  const auto one = runMonteCarloStudy(initial, poses, {}, options);
  options.threads = 2;
  const auto two = runMonteCarloStudy(initial, poses, {}, options);
  EXPECT_EQ(done.load(), 24);
  ASSERT_EQ(one.summaries.size(), 2U);
  for (std::size_t s = 0; s < 2; ++s) {
    EXPECT_EQ(one.summaries[s].runs_ok, 6);
    EXPECT_EQ(one.summaries[s].mean, two.summaries[s].mean);
    EXPECT_EQ(one.summaries[s].sigma, two.summaries[s].sigma);
    EXPECT_EQ(one.summaries[s].v2_mean, two.summaries[s].v2_mean);
    EXPECT_TRUE(std::isnan(one.summaries[s].v3_mean));  // no lines given
    for (const auto& run : one.summaries[s].runs)
      EXPECT_EQ(static_cast<int>(run.subset.size()), one.summaries[s].subset_size);
  }
  // The subsets share one noise draw, so their mean is one estimate (off by about the
  // 15-pose spread at most), and more poses shrink the spread.
  const auto truth = robot.trueValues(initial);
  const Eigen::Index l = static_cast<Eigen::Index>(initial.parameters.index("l"));
  EXPECT_NEAR(one.summaries[1].mean[l], truth[l], 2.0 * one.summaries[0].sigma[l]);
  EXPECT_LT(one.summaries[1].sigma[l], one.summaries[0].sigma[l]);
  // V2 at the validation poses is at the joint-noise level (≈ 1e-3 rad here), not zero.
  EXPECT_GT(one.summaries[1].v2_mean, 1e-5);
  EXPECT_LT(one.summaries[1].v2_mean, 3e-3);
  options.subset_sizes = {81};
  EXPECT_THROW(runMonteCarloStudy(initial, poses, {}, options), std::invalid_argument);
}

}  // namespace
}  // namespace mire::mechanism
