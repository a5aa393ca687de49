// Fisheye acceptance (doc/calibration.md): chessboard views rendered through a
// wide-angle fisheye camera (1024×768, fx ≈ 300: ≈ 120° across the width; k1..k4 of a real
// lens, Kalibr's equidistant example) are detected by mire's detector and calibrated with the
// fisheye model: fx fy cx cy within 0.3 px of the truth, and within 3σ of it.
#include "mire/calibration/calibrate.hpp"
#include "mire/datasets/render.hpp"
#include "mire/metrology/detection.hpp"
#include "mire/metrology/target.hpp"

#include "synthetic_calibration.hpp"

#include <gtest/gtest.h>

#include <cstdio>

namespace {

mire::calibration::Camera fisheyeCamera() {
  mire::calibration::Camera camera;
  camera.width = 1024;
  camera.height = 768;
  camera.lens = mire::calibration::LensModel::Fisheye;
  camera.params = {300.2,
                   299.6,
                   513.4,
                   381.7,
                   -0.005908650672531068,
                   0.01587953759563821,
                   -0.024196671184075886,
                   0.015501252412920248};
  camera.validate();
  return camera;
}

}  // namespace

TEST(FisheyeCalibration, RenderedViewsCalibrateWithinAThirdOfAPixel) {
  const auto truth = fisheyeCamera();
  mire::metrology::TargetSpec spec;
  spec.cols = 9;
  spec.rows = 6;
  spec.square_size_m = 0.03;
  const mire::metrology::Target target(spec);
  const mire::datasets::Renderer renderer(truth, target);
  // Whole-board views spread over the image (up to ≈ 60° off-axis), tilted up to 40°.
  const auto candidates = mire::test::makeViews(truth, target.points(), 30, 17, 40.0, 0.22, 0.12);
  std::vector<mire::calibration::CalibrationView> views;
  int rendered = 0;
  for (const auto& view : candidates) {
    if (view.ids.size() != target.points().size()) continue;
    if (views.size() >= 14) break;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(view.pose.head<3>().norm(), view.pose.head<3>().normalized()).toRotationMatrix();
    pose.translation() = view.pose.tail<3>();
    const auto rendering = renderer.render(pose);
    ++rendered;
    const cv::Mat image = mire::datasets::addNoise(rendering.radiance, {2.0, 0.0}, 100 + rendered);
    const auto detection = mire::metrology::detectTarget(target, image);
    if (!detection.found) continue;
    views.push_back({"view " + std::to_string(rendered), detection.ids, detection.pixels});
  }
  std::printf("fisheye: %zu of %d rendered views detected\n", views.size(), rendered);
  ASSERT_GE(views.size(), 10u);
  mire::calibration::CalibrationOptions options;
  options.model = mire::calibration::DistortionModel::Fisheye;
  const auto result = mire::calibration::calibrateCamera(target.points(), views, truth.width, truth.height, options);
  EXPECT_EQ(result.camera.lens, mire::calibration::LensModel::Fisheye);
  const auto sigma = result.camera.sigmas();
  const auto names = truth.parameterNames();
  for (int i = 0; i < 8; ++i) {
    const double error = result.camera.params[i] - truth.params[i];
    std::printf("  %s = %.6f (truth %.6f, error %+.6f, sigma %.6f, error/sigma %+.2f)\n", names[i].c_str(),
                result.camera.params[i], truth.params[i], error, sigma[i], error / sigma[i]);
    if (i < 4) {
      EXPECT_LT(std::abs(error), 0.3) << names[i];
      EXPECT_LT(std::abs(error), 3.0 * sigma[i]) << names[i];
    }
  }
  std::printf("fisheye: %d views, %d points, rms %.4f px\n", result.used_views, result.used_points, result.camera.rms_px);
}
