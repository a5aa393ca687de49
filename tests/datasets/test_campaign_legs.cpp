// A campaign's legs as rods (campaign_legs.hpp, doc/simulation.md "Legs as rods"): the true robot's
// legs against its own encoders, the files of `mire simulate campaign --legs`, and the robots
// without drawn legs refused.
#include <gtest/gtest.h>

#include "mire/datasets/campaign_legs.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/legs_csv.hpp"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace mire::datasets {
namespace {

namespace fs = std::filesystem;

// The hexapod's rods join its joint centres (eccentric base joints included): their lengths are
// the legs its encoders read, ρ_i = q̄_i / g_i + ρ0_i.
TEST(CampaignLegs, HexapodRodsHaveTheLengthsItsEncodersRead) {
  const TrueRobot robot = makeDefectiveHexapod(2004);
  ASSERT_EQ(legsModel(robot), "gough-stewart");
  const std::vector<Eigen::VectorXd> poses = protocolCoordinates(robot);
  for (const std::size_t j : {0u, 40u, 80u}) {
    const Eigen::VectorXd q = robot.joints(poses[j]);
    const std::vector<LegSegment> legs = trueLegSegments(robot, poses[j]);
    ASSERT_EQ(legs.size(), 6u);
    for (int i = 0; i < 6; ++i) {
      const double rho =
          q[i] / robot.encoder_gain[static_cast<std::size_t>(i)] + robot.geometry.value("rho0" + std::to_string(i + 1));
      EXPECT_NEAR((legs[static_cast<std::size_t>(i)].to - legs[static_cast<std::size_t>(i)].from).norm(), rho, 1e-12);
    }
  }
}

// The Delta's forearms: as long as its true l_i, their elbows L_i from the leg's pivot (both moved
// out by the same plate offset), their plate ends r from the plate centre.
TEST(CampaignLegs, DeltaForearmsHaveTheTrueLengthsAndMeetThePlate) {
  const TrueRobot robot = makeDefectiveDelta(2004, true);
  ASSERT_EQ(legsModel(robot), "delta");
  const Eigen::VectorXd X = protocolCoordinates(robot)[7];
  const std::vector<LegSegment> legs = trueLegSegments(robot, X);
  ASSERT_EQ(legs.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const auto value = [&](const char* name) { return robot.geometry.value(name + std::to_string(i + 1)); };
    const LegSegment& leg = legs[static_cast<std::size_t>(i)];
    EXPECT_NEAR((leg.to - leg.from).norm(), value("l"), 1e-9);
    const Eigen::Vector3d offset = leg.to - X.head<3>();
    EXPECT_NEAR(offset.norm(), DeltaNominal{}.r, 1e-12);
    const Eigen::Vector3d pivot = Eigen::Vector3d(value("px"), value("py"), value("pz")) + offset;
    EXPECT_NEAR((leg.from - pivot).norm(), value("L"), 1e-9);
  }
}

TEST(CampaignLegs, OnlyTheHexapodAndTheDeltaDrawTheirLegs) {
  EXPECT_TRUE(campaignDrawsLegs("gough-stewart"));
  EXPECT_TRUE(campaignDrawsLegs("delta"));
  EXPECT_FALSE(campaignDrawsLegs("h4"));
  const TrueRobot h4 = trueRobotOf(MechanismImageCampaignSpec::reference("h4"));
  EXPECT_THROW(trueLegSegments(h4, protocolCoordinates(h4)[0]), std::invalid_argument);
  MechanismImageCampaignSpec spec = MechanismImageCampaignSpec::reference("delta");
  spec.leg_radius_m = 0.008;
  spec.camera_on_effector = true;
  EXPECT_THROW(generateMechanismImageCampaign(spec, fs::temp_directory_path() / "mire_never_written"),
               std::invalid_argument);
}

TEST(CampaignLegs, TheRulersPlacementIsFiveMillimetresAndOneDegreeOff) {
  const Eigen::Isometry3d bTc = mechanismBaseTCamera("gough-stewart");
  const Eigen::Isometry3d ruler = rulerBaseTCamera(bTc, 2004);
  EXPECT_NEAR((ruler.translation() - bTc.translation()).norm(), 5e-3, 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(ruler.linear() * bTc.linear().transpose()).angle(), kCampaignDeg, 1e-12);
}

// A small Delta campaign with its legs: legs.yaml says what predicts them, truth/legs.csv holds
// every leg at every pose (readable as legs.csv), and the legs change the pose images only.
TEST(CampaignLegs, DeltaCampaignWritesLegsYamlAndTheTrueAxes) {
  const fs::path dir = fs::temp_directory_path() / ("mire_campaign_legs_" + std::to_string(::getpid()));
  MechanismImageCampaignSpec spec = MechanismImageCampaignSpec::reference("delta");
  spec.calibration_views = 3;
  spec.images_per_pose = 1;
  spec.line_points = 3;
  spec.leg_radius_m = 0.008;
  const MechanismImageCampaign campaign = generateMechanismImageCampaign(spec, dir);
  std::ifstream yaml(campaign.legs_file());
  std::stringstream text;
  text << yaml.rdbuf();
  EXPECT_NE(text.str().find("model: delta\n"), std::string::npos) << text.str();
  EXPECT_NE(text.str().find("radius_mm: 8.0\n"), std::string::npos) << text.str();
  const std::vector<LegObservation> truth = readLegsCsv(dir / "truth" / "legs.csv", 3);
  ASSERT_EQ(truth.size(), 3 * campaign.pose_ids.size());
  // Each true axis passes through its rod's ends, in the camera frame.
  const std::vector<Rod> rods = legRods(campaign.robot, campaign.commanded[4], campaign.bTc, 0.008);
  for (int i = 0; i < 3; ++i) {
    const support::Line3d& line = truth[static_cast<std::size_t>(3 * 4 + i)].line;
    for (const Eigen::Vector3d& end : {rods[static_cast<std::size_t>(i)].from, rods[static_cast<std::size_t>(i)].to})
      EXPECT_LT((end.cross(line.direction) - line.moment).norm(), 1e-12);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mire::datasets
