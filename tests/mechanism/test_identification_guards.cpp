// identify() refuses degenerate problems instead of crashing (doc/robustness.md): no free parameter
// left, or a robust fit whose outliers leave too few equations.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "h4_test_robot.hpp"
#include "mire/mechanism/identification.hpp"

namespace mire::mechanism {
namespace {

IdentificationModel initialModel(const test::TestRobot& robot, const std::vector<PoseObservation>& poses) {
  return makeInitialModel(robot.mechanism, h4Model12Parameters(robot.nominal), poses, ExternalForm::AxisAligned);
}

TEST(IdentificationGuards, EveryParameterFixedIsAnError) {
  const test::TestRobot robot;
  std::mt19937 rng(3);
  const auto poses = robot.observe(test::TestRobot::protocolPoses(), &rng);
  const IdentificationModel model = initialModel(robot, poses);
  IdentificationOptions options;
  options.fix = model.parameters.names();
  try {
    identify(model, poses, options);
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no free parameter"), std::string::npos) << e.what();
  }
}

// Covariances 10^-12 of the real noise: every pose's chi-square is far beyond the threshold at
// the measured scale. That is a misfit of the whole covariance, not 81 outliers: the outlier test
// runs at the achieved scale (doc/uncertainty.md), so the robust fit succeeds, flags (almost) no
// pose and reports the residual-scaled sigma - never a crash, never sigma 0.
TEST(IdentificationGuards, RobustFitWithEveryPoseMisweightedIsResidualScaled) {
  const test::TestRobot robot;
  std::mt19937 rng(4);
  auto poses = robot.observe(test::TestRobot::protocolPoses(), &rng);
  for (auto& p : poses) {
    ASSERT_TRUE(p.covariance.has_value());
    *p.covariance *= 1e-12;
  }
  IdentificationOptions options;
  options.loss = RobustLoss::Huber;
  const IdentificationResult result = identify(initialModel(robot, poses), poses, options);
  EXPECT_EQ(result.covariance_method.rfind("residual-scaled", 0), 0u) << result.covariance_method;
  EXPECT_GT(result.covariance_scale2, 1e9);
  EXPECT_LT(result.outliers.size(), poses.size() / 10);
  EXPECT_TRUE(result.sigma.allFinite());
  EXPECT_GT(result.sigma.minCoeff(), -1e-300);
  EXPECT_GT(result.sigma.maxCoeff(), 0.0);
}

}  // namespace
}  // namespace mire::mechanism
