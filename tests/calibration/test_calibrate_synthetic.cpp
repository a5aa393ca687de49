// The calibration solver on exact synthetic data (synthetic_calibration.hpp): accuracy,
// Monte-Carlo coverage of its σ, outliers, target refinement on a bowed board.
#include "mire/calibration/calibrate.hpp"

#include "sample_statistics.hpp"
#include "synthetic_calibration.hpp"
#include "test_support.hpp"

#include <cmath>
#include <cstdio>
#include <vector>

namespace {

using mire::calibration::CalibrationOptions;
using mire::calibration::CalibrationResult;
using mire::calibration::CalibrationView;
using mire::calibration::DistortionModel;

constexpr int kCols = 11, kRows = 8;
constexpr double kSpacing = 0.02;  // 200 × 140 mm board

std::vector<CalibrationView> toViews(const std::vector<mire::test::SyntheticView>& views,
                                     const std::vector<std::vector<Eigen::Vector2d>>& pixels) {
  std::vector<CalibrationView> out;
  for (std::size_t v = 0; v < views.size(); ++v) out.push_back({"view " + std::to_string(v), views[v].ids, pixels[v]});
  return out;
}

CalibrationResult solve(const std::vector<Eigen::Vector3d>& nominal, const std::vector<CalibrationView>& views,
                        const CalibrationOptions& options = {}) {
  return mire::calibration::calibrateCamera(nominal, views, 1024, 768, options);
}

}  // namespace

TEST(CalibrateSynthetic, RecoversTheReferenceCameraWithin0p1Pixel) {
  const auto truth = mire::test::referenceCamera();
  // 0.1 px on fx..cy at 0.1 px noise needs a lot of information: a dense board
  // (25 × 18 corners, 10 mm), 30 views tilted up to ±55°, close enough to fill the image.
  const auto target = mire::test::gridTarget(25, 18, 0.01);
  const auto views = mire::test::makeViews(truth, target, 30, 7, 55.0, 0.22, 0.2);
  ASSERT_EQ(views.size(), 30u);
  const auto result = solve(target, toViews(views, mire::test::noisyPixels(views, 0.1, 11)));
  const auto& p = result.camera.params;
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(p[i], truth.params[i], 0.1) << result.camera.parameterNames()[i];
  for (int i = 4; i < 9; ++i) EXPECT_NEAR(p[i], truth.params[i], 0.01) << result.camera.parameterNames()[i];
  EXPECT_NEAR(result.sigma_px, 0.1, 0.01);
  EXPECT_EQ(result.rejected_views, 0);
  EXPECT_LE(result.rejected_points, 1);
  EXPECT_TRUE(result.warnings.empty()) << result.warnings.front();
  const auto uncertainty = mire::calibration::summarizeProjectionUncertainty(result);
  EXPECT_GT(uncertainty.centre_px, 0.0);
  EXPECT_LT(uncertainty.centre_px, uncertainty.corner_px);
  const auto sigma = result.camera.sigmas();
  std::printf("synthetic: sigma fx %.4f fy %.4f cx %.4f cy %.4f px\n", sigma[0], sigma[1], sigma[2], sigma[3]);
  std::printf(
      "synthetic: errors fx %.4f fy %.4f cx %.4f cy %.4f px; k1 %.2e k2 %.2e k3 %.2e; uncertainty centre %.4f "
      "edge %.4f corner %.4f px at %.3f m\n",
      p[0] - truth.params[0], p[1] - truth.params[1], p[2] - truth.params[2], p[3] - truth.params[3],
      p[4] - truth.params[4], p[5] - truth.params[5], p[8] - truth.params[8], uncertainty.centre_px,
      uncertainty.edge_px, uncertainty.corner_px, result.uncertainty_distance_m);
}

