// ViSP's intrinsic-calibration tutorial images (../shared/datasets/external/visp-circles):
// 320×240, symmetric 6×6 grid of dark discs, 34 mm spacing. ViSP reports, for a model
// without distortion: px = 276.5098, py = 272.9595, u0 = 163.8652, v0 = 113.3046 and a
// reprojection error of 0.32664 px. Detection (metrology::detectTarget) + calibration with
// the distortion fixed at 0 must agree within 1 px. (Disc diameter ≈ 17 mm: measured from the
// images, blob size / spacing ≈ 0.5; it only sizes the centre refinement window.)
#include "mire/calibration/calibrate.hpp"
#include "mire/metrology/detection.hpp"
#include "mire/metrology/target.hpp"

#include "test_support.hpp"

#include <opencv2/imgcodecs.hpp>

#include <cstdio>

TEST(VispCircles, CalibrationMatchesVispWithoutDistortion) {
  MIRE_REQUIRE_SHARED("datasets/external/visp-circles/circles-01.jpg");
  mire::metrology::TargetSpec spec;
  spec.type = mire::metrology::TargetType::Circles;
  spec.cols = 6;
  spec.rows = 6;
  spec.spacing_m = 0.034;
  spec.diameter_m = 0.017;
  const mire::metrology::Target target(spec);
  std::vector<mire::calibration::CalibrationView> views;
  for (int i = 1; i <= 5; ++i) {
    const std::string name = "circles-0" + std::to_string(i) + ".jpg";
    const cv::Mat gray =
        cv::imread((mire::test::sharedDir() / "datasets/external/visp-circles" / name).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(gray.empty()) << name;
    // mire's default detection: grid finder, then each disc's ink centroid (sub-pixel).
    const mire::metrology::DetectionOptions detection_options;
    const auto detection = mire::metrology::detectTarget(target, gray, detection_options);
    ASSERT_TRUE(detection.found) << name << ": " << detection.reason;
    EXPECT_EQ(detection.size(), 36u) << name << ": " << detection.reason;
    views.push_back({name, detection.ids, detection.pixels});
  }
  mire::calibration::CalibrationOptions options;
  options.model = mire::calibration::DistortionModel::OpenCV4;
  options.fixed_parameters = {"k1", "k2", "p1", "p2"};  // ViSP's model without distortion
  const auto result = mire::calibration::calibrateCamera(target.points(), views, 320, 240, options);
  const auto& p = result.camera.params;
  std::printf(
      "visp circles: px %.4f py %.4f u0 %.4f v0 %.4f (ViSP 276.5098 272.9595 163.8652 113.3046), rms %.4f px "
      "(ViSP 0.32664), rejected %d points\n",
      p[0], p[1], p[2], p[3], result.camera.rms_px, result.rejected_points);
  EXPECT_NEAR(p[0], 276.5098, 1.0);
  EXPECT_NEAR(p[1], 272.9595, 1.0);
  EXPECT_NEAR(p[2], 163.8652, 1.0);
  EXPECT_NEAR(p[3], 113.3046, 1.0);
  EXPECT_EQ(result.used_views, 5);
  EXPECT_NEAR(result.camera.rms_px / 0.32664, 1.0, 0.15);
  for (int i = 4; i < 8; ++i) EXPECT_EQ(p[i], 0.0);
  const auto sigma = result.camera.sigmas();
  EXPECT_EQ(sigma[4], 0.0);  // fixed parameters carry no variance
  EXPECT_GT(sigma[0], 0.0);
}
