// Ray against finite cylinders (render_rods.hpp).
#include "render_rods.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace mire::datasets {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Bounds of x = X/Z over a box [low, high] in X and [z_low, z_high] in Z, z_low > 0.
std::pair<double, double> ratioBounds(double low, double high, double z_low, double z_high) {
  return {low / (low >= 0.0 ? z_high : z_low), high / (high >= 0.0 ? z_low : z_high)};
}

}  // namespace

RodScene::RodScene(const std::vector<Rod>& rods, const RenderOptions& options)
    : level_(options.rod_level), shading_(options.rod_shading) {
  for (const Rod& rod : rods) {
    if (!rod.from.allFinite() || !rod.to.allFinite() || !(rod.radius_m > 0.0) || !std::isfinite(rod.radius_m))
      throw std::invalid_argument("rod: its ends must be finite and its radius > 0");
    const Eigen::Vector3d span = rod.to - rod.from;
    if (!(span.norm() > rod.radius_m)) throw std::invalid_argument("rod: its ends are closer than its radius");
    Prepared p;
    p.from = rod.from;
    p.axis = span.normalized();
    p.length = span.norm();
    p.radius = rod.radius_m;
    const Eigen::Vector3d low = rod.from.cwiseMin(rod.to).array() - rod.radius_m;
    const Eigen::Vector3d high = rod.from.cwiseMax(rod.to).array() + rod.radius_m;
    p.bounds << -kInfinity, kInfinity, -kInfinity, kInfinity;
    if (low.z() > 0.0) {
      const auto x = ratioBounds(low.x(), high.x(), low.z(), high.z());
      const auto y = ratioBounds(low.y(), high.y(), low.z(), high.z());
      p.bounds << x.first, x.second, y.first, y.second;
    }
    rods_.push_back(p);
  }
}

// The ray s·d (s > 0, d = (x, y, 1), so s is the depth z) against the cylinder
// ‖(P − a) − ((P − a)·u)u‖ = r, 0 ≤ (P − a)·u ≤ length, then its flat ends: the side's first
// root is the entry unless it falls beyond an end, where the ray can only enter through an end.
bool RodScene::hit(const Prepared& rod, const Eigen::Vector3d& d, double* depth, Eigen::Vector3d* normal) const {
  const Eigen::Vector3d w = -rod.from;  // camera centre − a
  const double du = d.dot(rod.axis), wu = w.dot(rod.axis);
  const double a = d.squaredNorm() - du * du;
  const double b = d.dot(w) - du * wu;  // half of the quadratic's linear coefficient
  const double c = w.squaredNorm() - wu * wu - rod.radius * rod.radius;
  if (c <= 0.0) return false;  // the camera inside the (infinite) cylinder: not a scene we render
  const double discriminant = b * b - a * c;
  // A ray along the axis (a = 0) stays outside the cylinder (c > 0): it meets nothing.
  if (!(a > 0.0) || discriminant < 0.0) return false;
  const double s = (-b - std::sqrt(discriminant)) / a;
  if (!(s > 0.0)) return false;
  const double t = s * du + wu;
  if (t >= 0.0 && t <= rod.length) {
    *depth = s;
    *normal = (s * d - rod.from - t * rod.axis) / rod.radius;
    return true;
  }
  // Entering beyond an end: through that end's disc, if at all.
  const double end = t < 0.0 ? 0.0 : rod.length;
  if (du == 0.0) return false;
  const double s_end = (end - wu) / du;
  if (!(s_end > 0.0)) return false;
  const Eigen::Vector3d radial = s_end * d - rod.from - end * rod.axis;
  if (radial.squaredNorm() > rod.radius * rod.radius) return false;
  *depth = s_end;
  *normal = t < 0.0 ? Eigen::Vector3d(-rod.axis) : rod.axis;
  return true;
}

// Matte grey lit from the camera (a ring light): Lambert's cosine between the normal and the
// ray takes `shading` of the level off towards the silhouette, where the surface grazes the ray.
bool RodScene::nearest(const Eigen::Vector2d& ray, double* depth, float* level) const {
  const Eigen::Vector3d d(ray.x(), ray.y(), 1.0);
  double best = kInfinity;
  Eigen::Vector3d best_normal = Eigen::Vector3d::Zero();
  for (const Prepared& rod : rods_) {
    if (ray.x() < rod.bounds[0] || ray.x() > rod.bounds[1] || ray.y() < rod.bounds[2] || ray.y() > rod.bounds[3])
      continue;
    double s = 0.0;
    Eigen::Vector3d normal;
    if (hit(rod, d, &s, &normal) && s < best) best = s, best_normal = normal;
  }
  if (best == kInfinity) return false;
  const double cosine = std::max(0.0, -best_normal.dot(d) / d.norm());
  *depth = best;
  *level = static_cast<float>(level_ * (1.0 - shading_ * (1.0 - cosine)));
  return true;
}

}  // namespace mire::datasets
