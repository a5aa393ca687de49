// `--refine-target` on OpenCV's sample chessboard photos left01..left14.jpg (9 × 6 inner
// corners, 25 mm; shipped by Debian's opencv-doc, skipped when absent): the result is finite,
// and the shift of cy against the flat-board calibration (≈ 5 px) is explained by
// the board's refined deformation: the refined camera, poses and board, projected exactly and
// calibrated as a flat board, reproduce the flat result's cy shift within 2σ.
#include "mire/calibration/calibrate.hpp"
#include "mire/metrology/detection.hpp"
#include "mire/metrology/target.hpp"

#include <ceres/rotation.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <filesystem>

namespace {

const std::filesystem::path kSamples = "/usr/share/doc/opencv-doc/examples/data";

}  // namespace

TEST(RefineTargetLeft, FiniteAndTheCyShiftIsTheBoardsDeformation) {
  if (!std::filesystem::exists(kSamples / "left01.jpg"))
    GTEST_SKIP() << "needs OpenCV's left*.jpg (Debian opencv-doc, " << kSamples << "): absent, skipped";
  mire::metrology::TargetSpec spec;
  spec.cols = 9;
  spec.rows = 6;
  spec.square_size_m = 0.025;
  const mire::metrology::Target target(spec);
  std::vector<mire::calibration::CalibrationView> views;
  int width = 0, height = 0;
  for (int i = 1; i <= 14; ++i) {
    const std::string name = std::string("left") + (i < 10 ? "0" : "") + std::to_string(i) + ".jpg";
    if (!std::filesystem::exists(kSamples / name)) continue;  // OpenCV ships no left10.jpg
    const cv::Mat gray = cv::imread((kSamples / name).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(gray.empty()) << name;
    width = gray.cols;
    height = gray.rows;
    const auto detection = mire::metrology::detectTarget(target, gray);
    if (detection.found) views.push_back({name, detection.ids, detection.pixels});
  }
  ASSERT_GE(views.size(), 12u);
  mire::calibration::CalibrationOptions options;
  const auto flat = mire::calibration::calibrateCamera(target.points(), views, width, height, options);
  options.refine_target = true;
  const auto refined = mire::calibration::calibrateCamera(target.points(), views, width, height, options);
  for (const double value : refined.camera.params) EXPECT_TRUE(std::isfinite(value));
  EXPECT_TRUE(refined.camera.covariance.allFinite());

  // 13 views cannot pin down 155 more unknowns: the refinement is flagged weakly determined
  // (the corner's projection uncertainty grows ≈ 40×) and cy's move beyond 3 rigid σ is named.
  ASSERT_TRUE(refined.target_refinement.has_value());
  const auto& check = *refined.target_refinement;
  std::printf(
      "left*.jpg refine check: %d unknowns added; projection uncertainty corner %.2f -> %.2f px (x%.1f); cy "
      "shift %.2f combined sigma\n",
      check.added_unknowns, check.rigid_uncertainty.corner_px, check.refined_uncertainty.corner_px,
      check.largest_uncertainty_ratio, check.shift_sigmas[3]);
  for (const auto& warning : refined.warnings) std::printf("  warning: %s\n", warning.c_str());
  EXPECT_TRUE(check.weakly_determined);
  EXPECT_GT(check.largest_uncertainty_ratio, 10.0);
  EXPECT_GT(check.shift_sigmas[3], 3.0);
  int named = 0;
  for (const auto& warning : refined.warnings)
    named +=
        warning.find("weakly determined") != std::string::npos || warning.find("moved cy 233.9") != std::string::npos;
  EXPECT_EQ(named, 2);

  // The refined world seen through a flat-board calibration.
  std::vector<mire::calibration::CalibrationView> synthetic;
  for (const auto& view : refined.views) {
    if (!view.used) continue;
    mire::calibration::CalibrationView copy{view.name, {}, {}};
    for (const int id : view.ids) {
      Eigen::Vector3d in_camera;
      ceres::AngleAxisRotatePoint(view.rotation.data(), refined.target_points[id].data(), in_camera.data());
      Eigen::Vector2d pixel;
      if (!refined.camera.project(in_camera + view.translation, &pixel)) continue;
      copy.ids.push_back(id);
      copy.pixels.push_back(pixel);
    }
    synthetic.push_back(copy);
  }
  options.refine_target = false;
  const auto explained = mire::calibration::calibrateCamera(target.points(), synthetic, width, height, options);
  const double sigma_flat = flat.camera.sigmas()[3], sigma_refined = refined.camera.sigmas()[3];
  const double shift = flat.camera.cy() - refined.camera.cy();
  const double predicted = explained.camera.cy() - refined.camera.cy();
  std::printf(
      "left*.jpg: cy flat %.3f +- %.3f, refined %.3f +- %.3f (shift %.3f px = %.1f sigma); the refined board "
      "(out of plane RMS %.3f mm, max %.3f mm) calibrated flat predicts a shift of %.3f px; fx flat %.3f refined "
      "%.3f predicted %.3f\n",
      flat.camera.cy(), sigma_flat, refined.camera.cy(), sigma_refined, shift, shift / sigma_flat,
      refined.target_out_of_plane_rms_m * 1e3, refined.target_out_of_plane_max_m * 1e3, predicted, flat.camera.fx(),
      refined.camera.fx(), explained.camera.fx());
  EXPECT_LT(std::abs(shift - predicted), 2.0 * sigma_flat);
  // The deformed board leaves residuals correlated within each view: the flat calibration's σ
  // grow with that evidence (view-cluster sandwich), here cy's by ≈ 1.9 (doc/calibration.md).
  std::printf("left*.jpg flat: sigma inflation fx %.2f fy %.2f cx %.2f cy %.2f k1 %.2f\n", flat.sigma_inflation[0],
              flat.sigma_inflation[1], flat.sigma_inflation[2], flat.sigma_inflation[3], flat.sigma_inflation[4]);
  EXPECT_GT(flat.sigma_inflation[3], 1.5);

  // The projection uncertainty without that inflation is mrcal's definition (σ²(JᵀJ)⁻¹ from the
  // residuals; doc/calibration.md, "mire's projection uncertainty and mrcal's"): the inflation
  // is the factor 2-3.4 between the two tools on these corners.
  mire::calibration::CalibrationOptions pixel_noise_only;
  pixel_noise_only.view_cluster_covariance = false;
  const auto plain = mire::calibration::calibrateCamera(target.points(), views, width, height, pixel_noise_only);
  const auto inflated_u = mire::calibration::summarizeProjectionUncertainty(flat);
  const auto plain_u = mire::calibration::summarizeProjectionUncertainty(plain);
  std::printf(
      "left*.jpg projection uncertainty (px, centre edge corner): with the view-cluster inflation %.4f %.4f "
      "%.4f, pixel noise only %.4f %.4f %.4f (ratios %.2f %.2f %.2f)\n",
      inflated_u.centre_px, inflated_u.edge_px, inflated_u.corner_px, plain_u.centre_px, plain_u.edge_px,
      plain_u.corner_px, inflated_u.centre_px / plain_u.centre_px, inflated_u.edge_px / plain_u.edge_px,
      inflated_u.corner_px / plain_u.corner_px);
  EXPECT_EQ(plain.camera.params, flat.camera.params);  // same solution, other σ
  EXPECT_GT(inflated_u.centre_px / plain_u.centre_px, 2.5);
  EXPECT_GT(inflated_u.edge_px / plain_u.edge_px, 1.5);
  EXPECT_NEAR(flat.camera.sigmas()[3], flat.sigma_inflation[3] * std::sqrt(flat.covariance_pixel_noise(3, 3)), 1e-9);
}
