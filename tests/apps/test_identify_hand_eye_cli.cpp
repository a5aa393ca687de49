// `mire identify --robot-poses` end to end on ViSP's real Franka Panda data (../shared, skipped
// without it): files in, eTc against ViSP's published result, the same file in reversed order,
// and bad input that stops with a message naming the cause and writes nothing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "mire/mechanism/io.hpp"
#include "mire/mechanism/pose.hpp"
#include "test_support.hpp"
#include "visp_handeye.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;

Eigen::Matrix<double, 6, 1> readEtc(const fs::path& yaml) {
  const auto file = mechanism::readParameterFile(yaml);
  Eigen::Matrix<double, 6, 1> v;
  int k = 0;
  for (const char* name : {"tx_EC", "ty_EC", "tz_EC", "rx_EC", "ry_EC", "rz_EC"}) {
    const auto* entry = file.find(name);
    if (entry == nullptr) throw std::runtime_error(std::string("no ") + name);
    v[k++] = file.number(*entry);
  }
  return v;
}

std::string identify(const test::TempDir& dir, const std::string& robot, const std::string& poses,
                     const std::string& output, const std::string& extra, int* code) {
  const fs::path d = dir.path();
  *code = test::runMireIn(dir, "identify --robot-poses " + (d / robot).string() + " --poses " + (d / poses).string() +
                                   " -o " + (d / output).string() + " " + extra);
  return test::readText(d / "stdout.txt") + test::readText(d / "stderr.txt");
}

TEST(IdentifyHandEyeCli, VispDataMatchPublishedResultInEitherOrder) {
  MIRE_REQUIRE_SHARED(test::kVispHandEyeDir);
  const test::TempDir dir;
  auto pairs = test::readVispHandEye();
  test::writeVispHandEyeCsv(pairs, dir.path() / "robot_poses.csv", dir.path() / "poses.csv");
  std::reverse(pairs.begin(), pairs.end());
  test::writeVispHandEyeCsv(pairs, dir.path() / "robot_reversed.csv", dir.path() / "poses_reversed.csv");
  int code = -1;
  const std::string options = "--mounting camera-on-effector --robot-sigma 1,0.1";
  std::string out = identify(dir, "robot_poses.csv", "poses.csv", "handeye.yaml", options, &code);
  ASSERT_EQ(code, 0) << out;
  std::printf("%s", out.c_str());
  EXPECT_NE(out.find("8 poses"), std::string::npos) << out;
  const auto etc = readEtc(dir.path() / "handeye.yaml");
  const Eigen::Isometry3d X = mechanism::toIsometry(etc), visp = mechanism::toIsometry(test::vispPublishedEmc());
  EXPECT_LT((X.translation() - visp.translation()).norm(), 2e-3);  // within 2σ: see test_hand_eye.cpp
  EXPECT_LT(Eigen::AngleAxisd(X.linear() * visp.linear().transpose()).angle(), 0.1 * 3.14159265358979 / 180.0);
  const std::string side = test::readText(dir.path() / "handeye_covariance.csv");
  EXPECT_EQ(side.rfind("name,value,tx_EC,ty_EC,tz_EC,rx_EC,ry_EC,rz_EC,tx_BM", 0), 0u) << side;
  const std::string yaml = test::readText(dir.path() / "handeye.yaml");
  EXPECT_NE(yaml.find("sigma_tz_EC"), std::string::npos);
  EXPECT_NE(yaml.find("mounting: \"camera-on-effector\""), std::string::npos) << yaml;

  EXPECT_EQ(out.find("warning"), std::string::npos) << out;
  // The wrong mounting fits, badly: the report says so.
  out = identify(dir, "robot_poses.csv", "poses.csv", "fixed.yaml", "--mounting camera-fixed --robot-sigma 1,0.1", &code);
  EXPECT_EQ(code, 0) << out;
  EXPECT_NE(out.find("is the mounting right (--mounting camera-on-effector?)"), std::string::npos) << out;
  out = identify(dir, "robot_reversed.csv", "poses_reversed.csv", "reversed.yaml", options, &code);
  ASSERT_EQ(code, 0) << out;
  const auto reversed = readEtc(dir.path() / "reversed.yaml");
  EXPECT_LT((reversed.head<3>() - etc.head<3>()).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((reversed.tail<3>() - etc.tail<3>()).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(IdentifyHandEyeCli, BadInputNamesTheCauseAndWritesNothing) {
  MIRE_REQUIRE_SHARED(test::kVispHandEyeDir);
  const test::TempDir dir;
  const auto pairs = test::readVispHandEye();
  test::writeVispHandEyeCsv(pairs, dir.path() / "robot_poses.csv", dir.path() / "poses.csv");
  std::vector<test::VispHandEyePair> fewer(pairs.begin(), pairs.end() - 1);
  test::writeVispHandEyeCsv(fewer, dir.path() / "robot_fewer.csv", dir.path() / "poses_fewer.csv");
  int code = -1;
  std::string out = identify(dir, "robot_poses.csv", "poses.csv", "a.yaml", "--robot-sigma 0.1,0.01", &code);
  EXPECT_EQ(code, 2);
  EXPECT_NE(out.find("--mounting"), std::string::npos) << out;
  out = identify(dir, "robot_poses.csv", "poses.csv", "a.yaml", "--mounting camera-on-effector", &code);
  EXPECT_EQ(code, 2);
  EXPECT_NE(out.find("--robot-sigma"), std::string::npos) << out;
  out = identify(dir, "robot_poses.csv", "poses.csv", "a.yaml", "--mounting sideways --robot-sigma 0.1,0.01", &code);
  EXPECT_EQ(code, 2);
  EXPECT_NE(out.find("camera-on-effector"), std::string::npos) << out;
  out = identify(dir, "robot_poses.csv", "poses.csv", "a.yaml", "--mounting camera-fixed --robot-sigma 0.1", &code);
  EXPECT_EQ(code, 2);
  EXPECT_NE(out.find("T_MM,R_DEG"), std::string::npos) << out;
  // A measured pose the robot file lacks: poses.csv's line 9 (pose 8).
  out = identify(dir, "robot_fewer.csv", "poses.csv", "a.yaml", "--mounting camera-on-effector --robot-sigma 0.1,0.01",
                 &code);
  EXPECT_EQ(code, 1);
  EXPECT_NE(out.find("poses.csv:9: pose '8' has no row in"), std::string::npos) << out;
  out = identify(dir, "robot_poses.csv", "poses.csv", "a.yaml",
                 "--mounting camera-on-effector --robot-sigma 0.1,0.01 --joints x.csv", &code);
  EXPECT_EQ(code, 2);
  EXPECT_NE(out.find("--joints does not apply"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir.path() / "a.yaml"));
  EXPECT_FALSE(fs::exists(dir.path() / "a_covariance.csv"));
}

}  // namespace
}  // namespace mire::app