// Every printed σ must be validated: over 50 noise draws (fixed seeds), (error / predicted σ)
// of each parameter must have a standard deviation near 1; so must the projection error at
// the centre and the corner against the predicted projection covariance.
TEST(CalibrateSynthetic, MonteCarloSigmaCoverage) {
  const auto truth = mire::test::referenceCamera();
  const auto target = mire::test::gridTarget(kCols, kRows, kSpacing);
  const auto views = mire::test::makeViews(truth, target, 20, 21);
  std::vector<mire::test::PoseVector> truth_poses;
  for (const auto& view : views) truth_poses.push_back(view.pose);
  const int runs = 50;
  const int n = static_cast<int>(truth.params.size());
  std::vector<std::vector<double>> z(n);
  std::vector<double> z_centre, z_corner;
  for (int run = 0; run < runs; ++run) {
    const auto result = solve(target, toViews(views, mire::test::noisyPixels(views, 0.1, 1000 + run)));
    ASSERT_EQ(result.used_views, static_cast<int>(views.size()));
    const auto sigma = result.camera.sigmas();
    for (int i = 0; i < n; ++i) z[i].push_back((result.camera.params[i] - truth.params[i]) / sigma[i]);
    // Projection error of a fixed world point (mrcal's definition, calibrate.hpp) whitened by
    // the predicted 2×2 covariance: each component of L⁻¹e is N(0, 1) when Σ = LLᵀ is right.
    std::vector<mire::test::PoseVector> estimate_poses;
    for (const int v : result.state_view_index) {
      mire::test::PoseVector pose;
      pose << result.views[v].rotation, result.views[v].translation;
      estimate_poses.push_back(pose);
    }
    const double d = result.uncertainty_distance_m;
    for (const auto& [pixel, out] : {std::pair<Eigen::Vector2d, std::vector<double>*>{{511.5, 383.5}, &z_centre},
                                     std::pair<Eigen::Vector2d, std::vector<double>*>{{30.0, 30.0}, &z_corner}}) {
      const Eigen::Vector2d error = mire::calibration::reprojectThroughEstimate(result.camera.params, estimate_poses,
                                                                                truth.params, truth_poses, pixel, d) -
                                    pixel;
      const Eigen::Matrix2d covariance = mire::calibration::projectionCovariancePx(result, pixel, d);
      const Eigen::Vector2d whitened = covariance.llt().matrixL().solve(error);
      out->push_back(whitened.x());
      out->push_back(whitened.y());
    }
  }
  const auto names = truth.parameterNames();
  for (int i = 0; i < n; ++i) {
    const double ratio = mire::test::sampleStandardDeviation(z[i]);
    std::printf("MC %s: std(error/sigma) = %.3f\n", names[i].c_str(), ratio);
    EXPECT_GE(ratio, 0.8) << names[i];
    EXPECT_LE(ratio, 1.25) << names[i];
  }
  const double centre = mire::test::sampleStandardDeviation(z_centre),
               corner = mire::test::sampleStandardDeviation(z_corner);
  std::printf("MC projection: std(whitened error) centre %.3f corner %.3f\n", centre, corner);
  EXPECT_GE(centre, 0.8);
  EXPECT_LE(centre, 1.25);
  EXPECT_GE(corner, 0.8);
  EXPECT_LE(corner, 1.25);
}

TEST(CalibrateSynthetic, RejectsGrossOutliersAndReportsThem) {
  const auto truth = mire::test::referenceCamera();
  const auto target = mire::test::gridTarget(kCols, kRows, kSpacing);
  const auto views = mire::test::makeViews(truth, target, 20, 5);
  auto pixels = mire::test::noisyPixels(views, 0.1, 3);
  const auto clean = solve(target, toViews(views, pixels));
  // 10 mismatched corners (3–8 px off) and one view with half its points wrong.
  for (int i = 0; i < 10; ++i) pixels[i][5 + i] += Eigen::Vector2d(3.0 + 0.5 * i, -2.0);
  for (std::size_t k = 0; k < pixels[12].size(); k += 2) pixels[12][k] += Eigen::Vector2d(6.0, 4.0);
  const auto result = solve(target, toViews(views, pixels));
  EXPECT_EQ(result.rejected_views, 1);
  EXPECT_FALSE(result.views[12].used);
  EXPECT_FALSE(result.views[12].rejection_reason.empty());
  EXPECT_GE(result.rejected_points, 10);
  EXPECT_LE(result.rejected_points, 12);
  // The outliers must not move the estimate: it stays within a fraction of σ of the
  // calibration of the same noisy data without them.
  const auto sigma = clean.camera.sigmas();
  for (std::size_t i = 0; i < truth.params.size(); ++i)
    EXPECT_NEAR(result.camera.params[i], clean.camera.params[i], 0.5 * sigma[i]) << truth.parameterNames()[i];
  EXPECT_NEAR(result.sigma_px, 0.1, 0.01);
}

