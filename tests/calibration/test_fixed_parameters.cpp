// `--fix` (CalibrationOptions::fixed_parameters): a fixed coefficient keeps its value exactly,
// gets zero rows/columns in the covariance and no degree of freedom, and the free parameters
// equal those of a solve where the coefficient does not exist (opencv5 with k3 fixed = opencv4;
// opencv4 with k1 k2 p1 p2 fixed = pinhole).
#include "mire/calibration/calibrate.hpp"

#include "synthetic_calibration.hpp"

#include <gtest/gtest.h>

#include <cstdio>

namespace mire::calibration {
namespace {

struct Scene {
  std::vector<Eigen::Vector3d> target;
  std::vector<CalibrationView> views;
};

Scene sceneOf(const Camera& truth, unsigned seed) {
  Scene scene;
  scene.target = test::gridTarget(10, 7, 0.03);
  const auto views = test::makeViews(truth, scene.target, 12, seed);
  const auto pixels = test::noisyPixels(views, 0.15, seed + 1);
  for (std::size_t v = 0; v < views.size(); ++v)
    scene.views.push_back({"view " + std::to_string(v), views[v].ids, pixels[v]});
  return scene;
}

CalibrationResult solve(const Scene& scene, DistortionModel model, std::vector<std::string> fixed) {
  CalibrationOptions options;
  options.model = model;
  options.fixed_parameters = std::move(fixed);
  return calibrateCamera(scene.target, scene.views, 1024, 768, options);
}

void expectSameFreeParameters(const CalibrationResult& fixed, const CalibrationResult& reduced,
                              const std::vector<int>& fixed_to_reduced) {
  for (std::size_t i = 0; i < fixed_to_reduced.size(); ++i) {
    const int j = fixed_to_reduced[i];
    if (j < 0) continue;
    const double a = fixed.camera.params[i], b = reduced.camera.params[static_cast<std::size_t>(j)];
    EXPECT_NEAR(a, b, 1e-7 * (1.0 + std::abs(b))) << fixed.camera.parameterNames()[i];
    EXPECT_NEAR(fixed.camera.sigmas()[i], reduced.camera.sigmas()[static_cast<std::size_t>(j)],
                1e-5 * reduced.camera.sigmas()[static_cast<std::size_t>(j)])
        << fixed.camera.parameterNames()[i];
  }
  EXPECT_EQ(fixed.free_parameter_count, reduced.free_parameter_count);
  EXPECT_NEAR(fixed.sigma_px, reduced.sigma_px, 1e-9);
}

TEST(FixedParameters, FixedK3StaysZeroAndTheRestEqualsOpenCV4) {
  const Camera truth = cameraFromOpenCV(1024, 768, 817.2, 816.4, 511.5, 383.5, {-0.30, 0.10, 4e-4, -3e-4, 0.0});
  const Scene scene = sceneOf(truth, 21);
  const CalibrationResult free5 = solve(scene, DistortionModel::OpenCV5, {});
  const CalibrationResult fixed = solve(scene, DistortionModel::OpenCV5, {"k3"});
  const CalibrationResult opencv4 = solve(scene, DistortionModel::OpenCV4, {});
  EXPECT_EQ(fixed.camera.params[8], 0.0);  // exactly
  EXPECT_EQ(fixed.camera.sigmas()[8], 0.0);
  EXPECT_TRUE(fixed.camera.covariance.row(8).isZero(0.0));
  EXPECT_TRUE(fixed.camera.covariance.col(8).isZero(0.0));
  EXPECT_EQ(fixed.free_parameter_count, free5.free_parameter_count - 1);
  expectSameFreeParameters(fixed, opencv4, {0, 1, 2, 3, 4, 5, 6, 7, -1});
  std::printf("opencv5 + fix k3: fx %.6f (opencv4 %.6f, k3 free %.6f); free parameters %d vs %d\n",
              fixed.camera.params[0], opencv4.camera.params[0], free5.camera.params[0], fixed.free_parameter_count,
              free5.free_parameter_count);
}

TEST(FixedParameters, AllDistortionFixedIsThePinholeModel) {
  const Camera truth = cameraFromOpenCV(1024, 768, 817.2, 816.4, 511.5, 383.5, {});
  const Scene scene = sceneOf(truth, 31);
  const CalibrationResult fixed = solve(scene, DistortionModel::OpenCV4, {"k1", "k2", "p1", "p2"});
  const CalibrationResult pinhole = solve(scene, DistortionModel::Pinhole, {});
  for (int i = 4; i < 8; ++i) EXPECT_EQ(fixed.camera.params[static_cast<std::size_t>(i)], 0.0);
  expectSameFreeParameters(fixed, pinhole, {0, 1, 2, 3, -1, -1, -1, -1});
  EXPECT_EQ(pinhole.camera.modelName(), "pinhole");
  for (int i = 0; i < 4; ++i)
    EXPECT_LT(std::abs(pinhole.camera.params[static_cast<std::size_t>(i)] - truth.params[static_cast<std::size_t>(i)]),
              0.3);
}

TEST(FixedParameters, FixedPrincipalPointSitsAtTheImageCentre) {
  const Camera truth = cameraFromOpenCV(1024, 768, 817.2, 816.4, 511.5, 383.5, {-0.30, 0.10, 4e-4, -3e-4, -0.015});
  const Scene scene = sceneOf(truth, 41);
  const CalibrationResult fixed = solve(scene, DistortionModel::OpenCV5, {"cx", "cy", "p1", "p2"});
  EXPECT_EQ(fixed.camera.cx(), 511.5);
  EXPECT_EQ(fixed.camera.cy(), 383.5);
  EXPECT_EQ(fixed.camera.params[6], 0.0);
  EXPECT_EQ(fixed.camera.sigmas()[2], 0.0);
  EXPECT_GT(fixed.camera.sigmas()[0], 0.0);
}

TEST(FixedParameters, UnknownNameIsAnErrorNamingTheModel) {
  const Camera truth = cameraFromOpenCV(1024, 768, 817.2, 816.4, 511.5, 383.5, {});
  const Scene scene = sceneOf(truth, 51);
  try {
    solve(scene, DistortionModel::Fisheye, {"p1"});
    FAIL() << "no error";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("fisheye"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("p1"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace mire::calibration
