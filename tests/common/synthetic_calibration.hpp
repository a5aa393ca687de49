#pragma once
// Synthetic calibration scenes for tests and benchmarks: a reference short-focal camera
// (paper §5, doc/measurement.md: 1024×768, 3.8 mm lens), a chessboard-like grid, well-spread views
// (target centre on a grid over the image, tilts up to ±40°), exact projections + Gaussian
// pixel noise. Only points that land inside the image are kept (partial views, as in reality).
#include "mire/calibration/camera_model.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <vector>

namespace mire::test {

using PoseVector = Eigen::Matrix<double, 6, 1>;  // angle-axis, t (cTm)

inline calibration::Camera referenceCamera() {
  return calibration::cameraFromOpenCV(1024, 768, 817.2, 816.4, 511.5, 383.5, {-0.30, 0.10, 4e-4, -3e-4, -0.015});
}

// cols × rows grid, `spacing` apart, z = 0; optionally bowed: a paraboloid whose corners are at
// z = 0 and whose centre is at z = sag (out of plane, towards +z).
inline std::vector<Eigen::Vector3d> gridTarget(int cols, int rows, double spacing, double sag = 0.0) {
  std::vector<Eigen::Vector3d> points;
  const double xc = 0.5 * (cols - 1) * spacing, yc = 0.5 * (rows - 1) * spacing;
  const double corner2 = xc * xc + yc * yc;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double x = c * spacing, y = r * spacing;
      const double d2 = (x - xc) * (x - xc) + (y - yc) * (y - yc);
      points.emplace_back(x, y, sag * (1.0 - d2 / corner2));
    }
  return points;
}

struct SyntheticView {
  PoseVector pose;
  std::vector<int> ids;
  std::vector<Eigen::Vector2d> exact;  // noise-free pixels
};

// Deterministic views of `target` (true geometry) by `camera`.
inline std::vector<SyntheticView> makeViews(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& target,
                                            int view_count, unsigned seed, double max_tilt_deg = 40.0,
                                            double min_distance = 0.30, double distance_range = 0.25) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : target) centre += p;
  centre /= static_cast<double>(target.size());
  std::vector<SyntheticView> views;
  const int grid = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(view_count))));
  for (int attempt = 0; static_cast<int>(views.size()) < view_count && attempt < 100 * view_count; ++attempt) {
    const int cell = static_cast<int>(views.size());
    // Target centre aimed at cell (i, j) of a grid over the image, reaching its corners.
    const double u = camera.width * (0.08 + 0.84 * ((cell % grid) + unit(rng) * 0.5) / grid);
    const double v = camera.height * (0.08 + 0.84 * (((cell / grid) % grid) + unit(rng) * 0.5) / grid);
    const double distance = min_distance + distance_range * unit(rng);
    Eigen::Vector2d normalized;
    if (!camera.unproject({u, v}, &normalized)) continue;
    const Eigen::Vector3d aim = distance * Eigen::Vector3d(normalized.x(), normalized.y(), 1.0).normalized();
    const double tilt_x = (unit(rng) * 2.0 - 1.0) * max_tilt_deg * M_PI / 180.0;
    const double tilt_y = (unit(rng) * 2.0 - 1.0) * max_tilt_deg * M_PI / 180.0;
    const double roll = (unit(rng) * 2.0 - 1.0) * 30.0 * M_PI / 180.0;
    const Eigen::Matrix3d rotation =
        (Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(tilt_x, Eigen::Vector3d::UnitX()) *
         Eigen::AngleAxisd(tilt_y, Eigen::Vector3d::UnitY()))
            .toRotationMatrix();
    const Eigen::Vector3d translation = aim - rotation * centre;
    SyntheticView view;
    const Eigen::AngleAxisd angle_axis(rotation);
    view.pose << angle_axis.angle() * angle_axis.axis(), translation;
    for (std::size_t i = 0; i < target.size(); ++i) {
      const Eigen::Vector3d p = rotation * target[i] + translation;
      Eigen::Vector2d pixel;
      if (!camera.project(p, &pixel)) continue;
      if (pixel.x() < 2.0 || pixel.y() < 2.0 || pixel.x() > camera.width - 3.0 || pixel.y() > camera.height - 3.0)
        continue;
      // Stay where the distortion model is monotonic (projection is invertible).
      Eigen::Vector2d back;
      if (!camera.unproject(pixel, &back) || (back - p.head<2>() / p.z()).norm() > 1e-9) continue;
      view.ids.push_back(static_cast<int>(i));
      view.exact.push_back(pixel);
    }
    if (view.ids.size() < target.size() / 2) continue;
    views.push_back(std::move(view));
  }
  return views;
}

// Adds N(0, noise²) to each coordinate.
inline std::vector<std::vector<Eigen::Vector2d>> noisyPixels(const std::vector<SyntheticView>& views, double noise_px,
                                                             unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> gauss(0.0, noise_px);
  std::vector<std::vector<Eigen::Vector2d>> pixels;
  for (const auto& view : views) {
    pixels.emplace_back();
    for (const auto& p : view.exact) pixels.back().push_back(p + Eigen::Vector2d(gauss(rng), gauss(rng)));
  }
  return pixels;
}

}  // namespace mire::test
