#pragma once
// How far two poses of a target move its features in the image, shared by
// tests/metrology/test_pose_integrity.cpp and benchmarks/bench_integrity.cpp.
#include <cmath>

#include "mire/calibration/camera_model.hpp"
#include "mire/datasets/render.hpp"
#include "mire/metrology/target.hpp"

namespace mire::test {

// RMS image displacement of the target's features between two poses (px).
inline double displacementPx(const calibration::Camera& camera, const metrology::Target& target,
                             const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  const auto pa = datasets::projectFeatures(camera, target, a);
  const auto pb = datasets::projectFeatures(camera, target, b);
  double sum = 0.0;
  for (std::size_t i = 0; i < pa.pixels.size(); ++i) sum += (pa.pixels[i] - pb.pixels[i]).squaredNorm();
  return std::sqrt(sum / static_cast<double>(pa.pixels.size()));
}

}  // namespace mire::test