// Lavest & Dhome: a board bowed by 0.3 mm biases the intrinsics of a calibration that assumes
// it flat; refining the target's points recovers the bow and removes the bias.
TEST(CalibrateSynthetic, RefineTargetRecoversABowedBoard) {
  const auto truth = mire::test::referenceCamera();
  const double sag = 0.3e-3;
  const auto bowed = mire::test::gridTarget(kCols, kRows, kSpacing, sag);
  const auto nominal = mire::test::gridTarget(kCols, kRows, kSpacing);
  const auto views = mire::test::makeViews(truth, bowed, 25, 17);
  const auto observed = toViews(views, mire::test::noisyPixels(views, 0.05, 19));

  const auto flat = solve(nominal, observed);
  CalibrationOptions refine;
  refine.refine_target = true;
  const auto refined = solve(nominal, observed, refine);

  double flat_worst = 0.0, refined_worst = 0.0, flat_worst_sigma = 0.0, refined_worst_sigma = 0.0;
  const auto flat_sigma = flat.camera.sigmas(), refined_sigma = refined.camera.sigmas();
  for (int i = 0; i < 4; ++i) {
    const double e_flat = std::abs(flat.camera.params[i] - truth.params[i]);
    const double e_refined = std::abs(refined.camera.params[i] - truth.params[i]);
    flat_worst = std::max(flat_worst, e_flat);
    refined_worst = std::max(refined_worst, e_refined);
    flat_worst_sigma = std::max(flat_worst_sigma, e_flat / flat_sigma[i]);
    refined_worst_sigma = std::max(refined_worst_sigma, e_refined / refined_sigma[i]);
  }
  // Recovered bow: every refined point's z against the truth, in the gauge's frame (the gauge
  // fixes three corners, which the paraboloid keeps at z = 0, so the frames coincide).
  double z_error2 = 0.0, z_error_max = 0.0;
  for (std::size_t i = 0; i < bowed.size(); ++i) {
    const double e = refined.target_points[i].z() - bowed[i].z();
    z_error2 += e * e;
    z_error_max = std::max(z_error_max, std::abs(e));
  }
  const double z_error_rms = std::sqrt(z_error2 / bowed.size());
  std::printf(
      "bow: flat-board fx fy cx cy worst error %.3f px (%.1f sigma), rms %.4f px; refined worst %.3f px "
      "(%.1f sigma), rms %.4f px\n",
      flat_worst, flat_worst_sigma, flat.camera.rms_px, refined_worst, refined_worst_sigma, refined.camera.rms_px);
  std::printf("bow: recovered out-of-plane max %.4f mm rms %.4f mm (true max %.3f mm); z error rms %.4f max %.4f mm\n",
              refined.target_out_of_plane_max_m * 1e3, refined.target_out_of_plane_rms_m * 1e3, sag * 1e3,
              z_error_rms * 1e3, z_error_max * 1e3);
  EXPECT_GT(flat_worst_sigma, 5.0);     // flat assumption: biased far beyond its σ
  EXPECT_LT(refined_worst_sigma, 3.0);  // refined: consistent with its σ
  EXPECT_LT(refined_worst, 0.5 * flat_worst);
  EXPECT_LT(z_error_rms, 0.03e-3);  // the 0.3 mm bow recovered to 10 % RMS
  EXPECT_LT(z_error_max, 0.08e-3);
  EXPECT_NEAR(std::abs(refined.target_points[(kRows / 2) * kCols + kCols / 2].z()), sag, 0.05e-3);
  EXPECT_GT(flat.camera.rms_px, 1.3 * refined.camera.rms_px);

  // 25 well-spread views determine the refinement: no "weakly determined" warning; the
  // comparison with the rigid board is kept, and the bias it removes shows as a shift.
  ASSERT_TRUE(refined.target_refinement.has_value());
  const auto& check = *refined.target_refinement;
  std::printf(
      "bow: refinement adds %d unknowns; largest fx..cy shift %.1f combined sigma; projection uncertainty "
      "x%.2f at most; weakly determined %d\n",
      check.added_unknowns, check.largest_intrinsic_shift_sigma, check.largest_uncertainty_ratio,
      check.weakly_determined ? 1 : 0);
  EXPECT_EQ(check.added_unknowns, 3 * kCols * kRows - 7);
  EXPECT_FALSE(check.weakly_determined);
  EXPECT_LT(check.largest_uncertainty_ratio, 3.0);
  for (const auto& warning : refined.warnings)
    EXPECT_EQ(warning.find("weakly determined"), std::string::npos) << warning;
  EXPECT_NEAR(check.rigid_params[2], flat.camera.params[2], 1e-9);
  EXPECT_FALSE(flat.target_refinement.has_value());
}

