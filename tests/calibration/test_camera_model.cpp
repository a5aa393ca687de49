// The templated projection against cv::projectPoints, and unproject as its exact inverse.
#include "mire/calibration/camera_model.hpp"

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include <Eigen/Geometry>

#include <random>

namespace mire::calibration {
namespace {

// The reference camera (paper §5 / datasets/specs/reference_camera.yaml) with `count`
// coefficients; the higher-order ones small but non-zero so that every term is exercised.
Camera referenceCamera(int count) {
  std::vector<double> distortion = {-0.3, 0.1, 1e-3, -1e-3, -0.02, 0.01, -0.005, 0.002, 1e-3, -5e-4, 8e-4, -3e-4};
  distortion.resize(count);
  return cameraFromOpenCV(1024, 768, 817.2, 816.5, 512.3, 383.7, distortion);
}

TEST(CameraModel, ProjectionMatchesOpenCVForEveryCoefficientCount) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (const int count : {4, 5, 8, 12}) {
    const Camera camera = referenceCamera(count);
    double worst = 0.0;
    for (int view = 0; view < 20; ++view) {
      // A random pose, and points in front of the camera within the image's field.
      const Eigen::Vector3d axis = Eigen::Vector3d(uniform(random), uniform(random), uniform(random)).normalized();
      const Eigen::Matrix3d rotation = Eigen::AngleAxisd(3.0 * uniform(random), axis).toRotationMatrix();
      const Eigen::Vector3d translation(0.2 * uniform(random), 0.2 * uniform(random), 0.3 * uniform(random));
      std::vector<cv::Point3d> object;
      std::vector<Eigen::Vector3d> in_camera;
      for (int i = 0; i < 50; ++i) {
        const double z = 0.3 + 0.7 * (uniform(random) + 1.0);
        const Eigen::Vector3d pc(0.6 * z * uniform(random), 0.45 * z * uniform(random), z);
        const Eigen::Vector3d po = rotation.transpose() * (pc - translation);
        object.emplace_back(po.x(), po.y(), po.z());
        in_camera.push_back(pc);
      }
      cv::Mat rvec, tvec = (cv::Mat_<double>(3, 1) << translation.x(), translation.y(), translation.z());
      cv::Mat r(3, 3, CV_64F);
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) r.at<double>(a, b) = rotation(a, b);
      cv::Rodrigues(r, rvec);
      const cv::Matx33d k(camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1);
      const std::vector<double> d(camera.params.begin() + kIntrinsicCount, camera.params.end());
      std::vector<cv::Point2d> expected;
      cv::projectPoints(object, rvec, tvec, k, d, expected);
      for (std::size_t i = 0; i < object.size(); ++i) {
        Eigen::Vector2d pixel;
        ASSERT_TRUE(camera.project(in_camera[i], &pixel));
        worst = std::max(worst, (pixel - Eigen::Vector2d(expected[i].x, expected[i].y)).norm());
      }
    }
    EXPECT_LT(worst, 1e-9) << count << " coefficients";
    std::cout << count << " coefficients: largest difference to cv::projectPoints " << worst << " px\n";
  }
  Eigen::Vector2d unused;
  EXPECT_FALSE(referenceCamera(5).project(Eigen::Vector3d(0.1, 0.1, -1.0), &unused));
  EXPECT_FALSE(referenceCamera(5).project(Eigen::Vector3d(0.1, 0.1, 0.0), &unused));
}

TEST(CameraModel, UnprojectInvertsProjectionOverTheWholeImage) {
  for (const int count : {5, 8, 12}) {
    const Camera camera = referenceCamera(count);
    double worst = 0.0;
    int points = 0;
    // Every 4 px over the whole image, edges of the outer pixels included.
    for (double v = -0.5; v <= camera.height - 0.5; v += 4.0) {
      for (double u = -0.5; u <= camera.width - 0.5; u += 4.0) {
        const Eigen::Vector2d pixel(u, v);
        Eigen::Vector2d ray;
        ASSERT_TRUE(camera.unproject(pixel, &ray)) << u << ", " << v;
        Eigen::Vector2d back;
        ASSERT_TRUE(camera.project(Eigen::Vector3d(ray.x(), ray.y(), 1.0), &back));
        worst = std::max(worst, (back - pixel).norm());
        ++points;
      }
    }
    EXPECT_LT(worst, 1e-9) << count << " coefficients";
    std::cout << count << " coefficients: project(unproject(p)) - p <= " << worst << " px over " << points << " pixels\n";
  }
}

}  // namespace
}  // namespace mire::calibration
