// Every lens model, one struct each (COLMAP-style): the templated projection against its
// reference implementation in OpenCV (cv::projectPoints, cv::fisheye::projectPoints) to
// 1e-10 px, unproject as its exact inverse, and calibration of exact synthetic views.
// Adding a model (lens_models.hpp, doc/calibration.md): add a struct here with camera()
// (a realistic camera of that model), reference() (OpenCV's projection of camera-frame
// points) and model (calibrate's DistortionModel), and append it to LensModelTypes.
#include "mire/calibration/calibrate.hpp"
#include "mire/calibration/camera_io.hpp"
#include "mire/calibration/camera_model.hpp"

#include "synthetic_calibration.hpp"

#include <ceres/jet.h>
#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>

namespace mire::calibration {
namespace {

std::vector<cv::Point2d> openCVProjection(const Camera& camera, const std::vector<cv::Point3d>& points) {
  const cv::Matx33d k(camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1);
  const std::vector<double> d(camera.params.begin() + kIntrinsicCount, camera.params.end());
  std::vector<cv::Point2d> pixels;
  cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, d, pixels);
  return pixels;
}

struct PinholeModel {
  static double maxDistortedRadius(const Camera&) { return 1e9; }
  static constexpr DistortionModel model = DistortionModel::Pinhole;
  static Camera camera() { return cameraFromOpenCV(640, 480, 520.3, 519.1, 321.4, 238.2, {}); }
  static std::vector<cv::Point2d> reference(const Camera& c, const std::vector<cv::Point3d>& p) {
    return openCVProjection(c, p);
  }
};

struct OpenCV5Model {
  static double maxDistortedRadius(const Camera&) { return 1e9; }
  static constexpr DistortionModel model = DistortionModel::OpenCV5;
  static Camera camera() { return test::referenceCamera(); }
  static std::vector<cv::Point2d> reference(const Camera& c, const std::vector<cv::Point3d>& p) {
    return openCVProjection(c, p);
  }
};

struct OpenCV8Model {
  static double maxDistortedRadius(const Camera&) { return 1e9; }
  static constexpr DistortionModel model = DistortionModel::OpenCV8;
  static Camera camera() {
    return cameraFromOpenCV(1024, 768, 817.2, 816.4, 511.5, 383.5,
                            {-0.30, 0.10, 4e-4, -3e-4, -0.015, 0.01, -0.005, 0.002});
  }
  static std::vector<cv::Point2d> reference(const Camera& c, const std::vector<cv::Point3d>& p) {
    return openCVProjection(c, p);
  }
};

// Rational + thin prism (CALIB_THIN_PRISM_MODEL): a decentred lens, s1..s4 of a cheap lens.
struct OpenCV12Model {
  static double maxDistortedRadius(const Camera&) { return 1e9; }
  static constexpr DistortionModel model = DistortionModel::OpenCV12;
  static Camera camera() {
    return cameraFromOpenCV(1024, 768, 817.2, 816.4, 517.6, 381.2,
                            {-0.30, 0.10, 4e-4, -3e-4, -0.015, 0.01, -0.005, 0.002, 0.004, -0.002, 0.003, 0.001});
  }
  static std::vector<cv::Point2d> reference(const Camera& c, const std::vector<cv::Point3d>& p) {
    return openCVProjection(c, p);
  }
};

// A wide-angle camera: 1024×768 with fx ≈ 300 (≈ 120° across the diagonal) and the k1..k4 of a
// real lens (Kalibr's equidistant example calibration, ../shared/datasets/external/camera-files).
struct FisheyeModel {
  // The image corners see beyond 90° (θd(90°) ≈ 1.57 < 640 px / 300 px): no ray (x, y, 1) there.
  static double maxDistortedRadius(const Camera& c) {
    const double theta = 88.0 * M_PI / 180.0, t2 = theta * theta;
    return theta * (1.0 + t2 * (c.params[4] + t2 * (c.params[5] + t2 * (c.params[6] + t2 * c.params[7]))));
  }
  static constexpr DistortionModel model = DistortionModel::Fisheye;
  static Camera camera() {
    Camera c;
    c.width = 1024;
    c.height = 768;
    c.lens = LensModel::Fisheye;
    c.params = {300.2,
                299.6,
                513.4,
                381.7,
                -0.005908650672531068,
                0.01587953759563821,
                -0.024196671184075886,
                0.015501252412920248};
    c.validate();
    return c;
  }
  static std::vector<cv::Point2d> reference(const Camera& c, const std::vector<cv::Point3d>& p) {
    const cv::Matx33d k(c.fx(), 0, c.cx(), 0, c.fy(), c.cy(), 0, 0, 1);
    const cv::Vec4d d(c.params[4], c.params[5], c.params[6], c.params[7]);
    std::vector<cv::Point2d> pixels;
    cv::fisheye::projectPoints(p, pixels, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), k, d);
    return pixels;
  }
};

