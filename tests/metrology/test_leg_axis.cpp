// A leg's axis from its apparent contours (cylinder_axis.hpp, leg_contours.hpp, leg_axis.hpp,
// doc/legs.md "Measuring a leg"): the contours of a cylinder are tangent to it and give back its
// axis exactly; the Jacobian carries the contours' covariance to the δ spread; on small rendered
// images of rods (area-sampled, noisy) the averaged axis lies within its σ of the truth, with the
// prediction off by several pixels and another rod crossing.
#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/cylinder_axis.hpp"
#include "mire/metrology/leg_axis.hpp"
#include "mire/metrology/leg_contours.hpp"
#include "sample_statistics.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

namespace {

namespace metro = mire::metrology;
using mire::support::Line3d;

// A rod from (-0.1, 0.05, 0.6) to (0.12, -0.03, 0.75) (m), as a hexapod leg seen from 0.7 m.
Line3d testAxis() { return Line3d::throughPoints({-0.1, 0.05, 0.6}, {0.12, -0.03, 0.75}); }

// The distance between the ray through the origin along `ray` and `line`: |ray·m| / |ray × d|.
double rayDistance(const Eigen::Vector3d& ray, const Line3d& line) {
  return std::abs(ray.dot(line.moment)) / ray.cross(line.direction).norm();
}

TEST(CylinderAxis, ContoursAreTangentAndGiveTheAxisBack) {
  const double radius = 0.008;
  const Line3d axis = testAxis();
  const auto contours = metro::cylinderContours(axis, radius);
  for (const auto& contour : contours) {
    const Eigen::Vector2d normal(std::cos(contour.theta), std::sin(contour.theta));
    const Eigen::Vector2d along(-normal.y(), normal.x());
    for (const double s : {-0.3, 0.0, 0.2}) {
      // Rays through the contour touch the cylinder; a ray just inside it enters the cylinder.
      const Eigen::Vector2d on = contour.rho * normal + s * along;
      EXPECT_NEAR(rayDistance(on.homogeneous(), axis), radius, 1e-12);
      EXPECT_LT(rayDistance((on + 1e-3 * normal).homogeneous(), axis), radius);
    }
  }
  const Line3d back = metro::cylinderAxis(contours, radius);
  EXPECT_LT(mire::support::lineDifference(back, axis).norm(), 1e-12);
  EXPECT_LT((back.closestPointToOrigin() - axis.closestPointToOrigin()).norm(), 1e-12);
}

TEST(CylinderAxis, RefusesTheCentreInsideAndParallelContours) {
  EXPECT_THROW(metro::cylinderContours(Line3d::throughPoints({0.001, 0, 0}, {0.001, 0, 1}), 0.008),
               std::invalid_argument);
  const metro::ContourLine line{0.3, 0.1};
  EXPECT_THROW(metro::cylinderAxis({line, line}, 0.008), std::invalid_argument);
}

// The Jacobian against Monte Carlo: contours perturbed by a covariance of the size a fit gives
// (0.1 px at f = 1000 on ρ, 0.5 mrad on θ) scatter the axis as J·Σ·Jᵀ predicts.
TEST(CylinderAxis, JacobianPredictsTheAxisSpread) {
  const double radius = 0.008;
  const Line3d axis = testAxis();
  const auto contours = metro::cylinderContours(axis, radius);
  const Eigen::Matrix4d jacobian = metro::cylinderAxisJacobian(contours, radius);
  const Eigen::Vector4d sigma(5e-4, 1e-4, 5e-4, 1e-4);
  const Eigen::Matrix4d predicted = jacobian * sigma.cwiseAbs2().asDiagonal() * jacobian.transpose();
  std::mt19937 random(3);
  std::normal_distribution<double> normal;
  Eigen::Matrix4d spread = Eigen::Matrix4d::Zero();
  const int samples = 4000;
  for (int i = 0; i < samples; ++i) {
    auto noisy = contours;
    noisy[0].theta += sigma[0] * normal(random);
    noisy[0].rho += sigma[1] * normal(random);
    noisy[1].theta += sigma[2] * normal(random);
    noisy[1].rho += sigma[3] * normal(random);
    const Eigen::Vector4d delta = mire::support::lineDifference(metro::cylinderAxis(noisy, radius), axis);
    spread += delta * delta.transpose() / samples;
  }
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(std::sqrt(spread(k, k) / predicted(k, k)), 1.0, 0.06) << "component " << k;
}

// A small pinhole camera and an area-sampled image of rods (4 × 4 samples per pixel): shaded
// rods darker than the light background (190), the nearer rod in front.
mire::calibration::Camera smallCamera() {
  return mire::calibration::cameraFromOpenCV(320, 240, 400.0, 400.0, 161.3, 118.7, {});
}

struct Rod {
  Eigen::Vector3d from, to;
  double radius;
};

// Where the ray s·(x, y, 1) enters the rod's side: its depth s, and the level of a matte rod lit
// from the camera, `level`·(1 − 0.4·(1 − cos)) with cos between the surface normal and the ray (the
// silhouette is darker, as in the project's renderer); infinity when the ray misses the side.
double hitDepth(const Eigen::Vector3d& ray, const Rod& rod, double level, double* shaded) {
  const Eigen::Vector3d d = (rod.to - rod.from).normalized(), w = -rod.from;
  const double du = ray.dot(d), wu = w.dot(d);
  const double a = ray.squaredNorm() - du * du, b = ray.dot(w) - du * wu;
  const double c = w.squaredNorm() - wu * wu - rod.radius * rod.radius;
  const double discriminant = b * b - a * c;
  if (discriminant < 0.0) return HUGE_VAL;
  const double s = (-b - std::sqrt(discriminant)) / a, t = s * du + wu;
  if (t < 0.0 || t > (rod.to - rod.from).norm()) return HUGE_VAL;
  const Eigen::Vector3d normal = (s * ray - rod.from - t * d) / rod.radius;
  *shaded = level * (1.0 - 0.4 * (1.0 - std::max(0.0, -normal.dot(ray) / ray.norm())));
  return s;
}

cv::Mat renderRods(const mire::calibration::Camera& camera, const std::vector<Rod>& rods) {
  cv::Mat radiance(camera.height, camera.width, CV_32F);
  const int n = 4;
  for (int v = 0; v < camera.height; ++v)
    for (int u = 0; u < camera.width; ++u) {
      double sum = 0.0;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          const Eigen::Vector3d ray((u - 0.5 + (i + 0.5) / n - camera.cx()) / camera.fx(),
                                    (v - 0.5 + (j + 0.5) / n - camera.cy()) / camera.fy(), 1.0);
          double nearest = HUGE_VAL, level = 190.0, shaded = 0.0;
          for (std::size_t r = 0; r < rods.size(); ++r) {
            const double depth = hitDepth(ray, rods[r], r == 0 ? 80.0 : 120.0, &shaded);
            if (depth < nearest) {
              nearest = depth;
              level = shaded;
            }
          }
          sum += level;
        }
      radiance.at<float>(v, u) = static_cast<float>(sum / (n * n));
    }
  cv::GaussianBlur(radiance, radiance, cv::Size(0, 0), 0.6);  // a slightly soft lens, as the demo's
  return radiance;
}

