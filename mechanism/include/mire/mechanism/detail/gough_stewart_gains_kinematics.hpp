#pragma once
// Templated IKM of model `gough-stewart-gains` for MechanismAdapter (gough_stewart_gains.hpp):
// the Gough–Stewart legs of parallel_kinematics.hpp read through per-leg scales,
// q̄_i = (ρ_i − ρ0_i)/s_i, s_i at g[42 + i].
#include <string>

#include "mire/mechanism/detail/parallel_kinematics.hpp"

namespace mire::mechanism {

struct GoughStewartGainsKinematics : GoughStewartKinematics {
  static constexpr int kGeometric = 48;
  static constexpr int kScale = 42;  // index of s1

  std::string name() const { return "gough-stewart-gains"; }
  bool inStroke(const double* g, int leg, double q) const {
    const double rho = g[36 + leg] + g[kScale + leg] * q;
    return rho >= leg_min && rho <= leg_max;
  }
  template <class T>
  int inverseKinematics(const T* g, const T* R, const T* t, T* joints) const {
    GoughStewartKinematics::inverseKinematics(g, R, t, joints);  // ρ_i − ρ0_i
    for (int i = 0; i < 6; ++i) joints[i] /= g[kScale + i];
    return 0;
  }
};

}  // namespace mire::mechanism