template <typename Model>
class LensModels : public ::testing::Test {};
using LensModelTypes = ::testing::Types<PinholeModel, OpenCV5Model, OpenCV8Model, OpenCV12Model, FisheyeModel>;
TYPED_TEST_SUITE(LensModels, LensModelTypes);

// Camera-frame points whose pixels cover the image (and a margin), at random depths.
std::vector<Eigen::Vector3d> pointsOverTheImage(const Camera& camera, int step_px, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> depth(0.2, 5.0);
  std::vector<Eigen::Vector3d> points;
  for (int v = 0; v < camera.height; v += step_px)
    for (int u = 0; u < camera.width; u += step_px) {
      Eigen::Vector2d ray;
      if (camera.unproject({u + 0.37, v + 0.61}, &ray))
        points.push_back(depth(random) * Eigen::Vector3d(ray.x(), ray.y(), 1.0));
    }
  return points;
}

TYPED_TEST(LensModels, ProjectionMatchesOpenCV) {
  const Camera camera = TypeParam::camera();
  const std::vector<Eigen::Vector3d> points = pointsOverTheImage(camera, 16, 3);
  ASSERT_GT(points.size(), 900u);
  std::vector<cv::Point3d> cv_points;
  for (const auto& p : points) cv_points.emplace_back(p.x(), p.y(), p.z());
  cv_points.emplace_back(0.0, 0.0, 1.0);  // the optical axis (fisheye: r = 0)
  const std::vector<cv::Point2d> expected = TypeParam::reference(camera, cv_points);
  double worst = 0.0;
  for (std::size_t i = 0; i < cv_points.size(); ++i) {
    Eigen::Vector2d pixel;
    ASSERT_TRUE(camera.project({cv_points[i].x, cv_points[i].y, cv_points[i].z}, &pixel));
    worst = std::max(worst, (pixel - Eigen::Vector2d(expected[i].x, expected[i].y)).norm());
  }
  std::printf("%s: largest difference to OpenCV's projection %.2e px over %zu points\n", camera.modelName().c_str(),
              worst, cv_points.size());
  EXPECT_LT(worst, 1e-10);
}

TYPED_TEST(LensModels, UnprojectRoundTripsOverTheWholeImage) {
  const Camera camera = TypeParam::camera();
  double worst = 0.0;
  int failed = 0, total = 0;
  for (int v = 0; v <= camera.height; v += 8)
    for (int u = 0; u <= camera.width; u += 8) {
      const Eigen::Vector2d pixel(u - 0.5, v - 0.5);
      const bool representable =
          Eigen::Vector2d((pixel.x() - camera.cx()) / camera.fx(), (pixel.y() - camera.cy()) / camera.fy()).norm() <
          TypeParam::maxDistortedRadius(camera);
      total += representable ? 1 : 0;
      Eigen::Vector2d ray, back;
      if (!camera.unproject(pixel, &ray) || !camera.project({ray.x(), ray.y(), 1.0}, &back)) {
        failed += representable ? 1 : 0;  // beyond 88° off-axis (fisheye corners) false is right
        continue;
      }
      worst = std::max(worst, (back - pixel).norm());
    }
  std::printf("%s: unproject -> project round trip worst %.2e px, %d of %d pixels not invertible\n",
              camera.modelName().c_str(), worst, failed, total);
  EXPECT_EQ(failed, 0);
  EXPECT_LT(worst, 1e-9);
}

// Ceres autodiff through the model: derivatives finite on the axis and equal to central
// differences elsewhere.
TYPED_TEST(LensModels, AutodiffJacobianMatchesFiniteDifferences) {
  const Camera camera = TypeParam::camera();
  using Jet = ceres::Jet<double, 3>;
  for (const Eigen::Vector3d& point :
       {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0.3, -0.2, 1.1), Eigen::Vector3d(1.2, 0.8, 1.0)}) {
    std::vector<Jet> params(camera.params.begin(), camera.params.end());
    const Jet p[3] = {Jet(point.x(), 0), Jet(point.y(), 1), Jet(point.z(), 2)};
    Jet pixel[2];
    ASSERT_TRUE(projectPoint(params.data(), camera.lens, camera.distortionCount(), p, pixel));
    for (int axis = 0; axis < 3; ++axis) {
      const double h = 1e-6;
      Eigen::Vector2d plus, minus;
      ASSERT_TRUE(camera.project(point + h * Eigen::Vector3d::Unit(axis), &plus));
      ASSERT_TRUE(camera.project(point - h * Eigen::Vector3d::Unit(axis), &minus));
      const Eigen::Vector2d numeric = (plus - minus) / (2 * h);
      EXPECT_NEAR(pixel[0].v[axis], numeric.x(), 1e-4 * (1 + std::abs(numeric.x())))
          << point.transpose() << " d/d" << axis;
      EXPECT_NEAR(pixel[1].v[axis], numeric.y(), 1e-4 * (1 + std::abs(numeric.y())))
          << point.transpose() << " d/d" << axis;
    }
  }
}

