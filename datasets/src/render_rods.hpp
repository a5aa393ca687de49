#pragma once
// Rods (finite cylinders with flat ends) seen by the renderer (render.hpp, doc/simulation.md,
// "Legs as rods"): the nearest rod a ray (x, y, 1) meets, its depth and its grey level.
#include "mire/datasets/render.hpp"

#include <Eigen/Core>

#include <vector>

namespace mire::datasets {

class RodScene {
 public:
  // Throws std::invalid_argument for a rod with a non-finite end, ends closer than its radius,
  // or a radius not > 0.
  RodScene(const std::vector<Rod>& rods, const RenderOptions& options);

  bool empty() const { return rods_.empty(); }
  // Whether the ray (x, y, 1) meets a rod in front of the camera; if so the depth z (camera
  // frame, m) of the nearest hit and its grey level.
  bool nearest(const Eigen::Vector2d& ray, double* depth, float* level) const;

 private:
  struct Prepared {
    Eigen::Vector3d from, axis;  // axis: unit, from → to
    double length = 0.0, radius = 0.0;
    // Conservative bounds of the rod's rays (x_min, x_max, y_min, y_max), from its 3-D box;
    // unbounded when the box reaches behind the camera.
    Eigen::Vector4d bounds;
  };
  bool hit(const Prepared& rod, const Eigen::Vector3d& direction, double* depth, Eigen::Vector3d* normal) const;

  std::vector<Prepared> rods_;
  double level_ = 0.0, shading_ = 0.0;
};

}  // namespace mire::datasets
