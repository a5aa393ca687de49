#pragma once
// Calibration σ under systematic error (doc/calibration.md): calibration sets
// rendered like the demo's (reference camera, the H4 chessboard 12 × 9 of 16 mm, blur 0.6 px,
// read noise 1.5 grey levels + shot noise), detected by mire's detector, whose sub-pixel bias
// on rendered corners is the systematic error; each set calibrated once, and error/σ of every
// parameter recorded with the printed σ (view-cluster inflation) and with pixel noise alone.
// Shared by the fast test (tests/metrology) and the benchmark (benchmarks/).
#include "mire/calibration/calibrate.hpp"
#include "mire/datasets/feature_campaign.hpp"
#include "mire/datasets/render.hpp"
#include "mire/datasets/simulation.hpp"
#include "mire/metrology/detection.hpp"
#include "mire/metrology/target.hpp"

#include "chessboard_views.hpp"

#include <opencv2/core/utility.hpp>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace mire::test {

struct SigmaStudySet {
  std::vector<double> error;        // estimate − truth, per parameter
  std::vector<double> sigma;        // printed σ (inflated where the data show systematic error)
  std::vector<double> sigma_pixel;  // pixel-noise σ alone
  std::vector<double> inflation;
  int views = 0;
  double rms_px = 0.0;
};

inline metrology::Target demoTarget() { return chessboard(12, 9, 0.016); }

// One calibration set: `views` rendered views drawn with `seed` (poses and noise).
inline SigmaStudySet runSigmaStudySet(int views, std::uint64_t seed) {
  const calibration::Camera truth = datasets::referenceCamera();
  const metrology::Target target = demoTarget();
  datasets::RenderOptions render;
  render.blur_sigma_px = 0.6;
  const datasets::Renderer renderer(truth, target, render);
  datasets::CalibrationViewsSpec spec;
  spec.views = views;
  const std::vector<Eigen::Isometry3d> poses = datasets::generateCalibrationViews(truth, target, spec, seed);
  std::vector<calibration::CalibrationView> detected(poses.size());
  std::vector<char> found(poses.size(), 0);
  cv::parallel_for_(cv::Range(0, static_cast<int>(poses.size())), [&](const cv::Range& range) {
    for (int v = range.start; v < range.end; ++v) {
      const auto rendering = renderer.render(poses[static_cast<std::size_t>(v)]);
      const cv::Mat image =
          datasets::addNoise(rendering.radiance, {1.5, 20.0}, seed * 1000 + static_cast<std::uint64_t>(v));
      const auto detection = metrology::detectTarget(target, image);
      if (!detection.found) continue;
      detected[static_cast<std::size_t>(v)] = {"view " + std::to_string(v), detection.ids, detection.pixels};
      found[static_cast<std::size_t>(v)] = 1;
    }
  });
  std::vector<calibration::CalibrationView> calibration_views;
  for (std::size_t v = 0; v < poses.size(); ++v)
    if (found[v]) calibration_views.push_back(detected[v]);
  calibration::CalibrationOptions options;
  options.model = calibration::DistortionModel::OpenCV5;
  const auto result =
      calibration::calibrateCamera(target.points(), calibration_views, truth.width, truth.height, options);
  SigmaStudySet out;
  out.views = result.used_views;
  out.rms_px = result.camera.rms_px;
  out.sigma = result.camera.sigmas();
  out.inflation = result.sigma_inflation;
  for (std::size_t i = 0; i < truth.params.size(); ++i) {
    out.error.push_back(result.camera.params[i] - truth.params[i]);
    out.sigma_pixel.push_back(
        std::sqrt(result.covariance_pixel_noise(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i))));
  }
  return out;
}

// std(error/σ) over sets, per parameter (about 0, not the sample mean: a bias is an error).
inline std::vector<double> normalisedSpread(const std::vector<SigmaStudySet>& sets, bool pixel_noise_only) {
  std::vector<double> spread;
  if (sets.empty()) return spread;
  for (std::size_t i = 0; i < sets.front().error.size(); ++i) {
    double sum = 0.0;
    for (const auto& set : sets) {
      const double z = set.error[i] / (pixel_noise_only ? set.sigma_pixel[i] : set.sigma[i]);
      sum += z * z;
    }
    spread.push_back(std::sqrt(sum / static_cast<double>(sets.size())));
  }
  return spread;
}

}  // namespace mire::test
