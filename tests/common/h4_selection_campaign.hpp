#pragma once
// The simulated H4 campaign of the model-selection test and study (doc/plan-and-select.md),
// shared by tests/mechanism/test_model_selection.cpp and benchmarks/bench_select.cpp.
#include <random>
#include <vector>

#include "mire/datasets/h4_true_robot.hpp"
#include "mire/mechanism/pose.hpp"

namespace mire::test {

// A true H4 with model-12 errors (1 mm / 0.5°) and, when `legs_differ`, arm and forearm
// lengths changed per leg by 1–3 mm (random sign); the 81 protocol poses measured with noise.
inline std::vector<mechanism::PoseObservation> h4SelectionCampaign(unsigned seed, bool legs_differ) {
  namespace ds = mire::datasets;
  const ds::H4ErrorSizes sizes = ds::H4ErrorSizes::withoutUnmodelledDefects();
  ds::H4TrueGeometry g = ds::geometryFromModel12(ds::drawModel12Values(mechanism::H4Nominal{}, sizes, seed));
  if (legs_differ) {
    std::mt19937 rng(seed + 77);
    std::uniform_real_distribution<double> size(1e-3, 3e-3);
    for (auto& leg : g.legs) {
      leg.arm_length += (rng() & 1U ? 1 : -1) * size(rng);
      leg.forearm_length += (rng() & 1U ? 1 : -1) * size(rng);
    }
  }
  const ds::H4TrueKinematics robot(g);
  const ds::H4MeasurementNoise noise;
  return ds::toObservations(ds::simulateMeasurements(robot, ds::protocolPoses(), noise, seed), noise);
}

}  // namespace mire::test
