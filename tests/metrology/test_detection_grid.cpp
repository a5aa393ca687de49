// Chessboard and circle-grid detection on exact synthetic renders (synthetic_board.hpp):
// accuracy against the projected ground truth, frame conventions (doc/file-formats.md), re-refinement.
#include "mire/metrology/detection.hpp"
#include "mire/support/constants.hpp"

#include "synthetic_board.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace mire::metrology {
namespace {

using support::kPi;

struct Errors {
  double rms = 0.0;
  double max = 0.0;
};

// Pixel errors of `detection` against the view's projection of `truth_index(id)`.
template <typename IndexMap>
Errors errorsAgainstTruth(const Target& target, const test::SyntheticView& view, const Detection& detection,
                          IndexMap truth_index) {
  Errors errors;
  for (std::size_t i = 0; i < detection.size(); ++i) {
    const double e = (view.project(target.points()[truth_index(detection.ids[i])]) - detection.pixels[i]).norm();
    errors.rms += e * e;
    errors.max = std::max(errors.max, e);
  }
  errors.rms = std::sqrt(errors.rms / std::max<std::size_t>(1, detection.size()));
  return errors;
}
Errors errorsAgainstTruth(const Target& target, const test::SyntheticView& view, const Detection& detection) {
  return errorsAgainstTruth(target, view, detection, [](int id) { return id; });
}

Target chessboard(int cols, int rows) {
  TargetSpec spec;
  spec.type = TargetType::Chessboard;
  spec.cols = cols;
  spec.rows = rows;
  spec.square_size_m = 0.025;
  return Target(spec);
}

test::SyntheticView view(const Target& target, double distance, double tilt_x, double tilt_y, double roll, unsigned seed) {
  test::SyntheticView v;
  v.seed = seed;
  v.noise_sigma = 1.5;
  v.blur_sigma_px = 0.8;
  v.camera_T_target = test::lookAtTarget(target, distance, tilt_x, tilt_y, roll);
  return v;
}

TEST(DetectionGrid, ChessboardCornersAreAccurateAndInTheTargetFrame) {
  const Target target = chessboard(9, 6);
  ASSERT_FALSE(target.isRotationallyAmbiguous());
  // Roll π + 0.3: the board is upside down in the image; the colour rule must still put
  // the origin at the corner next to the dark outside square.
  const double rolls[] = {0.2, kPi + 0.3, -1.2};
  for (int k = 0; k < 3; ++k) {
    const test::SyntheticView v = view(target, 0.5, 0.35 * (k - 1), 0.25, rolls[k], 10 + k);
    const Detection detection = detectTarget(target, test::renderSynthetic(target, v));
    ASSERT_TRUE(detection.found) << detection.reason;
    ASSERT_EQ(detection.size(), target.points().size());
    const Errors errors = errorsAgainstTruth(target, v, detection);
    EXPECT_LT(errors.rms, 0.05) << "view " << k;
    EXPECT_LT(errors.max, 0.12) << "view " << k;
  }
}

TEST(DetectionGrid, AmbiguousChessboardFollowsTheDocumentedConvention) {
  const Target target = chessboard(8, 6);  // both even: looks the same turned by 180°
  ASSERT_TRUE(target.isRotationallyAmbiguous());
  const auto turned = [&](int id) {  // the feature at the same place after a 180° turn
    const int cols = target.spec().cols, rows = target.spec().rows;
    return (rows - 1 - id / cols) * cols + (cols - 1 - id % cols);
  };
  // Upright: the truth's x_M points right. Upside down: the detector picks the frame whose
  // x points right, i.e. the truth turned by 180°.
  const test::SyntheticView upright = view(target, 0.5, 0.2, -0.2, 0.3, 3);
  const Detection a = detectTarget(target, test::renderSynthetic(target, upright));
  ASSERT_TRUE(a.found) << a.reason;
  EXPECT_LT(errorsAgainstTruth(target, upright, a).rms, 0.05);
  const test::SyntheticView flipped = view(target, 0.5, 0.2, -0.2, kPi + 0.3, 4);
  const Detection b = detectTarget(target, test::renderSynthetic(target, flipped));
  ASSERT_TRUE(b.found) << b.reason;
  EXPECT_LT(errorsAgainstTruth(target, flipped, b, turned).rms, 0.05);
}

TEST(DetectionGrid, CircleGridsAreAccurateAndOrdered) {
  TargetSpec symmetric;
  symmetric.type = TargetType::Circles;
  symmetric.cols = 7;
  symmetric.rows = 5;
  symmetric.spacing_m = 0.03;
  symmetric.diameter_m = 0.015;
  TargetSpec asymmetric;
  asymmetric.type = TargetType::AsymmetricCircles;
  asymmetric.cols = 4;
  asymmetric.rows = 11;  // odd: unambiguous, so upside down must still be right
  asymmetric.spacing_m = 0.02;
  asymmetric.diameter_m = 0.015;
  for (const TargetSpec& spec : {symmetric, asymmetric}) {
    const Target target(spec);
    const double roll = spec.type == TargetType::Circles ? 0.4 : kPi - 0.4;
    const test::SyntheticView v = view(target, 0.45, 0.3, -0.25, roll, 7);
    const Detection detection = detectTarget(target, test::renderSynthetic(target, v));
    ASSERT_TRUE(detection.found) << targetTypeName(spec.type) << ": " << detection.reason;
    ASSERT_EQ(detection.size(), target.points().size());
    const Errors errors = errorsAgainstTruth(target, v, detection);
    // Includes the perspective offset between an ellipse's centre and the disc's projected
    // centre (≈ 0.05 px here), which no detector removes.
    EXPECT_LT(errors.rms, 0.08) << targetTypeName(spec.type);
    EXPECT_LT(errors.max, 0.15) << targetTypeName(spec.type);
  }
}

TEST(DetectionGrid, RefinementReusesAnInitialDetectionInAnotherImage) {
  const Target target = chessboard(9, 6);
  test::SyntheticView v = view(target, 0.55, 0.3, 0.2, 0.1, 21);
  const Detection initial = detectTarget(target, test::renderSynthetic(target, v));
  ASSERT_TRUE(initial.found);
  // Same pose, another noise draw, and an initial guess off by ~1.4 px.
  v.seed = 22;
  Detection shifted = initial;
  for (Eigen::Vector2d& p : shifted.pixels) p += Eigen::Vector2d(1.0, -1.0);
  const Detection refined = refineDetection(target, test::renderSynthetic(target, v), shifted);
  ASSERT_TRUE(refined.found) << refined.reason;
  EXPECT_EQ(refined.size(), target.points().size());
  EXPECT_LT(errorsAgainstTruth(target, v, refined).rms, 0.05);

  TargetSpec circles_spec;
  circles_spec.type = TargetType::Circles;
  circles_spec.cols = 7;
  circles_spec.rows = 5;
  circles_spec.spacing_m = 0.03;
  circles_spec.diameter_m = 0.015;
  const Target circles(circles_spec);
  test::SyntheticView cv_view = view(circles, 0.5, -0.2, 0.3, -0.3, 31);
  const Detection circles_initial = detectTarget(circles, test::renderSynthetic(circles, cv_view));
  ASSERT_TRUE(circles_initial.found);
  cv_view.seed = 32;
  Detection circles_shifted = circles_initial;
  for (Eigen::Vector2d& p : circles_shifted.pixels) p += Eigen::Vector2d(-1.0, 0.8);
  const Detection circles_refined = refineDetection(circles, test::renderSynthetic(circles, cv_view), circles_shifted);
  ASSERT_EQ(circles_refined.size(), circles.points().size()) << circles_refined.reason;
  EXPECT_LT(errorsAgainstTruth(circles, cv_view, circles_refined).rms, 0.08);
}

TEST(DetectionGrid, ReportsWhyNothingWasFound) {
  const Target target = chessboard(9, 6);
  const cv::Mat blank(480, 640, CV_8UC1, cv::Scalar(128));
  const Detection detection = detectTarget(target, blank);
  EXPECT_FALSE(detection.found);
  EXPECT_NE(detection.reason.find("not found"), std::string::npos) << detection.reason;
  EXPECT_THROW(detectTarget(target, cv::Mat()), std::invalid_argument);
}

}  // namespace
}  // namespace mire::metrology
