#pragma once
// The model check on rendered calibration sets (doc/calibration.md, "Model check"): views like the
// demo's (the H4 chessboard 12 × 9 of 16 mm, blur 0.6 px, read noise 1.5 grey levels + shot noise)
// rendered through a given lens, detected by mire's detector (whose sub-pixel bias on rendered
// corners is a systematic error the check must not call a lens problem), calibrated and checked.
// Shared by the fast test (tests/metrology) and the false-alarm study (benchmarks/).
#include "mire/calibration/calibrate.hpp"
#include "mire/calibration/model_check.hpp"
#include "mire/datasets/feature_campaign.hpp"
#include "mire/datasets/render.hpp"
#include "mire/datasets/simulation.hpp"
#include "mire/metrology/detection.hpp"
#include "mire/metrology/target.hpp"

#include "chessboard_views.hpp"

#include <opencv2/core/utility.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace mire::test {

// The reference camera's lens, decentred: OpenCV's thin-prism terms of a cheap lens
// (s1..s4 = 0.004, −0.002, 0.003, 0.001), principal point off the image centre.
inline calibration::Camera thinPrismCamera() {
  return calibration::cameraFromOpenCV(1024, 768, 817.2, 817.2, 517.6, 381.2,
                                       {-0.30, 0.10, 4e-4, -3e-4, -0.015, 0.0, 0.0, 0.0, 0.004, -0.002, 0.003, 0.001});
}

struct RenderedCalibrationSet {
  metrology::Target target = chessboard(12, 9, 0.016);
  std::vector<calibration::CalibrationView> views;
};

// `views` views through `truth`, poses and noise drawn from `seed`; the views where the board is
// found.
inline RenderedCalibrationSet renderCalibrationSet(const calibration::Camera& truth, int views, std::uint64_t seed) {
  RenderedCalibrationSet set;
  datasets::RenderOptions render;
  render.blur_sigma_px = 0.6;
  const datasets::Renderer renderer(truth, set.target, render);
  datasets::CalibrationViewsSpec spec;
  spec.views = views;
  const std::vector<Eigen::Isometry3d> poses = datasets::generateCalibrationViews(truth, set.target, spec, seed);
  std::vector<calibration::CalibrationView> detected(poses.size());
  std::vector<char> found(poses.size(), 0);
  cv::parallel_for_(cv::Range(0, static_cast<int>(poses.size())), [&](const cv::Range& range) {
    for (int v = range.start; v < range.end; ++v) {
      const auto rendering = renderer.render(poses[static_cast<std::size_t>(v)]);
      const cv::Mat image =
          datasets::addNoise(rendering.radiance, {1.5, 20.0}, seed * 1000 + static_cast<std::uint64_t>(v));
      const auto detection = metrology::detectTarget(set.target, image);
      if (!detection.found) continue;
      detected[static_cast<std::size_t>(v)] = {"view " + std::to_string(v), detection.ids, detection.pixels};
      found[static_cast<std::size_t>(v)] = 1;
    }
  });
  for (std::size_t v = 0; v < poses.size(); ++v)
    if (found[v]) set.views.push_back(detected[v]);
  return set;
}

struct CheckedCalibration {
  calibration::CalibrationResult result;
  calibration::ModelCheck check;
};

inline CheckedCalibration calibrateAndCheck(const RenderedCalibrationSet& set, const calibration::Camera& truth,
                                            calibration::DistortionModel model, int holdout_folds = 0,
                                            const std::vector<std::string>& fixed = {}) {
  calibration::CalibrationOptions options;
  options.model = model;
  options.fixed_parameters = fixed;
  CheckedCalibration out{
      calibration::calibrateCamera(set.target.points(), set.views, truth.width, truth.height, options), {}};
  calibration::ModelCheckOptions check_options;
  check_options.holdout_folds = holdout_folds;
  out.check = calibration::checkCalibrationModel(out.result, options, check_options);
  return out;
}

}  // namespace mire::test
