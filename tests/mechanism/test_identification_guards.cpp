// identify() refuses degenerate problems instead of crashing (issue 12): no free parameter
// left, or a robust fit whose outliers leave too few equations.
#include <gtest/gtest.h>

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

TEST(IdentificationGuards, RobustFitWithEveryPoseAnOutlierIsAnError) {
  const test::TestRobot robot;
  std::mt19937 rng(4);
  auto poses = robot.observe(test::TestRobot::protocolPoses(), &rng);
  // Covariances 10^-12 of the real noise: every pose's chi-square is far beyond the threshold.
  for (auto& p : poses) {
    ASSERT_TRUE(p.covariance.has_value());
    *p.covariance *= 1e-12;
  }
  IdentificationOptions options;
  options.loss = RobustLoss::Huber;
  try {
    identify(initialModel(robot, poses), poses, options);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("are outliers"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mire::mechanism
