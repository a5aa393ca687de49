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

// One image of one tag: 4 corners, 8 residuals, 6 pose parameters. The σ rests on 2 degrees of
// freedom; the warning says so with the number, and the spread of error/σ over renders shows
// why: a t distribution with 2 degrees of freedom, far wider than 1.
TEST(MeasureWarnings, OneImageOfOneTagWarnsThatItsSigmaRestsOnTwoDegreesOfFreedom) {
  const calibration::Camera camera = datasets::referenceCamera();
  const Target target = oneTag();
  datasets::RenderOptions options;
  options.blur_sigma_px = 0.6;
  const datasets::Renderer renderer(camera, target, options);
  std::vector<double> z;  // tz error / σ(tz)
  for (int k = 0; k < 24; ++k) {
    const Eigen::Isometry3d pose = viewOf(Eigen::Vector3d(-0.03 + 0.002 * k, -0.03, 0.45 + 0.004 * k), 20.0);
    const auto rendering = renderer.render(pose);
    const cv::Mat image = datasets::addNoise(rendering.radiance, {2.0, 0.0}, 100 + k);
    const PoseMeasurement measured = measurePose(camera, target, {image}, {"tag.png"});
    ASSERT_TRUE(measured.ok) << measured.error;
    if (k == 0) {
      for (const auto& warning : measured.warnings) std::printf("  warning: %s\n", warning.c_str());
      EXPECT_TRUE(hasWarning(measured, "sigma from 2 residual degree(s) of freedom"));
      EXPECT_TRUE(hasWarning(measured, "about 50 %"));
      EXPECT_FALSE(hasWarning(measured, "does not fit"));
    }
    const double sigma = std::sqrt(measured.estimate.covariance(2, 2));
    z.push_back((measured.estimate.translation.z() - pose.translation().z()) / sigma);
  }
  double sum2 = 0.0, worst = 0.0;
  for (const double value : z) sum2 += value * value, worst = std::max(worst, std::abs(value));
  const double spread = std::sqrt(sum2 / z.size());
  std::printf("one tag, one image, %zu renders: RMS(tz error / sigma) = %.2f, worst %.1f\n", z.size(), spread, worst);
  // Honest σ would give ≈ 1; a σ from 2 degrees of freedom is often far too small.
  EXPECT_GT(spread, 1.25);
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
