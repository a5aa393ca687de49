// The simulated true H4: IKM/FKM round trip, ≈0.1° nacelle tilt, camera view, protocol.
#include <gtest/gtest.h>

#include "mire/datasets/h4_true_robot.hpp"

#include <algorithm>
#include <cmath>

namespace mire::datasets {
namespace {

H4TrueKinematics defectiveRobot() { return H4TrueKinematics(makeTrueGeometry(H4Model12Values{}, H4ErrorSizes{}, 3)); }

TEST(H4TrueKinematics, NominalIkmMatchesBriefClosedForm) {
  // The model-12 closed form (doc/mechanisms.md) on the nominal geometry at the workspace centre, leg 1.
  const H4TrueKinematics robot(geometryFromModel12(H4Model12Values{}));
  const H4Pose x(0.01, -0.02, -0.62, 0.1);
  const auto q = robot.joints(x);
  ASSERT_TRUE(q.has_value());
  const double h = 0.075, d = 0.10, R = 0.22, L = 0.30, l = 0.70;
  for (int i = 0; i < 4; ++i) {
    const double alpha = (0.25 + 0.5 * i) * kH4Pi;
    const Eigen::Vector3d u(std::cos(alpha), std::sin(alpha), 0.0);
    const Eigen::Vector3d a = x.head<3>() +
                              mechanism::kH4Epsilon[i] * h * Eigen::Vector3d(std::cos(x[3]), std::sin(x[3]), 0) +
                              mechanism::kH4Sigma[i] * d * Eigen::Vector3d::UnitY();
    const Eigen::Vector3d p = Eigen::Vector3d(mechanism::kH4Epsilon[i] * h, mechanism::kH4Sigma[i] * d, 0.0) + R * u;
    const Eigen::Vector3d w = a - p;
    const double aa = w.dot(u), bb = -w.z(), cc = (w.squaredNorm() + L * L - l * l) / (2 * L);
    const double phi = std::atan2(bb, aa) - std::acos(cc / std::hypot(aa, bb));
    EXPECT_NEAR((*q)[i], phi, 1e-12) << "leg " << i + 1;
    // Elbow out: the elbow lies farther from the z axis than the pivot.
    const Eigen::Vector3d elbow = robot.elbows(*q)[i];
    EXPECT_GT(elbow.head<2>().norm(), p.head<2>().norm());
  }
}

TEST(H4TrueKinematics, IkmFkmRoundTripOverTheProtocol) {
  const H4TrueKinematics robot = defectiveRobot();
  double worst = 0.0;
  for (const H4Pose& x : protocolPoses()) {
    const auto q = robot.joints(x);
    ASSERT_TRUE(q.has_value());
    // Start 5 mm / 1° away to make the FKM actually work.
    const auto back = robot.pose(*q, x + H4Pose(0.005, -0.005, 0.005, 0.017));
    ASSERT_TRUE(back.has_value());
    worst = std::max(worst, (*back - x).cwiseAbs().maxCoeff());
    // Forearm closure holds with the true lengths.
    const auto a = robot.attachmentPoints(x);
    const auto b = robot.elbows(*q);
    for (int i = 0; i < 4; ++i) EXPECT_NEAR((a[i] - b[i]).norm(), robot.geometry().legs[i].forearm_length, 1e-12);
  }
  EXPECT_LT(worst, 1e-9);
}

TEST(H4TrueKinematics, NacelleTiltIsAboutATenthOfADegreeAndVaries) {
  const H4TrueKinematics robot = defectiveRobot();
  double largest = 0.0, smallest = 1e9;
  Eigen::Vector3d lowest_tilt, highest_tilt;
  std::vector<Eigen::Vector3d> tilts;
  for (const H4Pose& x : protocolPoses()) tilts.push_back(robot.tilt(x));
  // Variation of the rotation axis over the workspace (paper §6.3: ≈0.1°).
  double spread = 0.0;
  for (const auto& a : tilts) {
    largest = std::max(largest, a.norm());
    smallest = std::min(smallest, a.norm());
    EXPECT_EQ(a.z(), 0.0);
    for (const auto& b : tilts) spread = std::max(spread, (a - b).norm());
  }
  const double deg = 180.0 / kH4Pi;
  RecordProperty("tilt_spread_deg", std::to_string(spread * deg));
  std::printf("nacelle tilt: %.3f..%.3f deg, spread over the 81 poses %.3f deg\n", smallest * deg, largest * deg,
              spread * deg);
  EXPECT_GT(spread * deg, 0.05);
  EXPECT_LT(spread * deg, 0.2);
  EXPECT_LT(largest * deg, 0.3);
  // The robot without unmodelled defects has no tilt at all.
  const H4TrueKinematics exact(makeTrueGeometry(H4Model12Values{}, H4ErrorSizes::withoutUnmodelledDefects(), 3));
  for (const H4Pose& x : protocolPoses()) EXPECT_EQ(exact.tilt(x).norm(), 0.0);
  // Same seed: same model-12 part.
  EXPECT_EQ(exact.geometry().h, robot.geometry().h);
  EXPECT_EQ(exact.geometry().legs[2].joint_offset, robot.geometry().legs[2].joint_offset);
}

TEST(H4TrueKinematics, EffectorPoseCarriesTiltAndRotation) {
  const H4TrueKinematics robot = defectiveRobot();
  const H4Pose x(0.05, 0.02, -0.6, 0.3);
  const Eigen::Isometry3d b_T_e = robot.baseTEffector(x);
  EXPECT_LT((b_T_e.translation() - x.head<3>()).norm(), 1e-15);
  const Eigen::Vector3d z_e = b_T_e.linear().col(2);
  EXPECT_NEAR(std::acos(z_e.z()), robot.tilt(x).norm(), 1e-9);
  // cTm composes as paper eq. 3: bTe = bTc · cTm · mTe.
  const Eigen::Isometry3d recomposed = robot.baseTCamera() * robot.cameraTMarker(x) * robot.markerTEffector();
  EXPECT_LT((recomposed.matrix() - b_T_e.matrix()).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(H4TrueKinematics, TargetStaysInViewOverTheProtocol) {
  const H4TrueKinematics robot = defectiveRobot();
  // Outer corners of the 12 x 9 inner-corner, 16 mm chessboard of specs/target_h4.yaml
  // (doc/file-formats.md: first inner corner at the origin, one square of border beyond).
  std::vector<Eigen::Vector3d> board;
  for (double x : {-0.016, 0.192})
    for (double y : {-0.016, 0.144}) board.emplace_back(x, y, 0.0);
  std::vector<H4Pose> poses = protocolPoses();
  for (const auto& line : straightLineMotions()) poses.insert(poses.end(), line.begin(), line.end());
  const double margin = smallestImageMargin(robot, poses, board);
  std::printf("smallest image margin of the board corners: %.0f px\n", margin);
  EXPECT_GT(margin, 20.0);
  // Camera–target distance 0.7–0.9 m.
  for (const H4Pose& x : poses) {
    const double distance = robot.cameraTMarker(x).translation().norm();
    EXPECT_GT(distance, 0.65);
    EXPECT_LT(distance, 0.95);
  }
}

TEST(H4TrueKinematics, ProtocolShapes) {
  const auto poses = protocolPoses();
  ASSERT_EQ(poses.size(), 81U);
  Eigen::Vector4d low = poses[0], high = poses[0];
  for (const auto& p : poses) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  EXPECT_NEAR(high.x() - low.x(), 0.20, 1e-12);
  EXPECT_NEAR(high.y() - low.y(), 0.20, 1e-12);
  EXPECT_NEAR(high.z() - low.z(), 0.15, 1e-12);
  EXPECT_NEAR(high[3], 20.0 * kH4Degree, 1e-12);
  EXPECT_NEAR(low[3], -20.0 * kH4Degree, 1e-12);
  const auto lines = straightLineMotions({}, 20);
  for (const auto& line : lines) {
    ASSERT_EQ(line.size(), 20U);
    const Eigen::Vector3d direction = (line.back() - line.front()).head<3>().normalized();
    for (const auto& p : line) {
      const Eigen::Vector3d r = (p - line.front()).head<3>();
      EXPECT_LT((r - r.dot(direction) * direction).norm(), 1e-12);
    }
  }
}

TEST(H4TrueKinematics, SquareTestWithTheTrueModelIsExactAndWithNominalIsMillimetres) {
  const H4TrueKinematics robot = defectiveRobot();
  const auto exact = squareTest(robot, [&](const H4Pose& x) { return robot.joints(x); });
  EXPECT_LT(exact.max_abs_error_m, 1e-9);
  const H4TrueKinematics nominal(geometryFromModel12(H4Model12Values{}));
  const auto before = squareTest(robot, [&](const H4Pose& x) { return nominal.joints(x); });
  std::printf("square sides with nominal control: %+.2f %+.2f %+.2f %+.2f mm\n", before.side_error_m[0] * 1e3,
              before.side_error_m[1] * 1e3, before.side_error_m[2] * 1e3, before.side_error_m[3] * 1e3);
  EXPECT_GT(before.max_abs_error_m, 1e-3);
}

TEST(H4TrueKinematics, SimulatedMeasurementsAreDeterministicAndNoisy) {
  const H4TrueKinematics robot = defectiveRobot();
  const auto poses = protocolPoses();
  const H4MeasurementNoise noise;
  const auto a = simulateMeasurements(robot, poses, noise, 3);
  const auto b = simulateMeasurements(robot, poses, noise, 3);
  ASSERT_EQ(a.size(), 81U);
  double sum_sq = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].camera_T_marker.matrix(), b[k].camera_T_marker.matrix());
    EXPECT_EQ(a[k].pose_id, static_cast<int>(k) + 1);
    sum_sq += (a[k].camera_T_marker.translation() - robot.cameraTMarker(poses[k]).translation()).squaredNorm();
  }
  const double rms = std::sqrt(sum_sq / (3.0 * a.size()));
  EXPECT_NEAR(rms, noise.translation_m, 0.3 * noise.translation_m);
}

}  // namespace
}  // namespace mire::datasets
