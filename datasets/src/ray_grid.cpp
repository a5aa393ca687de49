// Exact undistorted rays at the pixel corners, and their bilinear interpolation (render.hpp).
#include "mire/datasets/render.hpp"

#include <ceres/jet.h>
#include <opencv2/core/utility.hpp>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mire::datasets {
namespace {

// Newton on distort(x) = target (normalised coordinates), Jacobian by dual numbers through
// the same distortLens as projection (any lens model), so the inverse is exact to rounding.
bool undistortFrom(calibration::LensModel lens, const std::vector<ceres::Jet<double, 2>>& coefficients,
                   const Eigen::Vector2d& target, Eigen::Vector2d* x) {
  using Jet = ceres::Jet<double, 2>;
  const int count = static_cast<int>(coefficients.size());
  for (int iteration = 0; iteration < 60; ++iteration) {
    const Jet jx(x->x(), 0), jy(x->y(), 1);
    Jet xd, yd;
    calibration::distortLens(lens, coefficients.data(), count, jx, jy, &xd, &yd);
    const Eigen::Vector2d residual(xd.a - target.x(), yd.a - target.y());
    Eigen::Matrix2d jacobian;
    jacobian << xd.v[0], xd.v[1], yd.v[0], yd.v[1];
    const Eigen::Vector2d step = jacobian.inverse() * residual;
    if (!step.allFinite()) return false;
    *x -= step;
    if (step.norm() < 1e-15 * (1.0 + x->norm())) return true;
  }
  return false;
}

}  // namespace

RayGrid::RayGrid(const calibration::Camera& camera)
    : width_(camera.width), height_(camera.height), params_(camera.params), lens_(camera.lens) {
  camera.validate();
  rays_.resize(static_cast<std::size_t>(width_ + 1) * (height_ + 1));
  std::vector<ceres::Jet<double, 2>> coefficients;
  coefficients.reserve(static_cast<std::size_t>(camera.distortionCount()));
  for (int i = 0; i < camera.distortionCount(); ++i)
    coefficients.emplace_back(camera.params[calibration::kIntrinsicCount + static_cast<std::size_t>(i)]);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  cv::parallel_for_(cv::Range(0, height_ + 1), [&](const cv::Range& range) {
    for (int j = range.start; j < range.end; ++j) {
      const double y = (j - 0.5 - camera.cy()) / camera.fy();
      // Warm start from the row's previous corner: 2-3 Newton steps per corner.
      Eigen::Vector2d guess((-0.5 - camera.cx()) / camera.fx(), y);
      bool guess_valid = false;
      for (int i = 0; i <= width_; ++i) {
        const Eigen::Vector2d target((i - 0.5 - camera.cx()) / camera.fx(), y);
        Eigen::Vector2d x = guess_valid ? guess : target;
        bool ok = undistortFrom(lens_, coefficients, target, &x);
        if (!ok && guess_valid) {
          x = target;
          ok = undistortFrom(lens_, coefficients, target, &x);
        }
        guess_valid = ok;
        if (ok) guess = x;
        rays_[static_cast<std::size_t>(j) * (width_ + 1) + i] = ok ? x : Eigen::Vector2d(nan, nan);
      }
    }
  });
}

Eigen::Vector2d RayGrid::interpolate(double u, double v) const {
  const double fu = u + 0.5, fv = v + 0.5;
  const int i = std::clamp(static_cast<int>(std::floor(fu)), 0, width_ - 1);
  const int j = std::clamp(static_cast<int>(std::floor(fv)), 0, height_ - 1);
  const double a = fu - i, b = fv - j;
  return (1.0 - b) * ((1.0 - a) * corner(i, j) + a * corner(i + 1, j)) +
         b * ((1.0 - a) * corner(i, j + 1) + a * corner(i + 1, j + 1));
}

Eigen::Vector2d RayGrid::refine(const Eigen::Vector2d& guess, double u, double v) const {
  return guess - inverseJacobian(guess) * distortionResidual(guess, u, v);
}

Eigen::Matrix2d RayGrid::inverseJacobian(const Eigen::Vector2d& ray) const {
  using Jet = ceres::Jet<double, 2>;
  const int count = static_cast<int>(params_.size()) - calibration::kIntrinsicCount;
  Jet coefficients[12];
  for (int i = 0; i < count; ++i)
    coefficients[i] = Jet(params_[calibration::kIntrinsicCount + static_cast<std::size_t>(i)]);
  const Jet jx(ray.x(), 0), jy(ray.y(), 1);
  Jet xd, yd;
  calibration::distortLens(lens_, coefficients, count, jx, jy, &xd, &yd);
  Eigen::Matrix2d jacobian;
  jacobian << xd.v[0], xd.v[1], yd.v[0], yd.v[1];
  return jacobian.inverse();
}

Eigen::Vector2d RayGrid::distortionResidual(const Eigen::Vector2d& ray, double u, double v) const {
  const int count = static_cast<int>(params_.size()) - calibration::kIntrinsicCount;
  double xd = 0.0, yd = 0.0;
  calibration::distortLens(lens_, params_.data() + calibration::kIntrinsicCount, count, ray.x(), ray.y(), &xd, &yd);
  return {xd - (u - params_[2]) / params_[0], yd - (v - params_[3]) / params_[1]};
}

Eigen::Vector2d RayGrid::refine(const Eigen::Vector2d& guess, double u, double v,
                                const Eigen::Matrix2d& inverse_jacobian) const {
  // The Jacobian changes by ~1e-3 of itself across a pixel: each fixed-Jacobian step divides
  // the bilinear error (< 3.3e-4 px) by ~1e3, two steps reach the Newton step's < 1e-9 px.
  Eigen::Vector2d ray = guess - inverse_jacobian * distortionResidual(guess, u, v);
  return ray - inverse_jacobian * distortionResidual(ray, u, v);
}

double RayGrid::maxInterpolationErrorPx(const calibration::Camera& camera, int pixel_stride, int samples_per_side,
                                        bool refined) const {
  double worst = 0.0;
  const auto check = [&](int pixel_u, int pixel_v) {
    for (int sv = 0; sv < samples_per_side; ++sv) {
      for (int su = 0; su < samples_per_side; ++su) {
        const double u = pixel_u - 0.5 + (su + 0.5) / samples_per_side;
        const double v = pixel_v - 0.5 + (sv + 0.5) / samples_per_side;
        // Refined as the renderer does: one inverse Jacobian per pixel, at its centre.
        const Eigen::Vector2d ray =
            refined ? refine(interpolate(u, v), u, v, inverseJacobian(interpolate(pixel_u, pixel_v))) : interpolate(u, v);
        Eigen::Vector2d pixel;
        if (!ray.allFinite() || !camera.project(Eigen::Vector3d(ray.x(), ray.y(), 1.0), &pixel))
          return void(worst = std::numeric_limits<double>::infinity());
        worst = std::max(worst, (pixel - Eigen::Vector2d(u, v)).norm());
      }
    }
  };
  for (int v = 0; v < height_; v += pixel_stride)
    for (int u = 0; u < width_; u += pixel_stride) check(u, v);
  for (const int v : {0, height_ - 1})
    for (const int u : {0, width_ - 1}) check(u, v);
  return worst;
}

}  // namespace mire::datasets