cv::Mat noisy(const cv::Mat& radiance, double sigma, unsigned seed) {
  cv::Mat noise(radiance.size(), CV_32F);
  cv::theRNG().state = seed;
  cv::randn(noise, 0.0, sigma);
  cv::Mat image;
  cv::Mat(radiance + noise).convertTo(image, CV_8U);
  return image;
}

// The measured axis of rod 0 against the truth, whitened by its covariance, over `poses` rods
// moved about and 8 noisy images each; the prediction is the true rod shifted by 6 mm (~4 px).
std::vector<double> whitenedErrors(int poses, bool crossing) {
  const auto camera = smallCamera();
  std::vector<double> whitened;
  for (int p = 0; p < poses; ++p) {
    const Eigen::Vector3d shift(0.01 * std::sin(p), 0.008 * std::cos(1.7 * p), 0.02 * std::sin(0.5 * p));
    const Rod rod{Eigen::Vector3d(-0.12, 0.05, 0.6) + shift, Eigen::Vector3d(0.1, -0.04, 0.72) + shift, 0.008};
    std::vector<Rod> rods{rod};
    if (crossing) rods.push_back({{0.0, -0.1, 0.55}, {-0.02, 0.12, 0.6}, 0.008});
    const cv::Mat radiance = renderRods(camera, rods);
    std::vector<std::array<metro::ContourFit, 2>> fits;
    const Eigen::Vector3d offset(0.004, -0.004, 0.01);
    for (unsigned i = 0; i < 8; ++i) {
      const auto contours = metro::measureLegContours(metro::EdgeImage::of(noisy(radiance, 3.0, 100 * p + i)), camera,
                                                      rod.from + offset, rod.to + offset, rod.radius);
      EXPECT_TRUE(contours.ok) << contours.error;
      if (contours.ok) fits.push_back(contours.contours);
    }
    if (fits.empty()) continue;
    const metro::LegAxis leg = metro::averageLegAxis(fits, rod.radius);
    const Eigen::Vector4d error = mire::support::lineDifference(Line3d::throughPoints(rod.from, rod.to), leg.axis);
    const Eigen::Vector4d z = leg.covariance.llt().matrixL().solve(error);
    EXPECT_LT(z.norm(), 4.9) << "pose " << p << ": error " << error.transpose();  // χ²(4) at 0.999
    for (int k = 0; k < 4; ++k) whitened.push_back(z[k]);
  }
  return whitened;
}

TEST(LegContours, AveragedAxisLiesWithinItsSigma) {
  const std::vector<double> z = whitenedErrors(6, false);
  ASSERT_EQ(z.size(), 24u);
  const double spread = mire::test::sampleStandardDeviation(z);
  EXPECT_GT(spread, 0.5);
  EXPECT_LT(spread, 1.6);
}

TEST(LegContours, AnotherRodCrossingIsLeftOut) {
  const std::vector<double> z = whitenedErrors(3, true);
  ASSERT_EQ(z.size(), 12u);
}

TEST(LegContours, LegOutsideTheImageFailsWithAReason) {
  const auto camera = smallCamera();
  const metro::EdgeImage image = metro::EdgeImage::of(cv::Mat(240, 320, CV_8U, cv::Scalar(128)));
  const auto contours = metro::measureLegContours(image, camera, {2.0, 0.0, 0.6}, {2.2, 0.1, 0.7}, 0.008);
  EXPECT_FALSE(contours.ok);
  EXPECT_NE(contours.error.find("outside the image"), std::string::npos) << contours.error;
}

}  // namespace
