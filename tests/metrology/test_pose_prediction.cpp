// Visibility and predicted pose covariance before any image (pose_prediction.hpp,
// doc/plan-and-select.md "--camera"): partly outside the image and too oblique are refused;
// the predicted covariance is estimatePose's own (same numbers on exact features) and matches
// the Monte-Carlo spread of estimatePose on noisy projected corners.
#include "mire/datasets/feature_campaign.hpp"
#include "mire/metrology/feature_averaging.hpp"
#include "mire/metrology/pose_estimation.hpp"
#include "mire/metrology/pose_prediction.hpp"
#include "mire/metrology/target.hpp"
#include "mire/support/constants.hpp"
#include "synthetic_board.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

namespace metro = mire::metrology;
using Vector6d = Eigen::Matrix<double, 6, 1>;
using mire::support::kPi;

// The demo's board: 12 × 9 inner corners of 16 mm (datasets/specs/target_h4.yaml).
metro::Target demoBoard() { return mire::test::chessboard(12, 9, 0.016); }

// The board centred on the optical axis at `distance`, turned by `tilt_deg` about the camera's
// x axis, shifted by `shift` (camera frame).
Eigen::Isometry3d boardPose(const metro::Target& target, double distance, double tilt_deg,
                            const Eigen::Vector3d& shift = Eigen::Vector3d::Zero()) {
  const Eigen::Vector3d centre((target.spec().cols - 1) * 0.5 * target.spec().square_size_m,
                               (target.spec().rows - 1) * 0.5 * target.spec().square_size_m, 0.0);
  Eigen::Isometry3d cTm = Eigen::Isometry3d::Identity();
  cTm.linear() = Eigen::AngleAxisd(tilt_deg * kPi / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  cTm.translation() = Eigen::Vector3d(0, 0, distance) + shift - cTm.linear() * centre;
  return cTm;
}

TEST(PosePrediction, WholeTargetInsideIsVisible) {
  const auto camera = mire::datasets::referenceCamera();
  const metro::Visibility v = metro::targetVisibility(camera, demoBoard(), boardPose(demoBoard(), 0.8, 20.0));
  EXPECT_TRUE(v.visible) << v.reason;
  EXPECT_NEAR(v.tilt_deg, 20.0, 0.5);
  EXPECT_GT(v.min_margin_px, 100.0);
}

TEST(PosePrediction, PartlyOutsideTheImageIsExcluded) {
  const auto camera = mire::datasets::referenceCamera();
  const metro::Target board = demoBoard();
  // Slide the board to the right, 0.8 m away: the first shift that is refused still has most
  // features inside the image (partly outside), and the reason names the border or the outline.
  double shift = 0.0;
  metro::Visibility v;
  for (; shift < 1.0; shift += 0.005) {
    v = metro::targetVisibility(camera, board, boardPose(board, 0.8, 0.0, Eigen::Vector3d(shift, 0, 0)));
    if (!v.visible) break;
  }
  ASSERT_LT(shift, 1.0);
  ASSERT_GT(shift, 0.1);
  EXPECT_TRUE(v.reason.find("border") != std::string::npos || v.reason.find("outline") != std::string::npos) << v.reason;
  // 10 cm further about half the board is beyond the border: refused, naming a feature.
  const Eigen::Isometry3d cTm = boardPose(board, 0.8, 0.0, Eigen::Vector3d(shift + 0.1, 0, 0));
  int inside = 0;
  for (const auto& p : board.points()) {
    Eigen::Vector2d pixel;
    if (camera.project(cTm * p, &pixel) && pixel.x() >= 0 && pixel.x() < camera.width) ++inside;
  }
  EXPECT_GT(inside, 0);
  EXPECT_LT(inside, static_cast<int>(board.points().size()));
  const metro::Visibility partly = metro::targetVisibility(camera, board, cTm);
  EXPECT_FALSE(partly.visible);
  EXPECT_LT(partly.min_margin_px, 0.0);
  // Behind the camera.
  EXPECT_FALSE(metro::targetVisibility(camera, board, boardPose(board, -0.8, 0.0)).visible);
  // A margin wider than half the image refuses every pose.
  metro::VisibilityOptions strict;
  strict.margin_px = 1000.0;
  EXPECT_FALSE(metro::targetVisibility(camera, board, boardPose(board, 0.8, 0.0), strict).visible);
}

TEST(PosePrediction, TooObliqueIsExcluded) {
  const auto camera = mire::datasets::referenceCamera();
  const metro::Target board = demoBoard();
  const metro::Visibility oblique = metro::targetVisibility(camera, board, boardPose(board, 0.8, 65.0));
  EXPECT_FALSE(oblique.visible);
  EXPECT_NEAR(oblique.tilt_deg, 65.0, 0.5);
  EXPECT_NE(oblique.reason.find("tilted"), std::string::npos) << oblique.reason;
  EXPECT_TRUE(metro::targetVisibility(camera, board, boardPose(board, 0.8, 55.0)).visible);
  metro::VisibilityOptions wide;
  wide.max_tilt_deg = 70.0;
  EXPECT_TRUE(metro::targetVisibility(camera, board, boardPose(board, 0.8, 65.0), wide).visible);
}

// On exact features carrying the predicted covariance, estimatePose reports exactly the
// predicted (a) and (b): the same propagation.
TEST(PosePrediction, EqualsEstimatePoseOnExactFeatures) {
  auto camera = mire::datasets::referenceCamera();
  const metro::Target board = demoBoard();
  std::mt19937_64 rng(3);
  camera.covariance = mire::datasets::simulatedCalibrationCovariance(camera, board.points(), 25, 0.1, rng);
  const Eigen::Isometry3d cTm = boardPose(board, 0.8, 25.0, Eigen::Vector3d(0.05, -0.03, 0));
  metro::PredictionOptions options;
  options.pixel_sigma = 0.1;
  options.images = 4;
  options.systematic_px = 0.02;
  options.systematic_model = metro::SystematicModel::Constant;
  const metro::PosePrediction p = metro::predictPoseCovariance(camera, board.points(), cTm, options);
  ASSERT_TRUE(p.valid) << p.reason;

  const metro::Detection exact = mire::datasets::exactDetection(camera, board.points(), cTm);
  metro::AveragedFeatures features;
  features.ids = exact.ids;
  features.pixels = exact.pixels;
  const double variance = options.featureSigma() * options.featureSigma();
  features.covariance.assign(exact.ids.size(), variance * Eigen::Matrix2d::Identity());
  features.observations.assign(exact.ids.size(), options.images);
  features.pooled_dof = 10;
  const metro::PoseEstimate e = metro::estimatePose(camera, board.points(), features);
  ASSERT_TRUE(e.valid) << e.reason;
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(std::sqrt(p.covariance_noise(i, i)), std::sqrt(e.covariance_noise(i, i)),
                1e-6 * std::sqrt(e.covariance_noise(i, i)));
    EXPECT_NEAR(std::sqrt(p.covariance_intrinsics(i, i)), std::sqrt(e.covariance_intrinsics(i, i)),
                1e-6 * std::sqrt(e.covariance_intrinsics(i, i)));
  }
  EXPECT_GT(p.covariance_intrinsics.trace(), 0.0);
}

