// The C++ side of python/bench_project.py: projects 10⁶ camera-frame points through
// Camera::project (the reference camera, datasets/specs/reference_camera.yaml) and prints the
// best time of several repeats, so that the Python API's calling overhead can be measured
// against it in the same run.
#include "mire/calibration/camera_formats.hpp"

#include <Eigen/Core>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: mire_bench_project CAMERA.yaml [points] [repeats]\n");
    return 2;
  }
  const auto camera = mire::calibration::readCamera(argv[1]);
  const std::size_t count = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 1000000;
  const int repeats = argc > 3 ? std::atoi(argv[3]) : 7;
  // The same field as the Python side: x/z in ±0.55, y/z in ±0.4, z in [0.3, 2] m.
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> ux(-0.55, 0.55), uy(-0.4, 0.4), uz(0.3, 2.0);
  std::vector<Eigen::Vector3d> points(count);
  for (auto& p : points) {
    const double z = uz(rng);
    p = Eigen::Vector3d(ux(rng) * z, uy(rng) * z, z);
  }
  double best = 1e300, checksum = 0.0;
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    std::vector<Eigen::Vector2d> pixels(count);  // the output is allocated per call, as in Python
    for (std::size_t i = 0; i < count; ++i) camera.project(points[i], &pixels[i]);
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    checksum += pixels[count / 2].x();
  }
  std::printf("%zu points: best of %d: %.6f s (checksum %.3f)\n", count, repeats, best, checksum);
  return 0;
}
