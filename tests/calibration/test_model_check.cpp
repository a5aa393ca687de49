// The model check (model_check.hpp) on exact synthetic views with Gaussian noise: a decentred
// (thin-prism) lens calibrated with the default model is found insufficient and opencv12 is
// named; opencv12 then recovers fx fy cx cy; a lens the default model represents is adequate;
// the held-out check predicts the held-out error. Rendered images: tests/metrology.
#include "mire/calibration/calibrate.hpp"
#include "mire/calibration/model_check.hpp"

#include "synthetic_calibration.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

namespace mire::calibration {
namespace {

// The reference camera's lens, decentred: OpenCV's thin-prism terms of a cheap lens.
Camera thinPrismCamera() {
  return cameraFromOpenCV(1024, 768, 817.2, 816.4, 517.6, 381.2,
                          {-0.30, 0.10, 4e-4, -3e-4, -0.015, 0.0, 0.0, 0.0, 0.004, -0.002, 0.003, 0.001});
}

std::vector<CalibrationView> noisyViews(const Camera& truth, const std::vector<Eigen::Vector3d>& target, unsigned seed,
                                        double noise_px) {
  const auto views = test::makeViews(truth, target, 25, seed, 45.0, 0.30, 0.25);
  const auto pixels = test::noisyPixels(views, noise_px, seed + 100);
  std::vector<CalibrationView> out;
  for (std::size_t v = 0; v < views.size(); ++v) out.push_back({"view " + std::to_string(v), views[v].ids, pixels[v]});
  return out;
}

struct Checked {
  CalibrationResult result;
  ModelCheck check;
};

Checked calibrateAndCheck(const Camera& truth, DistortionModel model, unsigned seed, int folds = 0) {
  const auto target = test::gridTarget(11, 8, 0.02);
  CalibrationOptions options;
  options.model = model;
  Checked out{calibrateCamera(target, noisyViews(truth, target, seed, 0.03), truth.width, truth.height, options), {}};
  ModelCheckOptions check_options;
  check_options.holdout_folds = folds;
  out.check = checkCalibrationModel(out.result, options, check_options);
  return out;
}

TEST(ModelCheck, ThinPrismLensIsInsufficientWithTheDefaultModelAndOpencv12Fits) {
  const Camera truth = thinPrismCamera();
  const Checked opencv5 = calibrateAndCheck(truth, DistortionModel::OpenCV5, 7);
  const auto sigma = opencv5.result.camera.sigmas();
  std::printf("thin prism, opencv5: cx %+.2f px (%.1f sigma), cy %+.2f px (%.1f sigma), rms %.4f px\n%s\n",
              opencv5.result.camera.cx() - truth.cx(), (opencv5.result.camera.cx() - truth.cx()) / sigma[2],
              opencv5.result.camera.cy() - truth.cy(), (opencv5.result.camera.cy() - truth.cy()) / sigma[3],
              opencv5.result.camera.rms_px, opencv5.check.verdictLine().c_str());
  EXPECT_FALSE(opencv5.check.adequate);
  EXPECT_NE(opencv5.check.verdictLine().find("--model opencv12"), std::string::npos) << opencv5.check.verdictLine();

  const Checked opencv12 = calibrateAndCheck(truth, DistortionModel::OpenCV12, 7);
  const Camera& camera = opencv12.result.camera;
  const auto sigma12 = camera.sigmas();
  std::printf("thin prism, opencv12: fx %+.3f fy %+.3f cx %+.3f cy %+.3f px (sigma %.3f %.3f %.3f %.3f)\n%s\n",
              camera.fx() - truth.fx(), camera.fy() - truth.fy(), camera.cx() - truth.cx(), camera.cy() - truth.cy(),
              sigma12[0], sigma12[1], sigma12[2], sigma12[3], opencv12.check.verdictLine().c_str());
  EXPECT_NEAR(camera.fx(), truth.fx(), 0.3);
  EXPECT_NEAR(camera.fy(), truth.fy(), 0.3);
  EXPECT_NEAR(camera.cx(), truth.cx(), 1.0);
  EXPECT_NEAR(camera.cy(), truth.cy(), 1.0);
  EXPECT_TRUE(opencv12.check.adequate) << opencv12.check.verdictLine();
}

TEST(ModelCheck, ALensTheModelRepresentsIsAdequate) {
  int false_alarms = 0;
  for (const unsigned seed : {11u, 12u, 13u}) {
    const Checked checked = calibrateAndCheck(test::referenceCamera(), DistortionModel::OpenCV5, seed);
    std::printf("seed %u: %s (structure p %.3g; nested p %.3g %.3g)\n", seed, checked.check.verdictLine().c_str(),
                checked.check.structure.corrected_p_value, checked.check.nested[0].p_value,
                checked.check.nested[1].p_value);
    false_alarms += checked.check.adequate ? 0 : 1;
  }
  EXPECT_LE(false_alarms, 1);
}

TEST(ModelCheck, HeldOutErrorMatchesItsPrediction) {
  const Checked checked = calibrateAndCheck(test::referenceCamera(), DistortionModel::OpenCV5, 21, 5);
  ASSERT_TRUE(checked.check.holdout.has_value());
  const HoldoutCheck& holdout = *checked.check.holdout;
  std::printf("held out: %d views, measured %.4f px, predicted %.4f px (noise alone %.4f), ratio %.3f, t %.2f\n",
              holdout.views, holdout.measured_rms_px, holdout.predicted_rms_px, holdout.noise_only_rms_px,
              holdout.ratio, holdout.t_statistic);
  for (std::size_t i = 0; i < 4; ++i)
    std::printf("  %s jackknife sigma / printed sigma %.2f\n", holdout.names[i].c_str(), holdout.jackknife_ratio[i]);
  EXPECT_EQ(holdout.views, checked.result.used_views);
  EXPECT_NEAR(holdout.ratio, 1.0, 0.1);
  EXPECT_GT(holdout.predicted_rms_px, holdout.noise_only_rms_px);
  EXPECT_FALSE(holdout.significant);
  EXPECT_TRUE(checked.check.adequate) << checked.check.verdictLine();
}

TEST(ModelCheck, ResidualBinsCoverEveryInlier) {
  const Checked checked = calibrateAndCheck(test::referenceCamera(), DistortionModel::OpenCV5, 31);
  const ResidualStructure& structure = checked.check.structure;
  ASSERT_EQ(structure.bins.size(), 32u);
  int points = 0;
  for (const auto& bin : structure.bins) points += bin.points;
  EXPECT_EQ(points, checked.result.used_points);
  EXPECT_GT(structure.tested_bins, 24);
}

}  // namespace
}  // namespace mire::calibration
