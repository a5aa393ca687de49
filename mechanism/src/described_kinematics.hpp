#pragma once
// The templated IKM of a described mechanism (described.hpp; formulas in doc/mechanisms.md,
// "Described mechanisms"), usable with ceres::Jet. The leg kinds and where each leg's values sit
// in the geometric vector are runtime values: one instantiation serves every description.
#include <ceres/rotation.h>

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "mire/mechanism/described.hpp"

namespace mire::mechanism::detail {

// One leg: its kind and the index of each of its values in the geometric vector (−1: absent).
struct DescribedLeg {
  LegActuator actuator = LegActuator::Prismatic;
  int branch = 1;
  Eigen::Vector3d axis0 = Eigen::Vector3d::UnitZ();  // described axis u0; the tilts turn it
  Eigen::Vector3d e_a = Eigen::Vector3d::UnitX(), e_b = Eigen::Vector3d::UnitY();
  int base = -1, tilt = -1, arm = -1, rod = -1, platform = -1, offset = -1, gain = -1;
};

template <class T>
T dot3(const T* a, const T* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

template <class T>
void cross3(const T* a, const T* b, T* out) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

struct DescribedKinematics {
  std::vector<DescribedLeg> legs;
  bool full = false;  // 6-DoF platform (pose: t, rotation vector) or translation (t)

  int poseDof() const { return full ? 6 : 3; }

  template <class T>
  void poseToTransform(const T* pose, T* R, T* t) const {
    if (full) {
      ceres::AngleAxisToRotationMatrix(pose + 3, ceres::ColumnMajorAdapter3x3(R));
    } else {
      for (int k = 0; k < 9; ++k) R[k] = T(k % 4 == 0 ? 1 : 0);
    }
    for (int k = 0; k < 3; ++k) t[k] = pose[k];
  }

  // u = (u0 + ua·e_a + ub·e_b)/√(1 + ua² + ub²): regular for any tilt, exact unit norm.
  template <class T>
  static void axis(const DescribedLeg& leg, const T* g, T* u) {
    using std::sqrt;
    const T& a = g[leg.tilt];
    const T& b = g[leg.tilt + 1];
    const T scale = T(1) / sqrt(T(1) + a * a + b * b);
    for (int k = 0; k < 3; ++k) u[k] = (leg.axis0[k] + a * leg.e_a[k] + b * leg.e_b[k]) * scale;
  }

  // s_i from w = P_i − A_i; false where the leg cannot assemble (or sits exactly on a singularity).
  template <class T>
  static bool actuation(const DescribedLeg& leg, const T* g, const T* w, T* s) {
    using std::acos;
    using std::atan2;
    using std::sqrt;
    if (leg.actuator == LegActuator::Extensible) {
      const T norm2 = dot3(w, w);
      if (!(norm2 > T(0))) return false;
      *s = sqrt(norm2);
      return true;
    }
    T u[3];
    axis(leg, g, u);
    const T& l = g[leg.rod];
    if (leg.actuator == LegActuator::Prismatic) {
      const T along = dot3(w, u);
      const T radicand = l * l - dot3(w, w) + along * along;
      if (!(radicand > T(0))) return false;
      *s = along + T(leg.branch) * sqrt(radicand);
      return true;
    }
    // Revolute: a_∥ = (a·u)u, a_⊥ = a − a_∥, v = u × a_⊥, w' = w − a_∥.
    const T* a = g + leg.arm;
    const T a_along = dot3(a, u);
    T across[3], wp[3], v[3];
    for (int k = 0; k < 3; ++k) {
      across[k] = a[k] - a_along * u[k];
      wp[k] = w[k] - a_along * u[k];
    }
    cross3(u, across, v);
    const T alpha = T(2) * dot3(wp, across);
    const T beta = T(2) * dot3(wp, v);
    const T gamma = dot3(wp, wp) + dot3(across, across) - l * l;
    const T rho = sqrt(alpha * alpha + beta * beta);
    if (!(rho > T(0))) return false;
    const T ratio = gamma / rho;
    if (!(ratio < T(1) && ratio > T(-1))) return false;
    *s = atan2(beta, alpha) + T(leg.branch) * acos(ratio);
    return true;
  }

  // One leg's reading at bTe = (R column-major, t): q̄_i = (s_i − offset_i)/g_i; false where the
  // leg cannot assemble. `leg`'s indices point into `g` (the geometric vector, or one leg's
  // values alone: described_joint_cost.cpp).
  template <class T>
  static bool legJoint(const DescribedLeg& leg, const T* g, const T* R, const T* t, T* joint) {
    const T* A = g + leg.base;
    const T* p = g + leg.platform;
    T w[3];
    for (int k = 0; k < 3; ++k) w[k] = t[k] + R[k] * p[0] + R[3 + k] * p[1] + R[6 + k] * p[2] - A[k];
    T s;
    if (!actuation(leg, g, w, &s)) return false;
    *joint = s - g[leg.offset];
    if (leg.gain >= 0) *joint /= g[leg.gain];
    return true;
  }

  // IKM at bTe = (R column-major, t). Returns the bit mask of the legs that cannot assemble
  // (their q̄_i set to 0). A translation platform never turns (R = I, as the built-in Delta): a
  // rotation in bTe, such as X = bTc·cTm·mTe's with the target's rotation on the plate where the
  // initialisation put it, is not part of its pose and must not move its joints.
  template <class T>
  int inverseKinematics(const T* g, const T* R, const T* t, T* joints) const {
    T identity[9];
    if (!full) {
      for (int k = 0; k < 9; ++k) identity[k] = T(k % 4 == 0 ? 1 : 0);
      R = identity;
    }
    int mask = 0;
    for (std::size_t i = 0; i < legs.size(); ++i) {
      if (legJoint(legs[i], g, R, t, &joints[i])) continue;
      mask |= 1 << i;
      joints[i] = T(0);
    }
    return mask;
  }
};

}  // namespace mire::mechanism::detail

namespace mire::mechanism::detail {

// The layout of describedParameters(): each leg's values in file order (described_model.cpp).
DescribedKinematics describedKinematics(const MechanismDescription& description);

// Without `home`: a pose where every leg assembles, searched along z_B from the legs'
// reading-zero points at fractions of their mean length, above them first for a full platform,
// below first for a translation platform (described_model.cpp).
PoseVector describedDefaultHome(const MechanismDescription& description);

}  // namespace mire::mechanism::detail
