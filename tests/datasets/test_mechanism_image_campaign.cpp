// The mechanism campaign's switches for the end-to-end σ study (benchmarks/bench_chain.cpp):
// the robot's own seed, the true robot without its unmodelled defects, identical Delta legs, and the
// camera placement; the defaults stay the demo's. The H4 through the same generator.
#include <gtest/gtest.h>

#include "mire/datasets/iso9283_test.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>

namespace mire::datasets {
namespace {

namespace fs = std::filesystem;

// A cheap campaign: few calibration views, one image per pose.
MechanismImageCampaignSpec smallSpec(const std::string& mechanism) {
  MechanismImageCampaignSpec spec = MechanismImageCampaignSpec::reference(mechanism);
  spec.calibration_views = 3;
  spec.images_per_pose = 1;
  spec.line_points = 3;
  return spec;
}

class MechanismImageCampaignTest : public ::testing::Test {
 protected:
  void TearDown() override { fs::remove_all(dir_); }
  MechanismImageCampaign generate(const MechanismImageCampaignSpec& spec) {
    return generateMechanismImageCampaign(spec, dir_);
  }
  fs::path dir_ = fs::temp_directory_path() / ("mire_mechanism_campaign_" + std::to_string(::getpid()));
};

TEST_F(MechanismImageCampaignTest, HexapodWithoutUnmodelledDefectsKeepsTheGeometryOfItsSeed) {
  MechanismImageCampaignSpec spec = smallSpec("gough-stewart");
  spec.seed = 77;  // new images and encoder noise, the robot of seed 2004
  spec.robot_seed = 2004;
  spec.unmodelled_defects = false;
  const MechanismImageCampaign exact = generate(spec);
  const TrueRobot demo = makeDefectiveHexapod(2004);  // the demo's robot (seed 2004)
  EXPECT_EQ(exact.robot.geometry.values(), demo.geometry.values());
  EXPECT_DOUBLE_EQ(demo.eccentricity, 0.3e-3);
  EXPECT_DOUBLE_EQ(exact.robot.eccentricity, 0.0);
  for (const double gain : exact.robot.encoder_gain) EXPECT_DOUBLE_EQ(gain, 1.0);
  // The recorded joints are then the model's IKM: the robot is exactly `gough-stewart`.
  const Eigen::VectorXd X = exact.commanded[5];
  const Eigen::VectorXd q = exact.robot.joints(X);
  const Eigen::VectorXd model_q =
      exact.robot.mechanism().inverseKinematics(exact.robot.geometry.values(), exact.robot.effector(X)).joints;
  EXPECT_LT((q - model_q).cwiseAbs().maxCoeff(), 1e-12);
}

// The H4's true robot in the one type is the draw of h4_true_robot.hpp for the seed, bit for bit
// (the demo's published numbers depend on it), with the H4's mountings, its 81 protocol poses of
// paper §6 and its own readings and FKM.
TEST_F(MechanismImageCampaignTest, H4TrueRobotIsTheH4DrawOfItsSeed) {
  MechanismImageCampaignSpec spec = MechanismImageCampaignSpec::reference("h4");
  spec.seed = 31;
  const TrueRobot robot = trueRobotOf(spec);
  ASSERT_TRUE(robot.h4.has_value());
  const H4TrueGeometry drawn = makeTrueGeometry(H4Model12Values{}, spec.h4_errors, 31);
  for (std::size_t i = 0; i < 4; ++i) {
    const H4TrueLeg &leg = robot.h4->geometry().legs[i], &expected = drawn.legs[i];
    EXPECT_TRUE(leg.pivot == expected.pivot);
    EXPECT_EQ(leg.psi, expected.psi);
    EXPECT_EQ(leg.arm_length, expected.arm_length);
    EXPECT_EQ(leg.joint_offset, expected.joint_offset);
    EXPECT_EQ(leg.bar_mismatch, expected.bar_mismatch);
    EXPECT_GT(std::abs(leg.bar_mismatch), 0.5e-3);  // the unmodelled defect is there
  }
  EXPECT_TRUE(robot.geometry.values() == h4Model12Parameters(drawModel12Values({}, spec.h4_errors, 31)).values());
  EXPECT_TRUE(robot.h4->baseTCamera().matrix() == defaultBaseTCamera().matrix());
  EXPECT_TRUE(robot.h4->baseTCamera().matrix() == mechanismBaseTCamera("h4").matrix());

  const std::vector<Eigen::VectorXd> poses = protocolCoordinates(robot);
  const std::vector<H4Pose> grid = protocolPoses(H4ProtocolGrid{});
  ASSERT_EQ(poses.size(), 81u);
  for (std::size_t k = 0; k < grid.size(); ++k) EXPECT_TRUE(poses[k] == Eigen::VectorXd(grid[k])) << k;
  const Eigen::VectorXd& X = poses[7];
  const Eigen::VectorXd q = robot.joints(X);
  ASSERT_EQ(q.size(), 4);
  EXPECT_TRUE(q == Eigen::VectorXd(*robot.h4->joints(H4Pose(X))));
  EXPECT_LT((robot.fkm(q) - X).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_TRUE(robot.effector(X).matrix() == robot.h4->baseTEffector(H4Pose(X)).matrix());
  EXPECT_EQ(straightLinePoses(robot, 20)[1].size(), 20u);
  EXPECT_DOUBLE_EQ(iso9283SpecFor(robot).side, 0.15);  // the grid's smallest extent

  spec.unmodelled_defects = false;  // model 12 exactly, the same model-12 part
  const TrueRobot exact = trueRobotOf(spec);
  EXPECT_EQ(exact.h4->geometry().legs[2].bar_mismatch, 0.0);
  EXPECT_EQ(exact.h4->geometry().legs[2].beta, 0.5 * kH4Pi);
  EXPECT_TRUE(exact.geometry.values() == robot.geometry.values());

  spec.camera_on_effector = true;  // refused before anything is written
  EXPECT_THROW(generate(spec), std::invalid_argument);
  EXPECT_FALSE(fs::exists(dir_));
}

TEST_F(MechanismImageCampaignTest, DeltaSwitchesAndCameraPlacement) {
  MechanismImageCampaignSpec spec = smallSpec("delta");
  spec.unmodelled_defects = false;
  spec.delta_legs_differ = false;
  Eigen::Isometry3d moved = mechanismBaseTCamera("delta");
  moved.translation() += Eigen::Vector3d(0.005, -0.005, -0.02);
  spec.base_T_camera = moved;
  const MechanismImageCampaign campaign = generate(spec);
  EXPECT_DOUBLE_EQ(campaign.robot.tilt_per_m, 0.0);
  EXPECT_TRUE(campaign.bTc.isApprox(moved, 0.0));
  const auto& g = campaign.robot.geometry;
  EXPECT_DOUBLE_EQ(g.value("L1"), g.value("L2"));  // identical legs: exactly the `delta` model
  EXPECT_DOUBLE_EQ(g.value("l1"), g.value("l3"));
  EXPECT_TRUE(campaign.bTe[3].linear().isApprox(Eigen::Matrix3d::Identity(), 0.0));  // no plate tilt

  // A placement that loses the board is refused before anything is rendered.
  moved.translation().z() += 0.5;
  spec.base_T_camera = moved;
  EXPECT_THROW(generate(spec), std::runtime_error);

  const MechanismImageCampaign demo = generate(smallSpec("delta"));  // the defaults: the demo's
  EXPECT_TRUE(demo.bTc.isApprox(mechanismBaseTCamera("delta"), 0.0));
  EXPECT_DOUBLE_EQ(demo.robot.tilt_per_m, 0.0116);
  EXPECT_NE(demo.robot.geometry.value("L1"), demo.robot.geometry.value("L2"));
  EXPECT_FALSE(demo.bTe[3].linear().isApprox(Eigen::Matrix3d::Identity(), 1e-9));
}

}  // namespace
}  // namespace mire::datasets
