// Rods in the renderer (render.hpp, doc/simulation.md "Legs as rods"): their silhouettes where
// the cylinder's apparent contours project, occlusion with the target, and the target alone
// rendered exactly as without rods.
#include "mire/calibration/camera_io.hpp"
#include "mire/datasets/render.hpp"

#include "test_support.hpp"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <vector>

namespace {

using mire::calibration::Camera;
using mire::datasets::Renderer;
using mire::datasets::RenderOptions;
using mire::datasets::Rod;
using mire::metrology::Target;

// datasets/specs/reference_camera.yaml (paper §5): its distortion bends the contours.
Camera referenceCamera() {
  return mire::calibration::cameraFromOpenCV(1024, 768, 817.2043010752688, 817.2043010752688, 511.5, 383.5,
                                             {-0.30, 0.10, 4.0e-4, -3.0e-4, -0.015});
}

Target board() {
  mire::metrology::TargetSpec spec;
  spec.cols = 10;
  spec.rows = 7;
  spec.square_size_m = 0.03;
  return Target(spec);
}

Eigen::Isometry3d at(const Eigen::Vector3d& translation) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = translation;
  return pose;
}

// The two apparent contours of a rod seen from the camera centre O: the lines where the planes
// through O tangent to the cylinder touch it, a + r·(cos φ·ŵ ± sin φ·v̂) + t·u with ŵ the unit
// vector from the axis to O (⟂ u), v̂ = u × ŵ and cos φ = r / |w|.
std::vector<std::vector<Eigen::Vector2d>> projectedContours(const Camera& camera, const Rod& rod, double t_low,
                                                            double t_high) {
  const Eigen::Vector3d u = (rod.to - rod.from).normalized();
  const double length = (rod.to - rod.from).norm();
  const Eigen::Vector3d w = -rod.from + rod.from.dot(u) * u;
  const Eigen::Vector3d w_hat = w.normalized(), v_hat = u.cross(w_hat);
  const double cosine = rod.radius_m / w.norm(), sine = std::sqrt(1.0 - cosine * cosine);
  std::vector<std::vector<Eigen::Vector2d>> contours(2);
  for (int side = 0; side < 2; ++side) {
    const Eigen::Vector3d offset = rod.radius_m * (cosine * w_hat + (side ? sine : -sine) * v_hat);
    for (int k = 0; k <= 4000; ++k) {
      const double t = length * (t_low + (t_high - t_low) * k / 4000.0);
      Eigen::Vector2d pixel;
      EXPECT_TRUE(camera.project(rod.from + offset + t * u, &pixel));
      contours[static_cast<std::size_t>(side)].push_back(pixel);
    }
  }
  return contours;
}