// Monte-Carlo: 300 poses measured from 5 noisy images each (σ 0.1 px per corner per image,
// exact intrinsics); std(error/σ_predicted) per component in [0.8, 1.25].
TEST(PosePrediction, MatchesTheMonteCarloSpreadOfEstimatePose) {
  const auto camera = mire::datasets::referenceCamera();
  const metro::Target board = demoBoard();
  const Eigen::Isometry3d cTm = boardPose(board, 0.85, 30.0, Eigen::Vector3d(-0.08, 0.05, 0));
  metro::PredictionOptions options;
  options.pixel_sigma = 0.1;
  options.images = 5;
  options.systematic_px = 0.0;  // the simulated corners carry random noise only
  options.systematic_model = metro::SystematicModel::Constant;
  const metro::PosePrediction p = metro::predictPoseCovariance(camera, board.points(), cTm, options);
  ASSERT_TRUE(p.valid) << p.reason;
  const Vector6d sigma = p.covariance.diagonal().cwiseSqrt();

  const metro::Detection exact = mire::datasets::exactDetection(camera, board.points(), cTm);
  ASSERT_EQ(exact.ids.size(), board.points().size());
  const std::vector<double> feature_sigmas(exact.ids.size(), options.pixel_sigma);
  std::mt19937_64 rng(17);
  constexpr int kTrials = 300;
  Vector6d sum_z2 = Vector6d::Zero();
  for (int t = 0; t < kTrials; ++t) {
    const auto averaged = metro::averageDetections(mire::datasets::noisyDetections(exact, feature_sigmas, 5, rng));
    const metro::PoseEstimate e = metro::estimatePose(camera, board.points(), averaged);
    ASSERT_TRUE(e.valid) << e.reason;
    Vector6d error;
    error.head<3>() = e.translation - cTm.translation();
    error.tail<3>() = e.rotation_vector - metro::rotationVector(cTm.linear());
    sum_z2 += error.cwiseQuotient(sigma).cwiseAbs2();
  }
  for (int i = 0; i < 6; ++i) {
    const double z = std::sqrt(sum_z2[i] / kTrials);
    EXPECT_GE(z, 0.8) << "component " << i;
    EXPECT_LE(z, 1.25) << "component " << i;
  }
}