// A flat board, refined anyway from well-spread views: nothing to warn about (the refinement
// neither loses the intrinsics nor moves them beyond the rigid calibration's σ).
TEST(CalibrateSynthetic, RefiningAFlatBoardFromGoodViewsDoesNotWarn) {
  const auto truth = mire::test::referenceCamera();
  const auto target = mire::test::gridTarget(kCols, kRows, kSpacing);
  CalibrationOptions refine;
  refine.refine_target = true;
  int shift_warnings = 0;
  for (unsigned seed = 0; seed < 4; ++seed) {
    const auto views = mire::test::makeViews(truth, target, 25, 23 + seed);
    const auto refined = solve(target, toViews(views, mire::test::noisyPixels(views, 0.1, 29 + seed)), refine);
    ASSERT_TRUE(refined.target_refinement.has_value());
    const auto& check = *refined.target_refinement;
    std::printf(
        "flat board refined (seed %u): largest fx..cy shift %.2f combined sigma, projection uncertainty "
        "x%.2f at most\n",
        seed, check.largest_intrinsic_shift_sigma, check.largest_uncertainty_ratio);
    EXPECT_FALSE(check.weakly_determined);
    for (const auto& warning : refined.warnings) {
      EXPECT_EQ(warning.find("weakly determined"), std::string::npos) << warning;
      shift_warnings += warning.find("--refine-target moved") != std::string::npos;
    }
  }
  EXPECT_LE(shift_warnings, 1);  // 3 sigma over 4 parameters x 4 sets: a rare false alarm allowed
}

TEST(CalibrateSynthetic, WarnsWhenViewsAreFrontoParallelAndMissCorners) {
  const auto truth = mire::test::referenceCamera();
  const auto target = mire::test::gridTarget(kCols, kRows, kSpacing);
  std::vector<CalibrationView> views;
  for (int v = 0; v < 5; ++v) {
    CalibrationView view;
    view.name = "frontal " + std::to_string(v);
    const Eigen::Vector3d t(-0.1 + 0.01 * v, -0.07, 0.45 + 0.02 * v);
    for (std::size_t i = 0; i < target.size(); ++i) {
      Eigen::Vector2d pixel;
      ASSERT_TRUE(truth.project(target[i] + t, &pixel));
      view.ids.push_back(static_cast<int>(i));
      view.pixels.push_back(pixel);
    }
    views.push_back(view);
  }
  CalibrationOptions options;
  options.fixed_parameters = {"k3"};
  const auto result = solve(target, views, options);
  bool corner_warning = false, tilt_warning = false;
  for (const auto& w : result.warnings) {
    corner_warning = corner_warning || w.find("corner") != std::string::npos;
    tilt_warning = tilt_warning || w.find("fronto-parallel") != std::string::npos;
  }
  EXPECT_TRUE(corner_warning);
  EXPECT_TRUE(tilt_warning);
}

TEST(CalibrateSynthetic, TooFewViewsThrowsNamingTheCount) {
  const auto truth = mire::test::referenceCamera();
  const auto target = mire::test::gridTarget(kCols, kRows, kSpacing);
  const auto views = mire::test::makeViews(truth, target, 2, 3);
  try {
    solve(target, toViews(views, mire::test::noisyPixels(views, 0.1, 1)));
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("2 usable views"), std::string::npos) << error.what();
  }
}
