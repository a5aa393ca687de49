// The simulated ISO 9283 test (iso9283_test.hpp): the standard's positions, and the acceptance of
// the accuracy figures on it: AP within 3 of its stated σ of the truth over 50 repetitions.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "mire/datasets/iso9283_test.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/pose_accuracy.hpp"

namespace mire::datasets {
namespace {

namespace mech = mire::mechanism;

TEST(Iso9283Test, PositionsOnTheCubesDiagonalPlane) {
  Eigen::VectorXd centre(4);
  centre << 0.01, -0.02, -0.6, 0.3;
  const auto p = iso9283Positions(centre, 0.2);
  ASSERT_EQ(p.size(), 5u);
  EXPECT_TRUE(p[0].isApprox(centre));
  const Eigen::Vector3d normal = Eigen::Vector3d(1, -1, 0).normalized();  // the plane x = y through the centre
  for (std::size_t k = 1; k < 5; ++k) {
    const Eigen::Vector3d d = p[k].head<3>() - centre.head<3>();
    EXPECT_NEAR(d.norm(), 0.8 * 0.1 * std::sqrt(3.0), 1e-12) << "P" << k + 1;  // 10 % of the diagonal from a corner
    EXPECT_NEAR(d.dot(normal), 0.0, 1e-12);
    EXPECT_EQ(p[k][3], 0.3);
  }
  const auto [middle, side] = cubeInside({{0, 0, 0}, {0.3, 0.2, 0.1}, {-0.1, 0.1, 0.05}});
  EXPECT_NEAR(side, 0.1, 1e-12);
  EXPECT_TRUE(middle.isApprox(Eigen::Vector3d(0.1, 0.1, 0.05)));
}

struct Scores {
  std::vector<double> z;
  double max_abs = 0.0;
  double rms() const {
    double s = 0.0;
    for (double v : z) s += v * v;
    return std::sqrt(s / static_cast<double>(z.size()));
  }
};

// AP of the measured cycles (read through the true mounting) against AP of the true attained
// poses, in units of the stated σ: components x, y, z and AP_p.
void scoreRepetition(const Iso9283Test& test, const Eigen::Isometry3d& bTc, const Eigen::Isometry3d& mTe,
                     const mech::Mechanism& m, Scores& scores) {
  std::vector<mech::AccuracySample> measured, truth;
  for (std::size_t i = 0; i < test.ids.size(); ++i) {
    const Eigen::Isometry3d commanded = m.poseToTransform(test.commanded[i]);
    const mech::AttainedPose a =
        mech::attainedPose(bTc.inverse(), mTe.inverse(), test.measured[i].cTm, test.measured[i].covariance);
    measured.push_back({test.ids[i], test.positions[i], commanded, a.bTe, a.covariance});
    truth.push_back({test.ids[i], test.positions[i], commanded, test.attained[i], mech::IsoPoseCovariance::Zero()});
  }
  mech::AccuracyOptions options;
  options.noise_draws = 50;  // the noise-only parts are not scored here
  const auto got = mech::poseAccuracy(measured, options);
  const auto want = mech::poseAccuracy(truth, options);
  for (std::size_t p = 0; p < got.size(); ++p) {
    for (int k = 0; k < 3; ++k) scores.z.push_back((got[p].ap_xyz[k] - want[p].ap_xyz[k]) / got[p].sigma_ap_xyz[k]);
    const double zp = (got[p].ap_p - want[p].ap_p) / got[p].sigma_ap_p;
    scores.z.push_back(zp);
    for (int k = 0; k < 4; ++k) scores.max_abs = std::max(scores.max_abs, std::abs(scores.z[scores.z.size() - 1 - k]));
  }
}

void expectApWithinItsSigma(const TrueRobot& robot, const Eigen::VectorXd& controller) {
  const auto [bTc, mTe] = campaignMountings(robot.mechanism());
  Iso9283Spec spec = iso9283SpecFor(robot);
  spec.joint_repeatability = robot.mechanism().jointUnits().front() == Unit::Radian ? 2e-5 : 1e-6;
  Scores scores;
  double ap_true_min = 1e9;
  for (int r = 0; r < 50; ++r) {
    spec.seed = 100 + static_cast<unsigned>(r);
    const Iso9283Test test = simulateIso9283Test(robot.mechanism(), controller, reachOf(robot), bTc, mTe, spec);
    ASSERT_EQ(test.ids.size(), 150u);
    if (r == 0) {  // the nominal controller leaves a real bias the test must see
      for (std::size_t i = 0; i < 5; ++i)
        ap_true_min = std::min(
            ap_true_min,
            (test.attained[i].translation() - robot.mechanism().poseToTransform(test.commanded[i]).translation()).norm());
    }
    scoreRepetition(test, bTc, mTe, robot.mechanism(), scores);
  }
  const double rms = scores.rms();
  std::size_t beyond3 = 0;
  for (double v : scores.z) beyond3 += std::abs(v) > 3.0;
  std::cout << robot.mechanism().name() << ": " << scores.z.size() << " AP scores over 50 repetitions, rms(z) " << rms
            << ", max |z| " << scores.max_abs << ", beyond 3: " << beyond3 << "; smallest true AP " << ap_true_min * 1e3
            << " mm\n";
  EXPECT_GT(ap_true_min, 0.05e-3);
  EXPECT_GE(rms, 0.8);
  EXPECT_LE(rms, 1.25);
  // 3σ: 0.27 % of a normal's draws lie beyond; over 1000 scores at most a few may.
  EXPECT_LE(beyond3, 6u);
}

TEST(Iso9283Test, ApWithinThreeSigmaOfTheTruthDelta) {
  const TrueRobot robot = makeDefectiveDelta(11, true);
  expectApWithinItsSigma(robot, robot.geometry_model.nominal.values());
}

TEST(Iso9283Test, ApWithinThreeSigmaOfTheTruthHexapod) {
  const TrueRobot robot = makeDefectiveHexapod(12);
  expectApWithinItsSigma(robot, robot.geometry_model.nominal.values());
}

TEST(Iso9283Test, WrittenFilesAreWhatAccuracyReads) {
  const TrueRobot robot = makeDefectiveDelta(11, true);
  const auto [bTc, mTe] = campaignMountings(robot.mechanism());
  Iso9283Spec spec = iso9283SpecFor(robot);
  spec.cycles = 3;
  const Iso9283Test test =
      simulateIso9283Test(robot.mechanism(), robot.geometry_model.nominal.values(), reachOf(robot), bTc, mTe, spec);
  const auto dir = std::filesystem::temp_directory_path() / ("mire_iso9283_" + std::to_string(::getpid()));
  writeIso9283Test(dir, test, robot.mechanism(), spec);
  const auto rows = mech::readPosesCsv(dir / "poses.csv");
  ASSERT_EQ(rows.size(), 15u);
  EXPECT_EQ(rows[7].observation.id, "c2_P3");
  EXPECT_TRUE(rows[7].observation.cTm.isApprox(test.measured[7].cTm, 1e-12));
  ASSERT_TRUE(rows[7].observation.covariance.has_value());
  EXPECT_NEAR(std::sqrt((*rows[7].observation.covariance)(0, 0)), spec.noise_t, 1e-12);
  const auto joints = mech::readJointsCsv(dir / "joints.csv", robot.mechanism().jointColumnNames());
  ASSERT_EQ(joints.size(), 15u);
  EXPECT_TRUE(joints[7].joints.isApprox(test.joints[7], 1e-12));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mire::datasets