// The BoardImage model of σ_sys (pose_prediction.hpp): the projected square measured from the
// board (16 mm at 0.8 m through the reference camera: f·0.016/0.8 px), σ_sys inversely
// proportional to it (twice the distance: twice σ_sys), larger with the edges along the pixel
// rows than at 45°, and the covariance whitened by it (the Constant model with the same σ_sys
// gives the same covariance).
TEST(PosePrediction, SystematicErrorFollowsTheBoardsImage) {
  const auto camera = mire::datasets::referenceCamera();
  const metro::Target board = demoBoard();
  const Eigen::Isometry3d near = boardPose(board, 0.8, 0.0), far = boardPose(board, 1.6, 0.0);
  const metro::BoardImageGeometry g = metro::boardImageGeometry(camera, board.points(), near);
  ASSERT_TRUE(g.valid);
  EXPECT_NEAR(g.square_px, camera.params[0] * 0.016 / 0.8, 0.02 * g.square_px);
  EXPECT_NEAR(std::abs(std::cos(2.0 * g.edge_angle_rad)), 1.0, 1e-3);  // edges along the rows

  const metro::PredictionOptions options;  // BoardImage by default
  const metro::PosePrediction p_near = metro::predictPoseCovariance(camera, board.points(), near, options);
  const metro::PosePrediction p_far = metro::predictPoseCovariance(camera, board.points(), far, options);
  ASSERT_TRUE(p_near.valid && p_far.valid);
  EXPECT_NEAR(p_near.systematic_px,
              (options.systematic_mean_px + options.systematic_grid_px) * options.reference_square_px / g.square_px,
              1e-6 * p_near.systematic_px);
  EXPECT_NEAR(p_far.systematic_px / p_near.systematic_px, 2.0, 0.05);

  Eigen::Isometry3d turned = near;
  turned.linear() = Eigen::AngleAxisd(kPi / 4, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const metro::PosePrediction p_turned = metro::predictPoseCovariance(camera, board.points(), turned, options);
  ASSERT_TRUE(p_turned.valid);
  EXPECT_NEAR(p_turned.systematic_px,
              (options.systematic_mean_px - options.systematic_grid_px) * options.reference_square_px / g.square_px,
              0.02 * p_turned.systematic_px);

  metro::PredictionOptions constant = options;
  constant.systematic_model = metro::SystematicModel::Constant;
  constant.systematic_px = p_near.systematic_px;
  const metro::PosePrediction p_constant = metro::predictPoseCovariance(camera, board.points(), near, constant);
  EXPECT_NEAR(p_constant.systematic_px, p_near.systematic_px, 1e-15);
  EXPECT_TRUE(p_constant.covariance.isApprox(p_near.covariance, 1e-12));
}

}  // namespace
