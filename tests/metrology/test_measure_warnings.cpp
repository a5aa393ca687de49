// measurePose's warnings with numbers (doc/measurement.md, "Warnings with numbers"), on
// rendered images of known pose: one image of one tag (a σ from 2 residual degrees of
// freedom, and how far such a σ is from the spread it claims), and a camera file that does not
// fit the images.
#include "mire/datasets/feature_campaign.hpp"
#include "mire/datasets/render.hpp"
#include "mire/metrology/pose_measurement.hpp"

#include "chessboard_views.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace mire::metrology {
namespace {

Eigen::Isometry3d viewOf(const Eigen::Vector3d& translation, double tilt_deg) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(tilt_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pose.translation() = translation;
  return pose;
}

Target oneTag() {
  TargetSpec spec;
  spec.type = TargetType::AprilTag;
  spec.family = "tag36h11";
  spec.tag_size_m = 0.06;
  spec.tags = {{3, 0.0, 0.0}};
  return Target(spec);
}

bool hasWarning(const PoseMeasurement& measurement, const std::string& text) {
  return std::any_of(measurement.warnings.begin(), measurement.warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

// Tz error / σ over single-image renders of one tag, and the mean per-point residual² (what a
// calibration's rms_px² is for these images).
struct OneTagSpread {
  double rms_z = 0.0, worst_z = 0.0, mean_point_residual2 = 0.0;
  std::vector<std::string> first_warnings;
};

OneTagSpread oneTagSpread(const calibration::Camera& truth, const calibration::Camera& file, int renders) {
  const Target target = oneTag();
  datasets::RenderOptions options;
  options.blur_sigma_px = 0.6;
  const datasets::Renderer renderer(truth, target, options);
  OneTagSpread spread;
  double sum2 = 0.0;
  for (int k = 0; k < renders; ++k) {
    const Eigen::Isometry3d pose = viewOf(Eigen::Vector3d(-0.03 + 0.002 * k, -0.03, 0.45 + 0.004 * k), 20.0);
    const cv::Mat image = datasets::addNoise(renderer.render(pose).radiance, {2.0, 0.0}, 100 + k);
    const PoseMeasurement measured = measurePose(file, target, {image}, {"tag.png"});
    EXPECT_TRUE(measured.ok) << measured.error;
    if (!measured.ok) continue;
    if (k == 0) spread.first_warnings = measured.warnings;
    const double z =
        (measured.estimate.translation.z() - pose.translation().z()) / std::sqrt(measured.estimate.covariance(2, 2));
    sum2 += z * z;
    spread.worst_z = std::max(spread.worst_z, std::abs(z));
    spread.mean_point_residual2 += measured.estimate.rms_px * measured.estimate.rms_px / renders;
  }
  spread.rms_z = std::sqrt(sum2 / renders);
  return spread;
}

bool listed(const std::vector<std::string>& warnings, const std::string& text) {
  return std::any_of(warnings.begin(), warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

// One image of one tag: 4 corners, 8 residuals, 6 pose parameters. The σ from those 2 degrees of
// freedom alone is far from honest (a t distribution with 2 degrees of freedom); pooled with a
// calibration RMS that is the detector's noise on such images, it is much closer.
TEST(MeasureWarnings, OneImageOfOneTagSigmaRestsOnTwoDegreesOfFreedomAndIsPooledWithTheCalibration) {
  const calibration::Camera camera = datasets::referenceCamera();  // no rms_px: nothing to pool with
  const OneTagSpread alone = oneTagSpread(camera, camera, 24);
  for (const auto& warning : alone.first_warnings) std::printf("  warning: %s\n", warning.c_str());
  EXPECT_TRUE(listed(alone.first_warnings, "sigma from 2 residual degree(s) of freedom"));
  EXPECT_TRUE(listed(alone.first_warnings, "about 50 %"));
  EXPECT_FALSE(listed(alone.first_warnings, "does not fit"));
  // Per point, E[residual²] = dof/N · 2σ² (σ per coordinate): the RMS a calibration from such
  // images prints is √(2σ²) = √(N/dof · mean residual²).
  calibration::Camera with_rms = camera;
  with_rms.rms_px = std::sqrt(4.0 / 2.0 * alone.mean_point_residual2);
  const OneTagSpread pooled = oneTagSpread(camera, with_rms, 24);
  for (const auto& warning : pooled.first_warnings) std::printf("  warning: %s\n", warning.c_str());
  std::printf(
      "one tag, one image, 24 renders: RMS(tz error / sigma) %.2f (worst %.1f) from the residuals alone; "
      "%.2f (worst %.1f) pooled with rms_px %.3f px\n",
      alone.rms_z, alone.worst_z, pooled.rms_z, pooled.worst_z, with_rms.rms_px);
  EXPECT_GT(alone.rms_z, 1.25);
  EXPECT_TRUE(listed(pooled.first_warnings, "pooled with the camera file's calibration RMS"));
  // Pooling removes the σ that were far too small (2-dof estimates near 0); what remains above 1
  // is the detector's corner bias, common to these renders of nearly one pose, which no residual
  // of one image shows (doc/measurement.md): measured 1.72, against 3.71 alone.
  EXPECT_LT(pooled.rms_z, 0.6 * alone.rms_z);
  EXPECT_LT(pooled.worst_z, 0.5 * alone.worst_z);
  EXPECT_GT(pooled.rms_z, 0.8);
}

// A camera file that is not this camera's (the lens' k1 dropped): pixel-sized residuals that
// no pose removes, warned about with the RMS against the calibration's.
TEST(MeasureWarnings, WrongCameraFileWarnsThatTheCameraDoesNotFit) {
  const calibration::Camera camera = datasets::referenceCamera();
  const Target target = test::chessboard9x6();
  const datasets::Renderer renderer(camera, target);
  const Eigen::Isometry3d pose = viewOf(Eigen::Vector3d(-0.25, -0.12, 0.5), 15.0);
  const cv::Mat image = datasets::addNoise(renderer.render(pose).radiance, {1.0, 0.0}, 7);

  calibration::Camera right = camera;
  right.rms_px = 0.15;
  const PoseMeasurement good = measurePose(right, target, {image}, {"board.png"});
  ASSERT_TRUE(good.ok) << good.error;
  EXPECT_FALSE(hasWarning(good, "does not fit")) << good.estimate.rms_px;

  calibration::Camera wrong = right;
  wrong.params[4] = 0.0;  // k1
  const PoseMeasurement bad = measurePose(wrong, target, {image}, {"board.png"});
  ASSERT_TRUE(bad.ok) << bad.error;
  std::printf("right camera: RMS %.3f px; wrong camera (k1 = 0): RMS %.3f px\n", good.estimate.rms_px,
              bad.estimate.rms_px);
  for (const auto& warning : bad.warnings) std::printf("  warning: %s\n", warning.c_str());
  EXPECT_GT(bad.estimate.rms_px, 1.0);
  EXPECT_TRUE(hasWarning(bad, "the camera does not fit the images: reprojection RMS"));
  EXPECT_TRUE(hasWarning(bad, "0.150 px expected"));
}

}  // namespace
}  // namespace mire::metrology
