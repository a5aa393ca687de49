// The demo's pose scores (apps/src/pipeline/include/mire/pipeline/pose_scores.hpp): with a calibration error shared by every
// pose, error/σ pose by pose is one draw of that error per campaign, while the errors whitened with
// their whole cross-pose covariance are ≈ N(0, 1) — and expose a σ that is too large.
#include "mire/pipeline/pose_scores.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>

#include <cmath>
#include <random>
#include <vector>

namespace {

using mire::pipeline::PoseErrorSample;
using mire::pipeline::scorePoseErrors;

struct Campaign {
  std::vector<mire::pipeline::PoseErrorSample> samples;
  Eigen::MatrixXd camera_covariance;
};

Eigen::MatrixXd randomSpd(int n, double scale, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd a(n, n);
  for (int i = 0; i < a.size(); ++i) a.data()[i] = normal(rng);
  return scale * (a * a.transpose() / n + 0.2 * Eigen::MatrixXd::Identity(n, n));
}

// 81 poses, 4 intrinsics; the shared term dominates ty (component 1), as in the demo.
Campaign drawCampaign(std::mt19937& rng, double noise_scale_seen = 1.0) {
  std::normal_distribution<double> normal;
  Campaign c;
  c.camera_covariance = randomSpd(4, 1.0, rng);
  const Eigen::VectorXd dk =
      c.camera_covariance.llt().matrixL() * Eigen::Vector4d(normal(rng), normal(rng), normal(rng), normal(rng));
  for (int j = 0; j < 81; ++j) {
    mire::pipeline::PoseErrorSample s;
    s.sensitivity = Eigen::MatrixXd::Zero(6, 4);
    for (int i = 0; i < s.sensitivity.size(); ++i) s.sensitivity.data()[i] = 0.2 * normal(rng);
    s.sensitivity.row(1) += Eigen::RowVector4d(3.0, 0.5, 0.0, 0.0);  // ty: nearly the same for every pose
    const Eigen::MatrixXd noise = randomSpd(6, 1.0, rng);
    Eigen::Matrix<double, 6, 1> n;
    for (int k = 0; k < 6; ++k) n[k] = normal(rng);
    s.error = s.sensitivity * dk + noise.llt().matrixL() * n;
    s.independent = noise_scale_seen * noise;
    const Eigen::MatrixXd total = s.independent + s.sensitivity * c.camera_covariance * s.sensitivity.transpose();
    s.sigma = total.diagonal().cwiseSqrt();
    c.samples.push_back(s);
  }
  return c;
}

TEST(DemoPoseScores, WhitenedErrorsAreStandardWhilePoseByPoseDrawsTheSharedError) {
  std::mt19937 rng(5);
  double whitened_sum2 = 0.0, pose_ty_min = 1e9, pose_ty_max = 0.0;
  int whitened_outside = 0;
  const int trials = 200;
  for (int t = 0; t < trials; ++t) {
    const Campaign c = drawCampaign(rng);
    const auto s = mire::pipeline::scorePoseErrors(c.samples, c.camera_covariance);
    whitened_sum2 += s.rms_whitened_all * s.rms_whitened_all;
    for (int k = 0; k < 6; ++k) whitened_outside += s.rms_whitened[k] < 0.8 || s.rms_whitened[k] > 1.25;
    pose_ty_min = std::min(pose_ty_min, s.rms_per_pose[1]);
    pose_ty_max = std::max(pose_ty_max, s.rms_per_pose[1]);
  }
  EXPECT_NEAR(whitened_sum2 / trials, 1.0, 0.015);  // mean of χ²/(6·81) over 200 campaigns (sd 0.0045)
  EXPECT_LE(whitened_outside, 12) << "of " << 6 * trials << " component scores outside [0.8, 1.25]";
  // Pose by pose, ty's RMS is |one normal draw| (roughly): it ranges far outside [0.8, 1.25].
  EXPECT_LT(pose_ty_min, 0.3);
  EXPECT_GT(pose_ty_max, 2.0);
}

TEST(DemoPoseScores, WhitenedErrorsExposeAnOverstatedNoiseCovariance) {
  std::mt19937 rng(6);
  for (int t = 0; t < 20; ++t) {
    const Campaign c = drawCampaign(rng, 4.0);  // the scorer sees Σ_noise × 4 (σ twice too large)
    const auto s = mire::pipeline::scorePoseErrors(c.samples, c.camera_covariance);
    EXPECT_LT(s.rms_whitened_all, 0.65);
  }
}

TEST(DemoPoseScores, WithoutASharedTermAndWithDiagonalNoiseBothScoresAgree) {
  std::mt19937 rng(7);
  Campaign c = drawCampaign(rng);
  for (auto& s : c.samples) {
    s.sensitivity.resize(0, 0);
    s.independent = Eigen::Matrix<double, 6, 6>(s.independent.diagonal().asDiagonal());
    s.sigma = s.independent.diagonal().cwiseSqrt();
  }
  const auto s = mire::pipeline::scorePoseErrors(c.samples, Eigen::MatrixXd());
  for (int k = 0; k < 6; ++k) EXPECT_NEAR(s.rms_whitened[k], s.rms_per_pose[k], 1e-12) << k;
  EXPECT_NEAR(s.rms_whitened_all, s.rms_per_pose_all, 1e-12);
}

}  // namespace