// Where a projected contour crosses image row v (linear between its samples), if it does.
std::optional<double> crossing(const std::vector<Eigen::Vector2d>& contour, double v) {
  for (std::size_t k = 1; k < contour.size(); ++k) {
    const Eigen::Vector2d &a = contour[k - 1], &b = contour[k];
    if ((a.y() - v) * (b.y() - v) > 0.0 || a.y() == b.y()) continue;
    return a.x() + (v - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
  }
  return std::nullopt;
}

TEST(RenderRods, SilhouetteEdgesLieOnTheProjectedApparentContours) {
  // Sharp, noiseless, flat grey rod on the uniform background, target out of view: a pixel's
  // coverage is (background − I) / (background − rod). Along a row, with m a pixel wholly on
  // the rod, the left edge is at m + 0.5 − Σ_{i≤m} coverage and the right one at
  // m − 0.5 + Σ_{i≥m} coverage: exact for a straight edge across the pixel row (a row strip's
  // mean position is its centre's), the distorted contour being straight to 1e-4 px over 1 px.
  const Camera camera = referenceCamera();
  RenderOptions options;
  options.supersampling = 16;  // the coverage's sampling error ≈ 0.01 px per row
  options.rod_shading = 0.0;
  const Renderer renderer(camera, board(), options);
  const Rod rod{Eigen::Vector3d(-0.20, -0.16, 0.55), Eigen::Vector3d(0.05, 0.18, 0.75), 0.008};
  const auto rendering = renderer.render(at(Eigen::Vector3d(10.0, 0.0, 1.0)), {rod});
  const auto contours = projectedContours(camera, rod, 0.1, 0.9);  // away from the flat ends
  const double background = options.background_level, level = options.rod_level;
  const cv::Mat& image = rendering.radiance;
  double sum_squared = 0.0, worst = 0.0;
  int rows = 0;
  for (int v = 0; v < camera.height; ++v) {
    const auto a = crossing(contours[0], v), b = crossing(contours[1], v);
    if (!a || !b) continue;
    const double left = std::min(*a, *b), right = std::max(*a, *b);
    const int m = static_cast<int>(std::lround(0.5 * (left + right)));
    ASSERT_GT(right - left, 6.0);
    ASSERT_NEAR(image.at<float>(v, m), level, 1e-3) << "row " << v;
    double left_sum = 0.0, right_sum = 0.0;
    for (int i = m; i >= static_cast<int>(left) - 3; --i)
      left_sum += (background - image.at<float>(v, i)) / (background - level);
    for (int i = m; i <= static_cast<int>(right) + 3; ++i)
      right_sum += (background - image.at<float>(v, i)) / (background - level);
    for (const double error : {m + 0.5 - left_sum - left, m - 0.5 + right_sum - right}) {
      sum_squared += error * error;
      worst = std::max(worst, std::abs(error));
    }
    ++rows;
  }
  const double rms = std::sqrt(sum_squared / (2.0 * rows));
  std::cout << "[ render ] rod silhouettes against the projected contours over " << rows << " rows: RMS " << rms
            << " px, max " << worst << " px\n";
  EXPECT_GT(rows, 200);
  EXPECT_LT(rms, 0.02);
  EXPECT_LT(worst, 0.05);
}

TEST(RenderRods, NearestSurfaceWinsAndTheShadingDarkensTheSilhouette) {
  const Camera camera = referenceCamera();
  const RenderOptions options;
  const Renderer renderer(camera, board(), options);
  const Target target = board();
  const Eigen::Isometry3d pose = at(Eigen::Vector3d(-0.15, -0.1, 0.6));  // the board's centre on the axis
  // A horizontal rod across the image centre, in front of the board, then behind it.
  const auto levelOnAxis = [&](double depth) {
    const Rod rod{Eigen::Vector3d(-0.1, 0.0, depth), Eigen::Vector3d(0.1, 0.0, depth), 0.008};
    return renderer.render(pose, {rod}).radiance;
  };
  const cv::Mat in_front = levelOnAxis(0.5), behind = levelOnAxis(0.7), none = renderer.render(pose).radiance;
  const int u = 511, v = 383;  // the rod's axis projects on row 383.5
  EXPECT_NEAR(in_front.at<float>(v, u), options.rod_level, 0.5);
  EXPECT_EQ(behind.at<float>(v, u), none.at<float>(v, u));
  EXPECT_GT(std::abs(none.at<float>(v, u) - options.rod_level), 40.0);  // the print, not the rod
  // Just inside the silhouette (radius 8 mm at 0.5 m: 13.1 px) the surface grazes the ray.
  const float edge = in_front.at<float>(v + 13, u);
  EXPECT_LT(edge, options.rod_level * (1.0 - 0.5 * options.rod_shading));
  EXPECT_GT(edge, options.rod_level * (1.0 - options.rod_shading) - 1.0);
  EXPECT_LT(edge, options.background_level - 30.0);
}

TEST(RenderRods, WithoutRodsInViewTheTargetRendersByteForByteAsWithout) {
  const Camera camera = referenceCamera();
  RenderOptions options;
  options.blur_sigma_px = 0.6;
  options.cluttered_background = true;
  const Renderer renderer(camera, board(), options);
  const Eigen::Isometry3d pose = at(Eigen::Vector3d(-0.1, -0.05, 0.55));
  const Rod behind_camera{Eigen::Vector3d(0.0, 0.0, -0.5), Eigen::Vector3d(0.1, 0.0, -0.6), 0.01};
  const auto without = renderer.render(pose), with = renderer.render(pose, {behind_camera});
  EXPECT_EQ(cv::norm(without.radiance, with.radiance, cv::NORM_INF), 0.0);
  EXPECT_EQ(without.supersampled_pixels, with.supersampled_pixels);
  EXPECT_THROW(renderer.render(pose, {Rod{Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 0.001), 0.01}}),
               std::invalid_argument);
}

}  // namespace