// Exact synthetic views (a 10 × 7 grid of 30 mm) with 0.1 px noise: the model's parameters
// come back within 4σ, and the σ are those of a well-posed problem.
TYPED_TEST(LensModels, CalibrationRecoversTheCamera) {
  const Camera truth = TypeParam::camera();
  const auto target = test::gridTarget(10, 7, 0.03);
  const double distance = 100.0 / truth.fx();  // the board fills a similar part of every image
  const auto views = test::makeViews(truth, target, 15, 11, 40.0, distance, 0.5 * distance);
  ASSERT_GE(views.size(), 12u);
  const auto pixels = test::noisyPixels(views, 0.1, 5);
  std::vector<CalibrationView> calibration_views;
  for (std::size_t v = 0; v < views.size(); ++v)
    calibration_views.push_back({"view " + std::to_string(v), views[v].ids, pixels[v]});
  CalibrationOptions options;
  options.model = TypeParam::model;
  const CalibrationResult result = calibrateCamera(target, calibration_views, truth.width, truth.height, options);
  EXPECT_EQ(result.camera.lens, truth.lens);
  ASSERT_EQ(result.camera.params.size(), truth.params.size());
  const auto sigma = result.camera.sigmas();
  for (std::size_t i = 0; i < truth.params.size(); ++i) {
    const double error = result.camera.params[i] - truth.params[i];
    EXPECT_LT(std::abs(error), 4.0 * sigma[i]) << truth.parameterNames()[i];
    if (i < 4) {
      EXPECT_LT(std::abs(error), 0.3) << truth.parameterNames()[i];
    }
  }
  std::printf("%s: fx fy cx cy errors %.4f %.4f %.4f %.4f px (sigma %.4f %.4f %.4f %.4f), rms %.3f px\n",
              truth.modelName().c_str(), result.camera.params[0] - truth.params[0],
              result.camera.params[1] - truth.params[1], result.camera.params[2] - truth.params[2],
              result.camera.params[3] - truth.params[3], sigma[0], sigma[1], sigma[2], sigma[3], result.camera.rms_px);
}

// camera.yaml keeps the model (pinhole: 4 zero coefficients for OpenCV's readers).
TYPED_TEST(LensModels, CameraYamlRoundTripKeepsTheModel) {
  const Camera camera = TypeParam::camera();
  const auto path = std::filesystem::temp_directory_path() / ("mire-lens-" + camera.modelName() + ".yaml");
  std::ofstream(path) << cameraYamlString(camera);
  const Camera back = readCameraYaml(path);
  std::filesystem::remove(path);
  EXPECT_EQ(back.lens, camera.lens);
  EXPECT_EQ(back.modelName(), camera.modelName());
  EXPECT_EQ(back.params, camera.params);
}

TEST(LensModelNames, ParameterNamesAndValidation) {
  EXPECT_EQ(FisheyeModel::camera().parameterNames(),
            (std::vector<std::string>{"fx", "fy", "cx", "cy", "k1", "k2", "k3", "k4"}));
  EXPECT_EQ(PinholeModel::camera().parameterNames(), (std::vector<std::string>{"fx", "fy", "cx", "cy"}));
  EXPECT_EQ(FisheyeModel::camera().modelName(), "fisheye");
  EXPECT_EQ(PinholeModel::camera().modelName(), "pinhole");
  Camera wrong = FisheyeModel::camera();
  wrong.params.push_back(0.0);
  EXPECT_THROW(wrong.validate(), std::invalid_argument);
  EXPECT_EQ(parseDistortionModel("fisheye"), DistortionModel::Fisheye);
  EXPECT_EQ(parseDistortionModel("pinhole"), DistortionModel::Pinhole);
  EXPECT_EQ(parseDistortionModel("opencv12"), DistortionModel::OpenCV12);
  EXPECT_EQ(OpenCV12Model::camera().parameterNames().back(), "s4");
  EXPECT_EQ(OpenCV12Model::camera().modelName(), "opencv12");
  EXPECT_THROW(parseDistortionModel("kannala"), std::invalid_argument);
}

}  // namespace
}  // namespace mire::calibration
