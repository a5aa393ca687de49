// The mechanism campaign's switches for the end-to-end σ study (benchmarks/bench_chain_mechanisms.cpp):
// the robot's own seed, the true robot without its unmodelled defects, identical Delta legs, and the
// camera placement; the defaults stay the demo's.
#include <gtest/gtest.h>

#include "mire/datasets/mechanism_image_campaign.hpp"

#include <unistd.h>

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
  const DefectiveRobot demo = makeDefectiveHexapod(2004);  // the demo's robot (seed 2004)
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
