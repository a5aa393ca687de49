#pragma once
// Templated H4 IKMs (paper §3.2–3.3; doc/mechanisms.md) for MechanismAdapter. Each returns a bit mask of the
// unreachable legs (bit i set when |T/ρ| > 1 on leg i), 0 when all legs are reachable.
// R is column-major (bTe rotation), t the effector origin, both in the model's base frame.
#include <Eigen/Geometry>

#include <cmath>
#include <string>
#include <vector>

#include "mire/mechanism/detail/matrix3.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/parameter_set.hpp"

namespace mire::mechanism {

namespace detail {

// Solves S·sinφ + C·cosφ = T for the elbow-out branch, φ = atan2(S, C) − acos(T/ρ)
// (doc/mechanisms.md; the half-angle solution of eq. 21–22 written with atan2 for robustness).
template <class T>
bool solveElbowOut(const T& S, const T& C, const T& rhs, T* phi) {
  using std::acos;
  using std::atan2;
  using std::sqrt;
  const T rho = sqrt(S * S + C * C);
  if (!(rho > T(0))) return false;
  const T ratio = rhs / rho;
  if (!(ratio <= T(1) && ratio >= T(-1))) return false;
  *phi = atan2(S, C) - acos(ratio);
  return true;
}

// One leg with a general pivot axis M = Rz(ψ)·Rx(β) (eq. 17): W = A − P, arm
// V = M·Rz(φ)·(−1,0,0), constraint ‖W − L·V‖ = l (eq. 16) ⇒ S sinφ + C cosφ = T (eq. 19)
// with W' = Mᵀ W, S = −W'_y, C = −W'_x, T = (‖W‖² + L² − l²)/(2L).
template <class T>
bool legAngleGeneralAxis(const T* W, const T& psi, const T& beta, const T& L, const T& l, T* phi) {
  using std::cos;
  using std::sin;
  const T cp = cos(psi), sp = sin(psi), cb = cos(beta), sb = sin(beta);
  const T wx = cp * W[0] + sp * W[1];
  const T wy = -sp * cb * W[0] + cp * cb * W[1] + sb * W[2];
  const T norm2 = W[0] * W[0] + W[1] * W[1] + W[2] * W[2];
  return solveElbowOut(-wy, -wx, (norm2 + L * L - l * l) / (T(2) * L), phi);
}

// Where a general-axis model keeps leg i's ψ, β, L, l and q0 in its geometric vector:
// at offset + stride·i.
struct LegLayout {
  int psi, beta, L, l, q0;
  int stride = 1;
};

// The joints of N legs with a general pivot axis from their W_i = A_i − P_i (eq. 16–19):
// q_i = φ_i − q0_i. Returns the mask of the unreachable legs (their q_i set to 0).
template <int N, class T>
int generalAxisJoints(const T (&W)[N][3], const T* g, const LegLayout& at, T* q) {
  int unreachable = 0;
  for (int i = 0; i < N; ++i) {
    const int k = at.stride * i;
    T phi;
    if (!legAngleGeneralAxis(W[i], g[at.psi + k], g[at.beta + k], g[at.L + k], g[at.l + k], &phi)) {
      unreachable |= 1 << i;
      q[i] = T(0);
      continue;
    }
    q[i] = phi - g[at.q0 + k];
  }
  return unreachable;
}

}  // namespace detail

// Pose convention shared by the H4 models: X = (x, y, z, θ), bTe = [Rz(k·θ), (x, y, z)].
struct H4PoseConvention {
  static constexpr MotionType kMotion = MotionType::Schoenflies;
  static constexpr Unit kJointUnit = Unit::Radian;
  double amplification = 1.0;

  std::vector<std::string> poseComponentNames() const { return {"x", "y", "z", "theta"}; }
  std::vector<Unit> poseComponentUnits() const { return {Unit::Metre, Unit::Metre, Unit::Metre, Unit::Radian}; }
  Eigen::VectorXd transformToPose(const Eigen::Isometry3d& bTe) const {
    Eigen::VectorXd pose(4);
    pose << bTe.translation(), std::atan2(bTe.linear()(1, 0), bTe.linear()(0, 0)) / amplification;
    return pose;
  }

  template <class T>
  void poseToTransform(const T* pose, T* R, T* t) const {
    detail::rotationZ(pose[3] * T(amplification), R);
    t[0] = pose[0];
    t[1] = pose[1];
    t[2] = pose[2];
  }

  // cos θ and sin θ of the effector rotation R = Rz(k·θ).
  template <class T>
  void heading(const T* R, T* ct, T* st) const {
    using std::atan2;
    using std::cos;
    using std::sin;
    const T theta = atan2(R[1], R[0]) / T(amplification);
    *ct = cos(theta);
    *st = sin(theta);
  }
};

// Model 12 (paper §3.2): parameters R L l h d alpha1..4 q01..4 (d fixed: no influence).
struct H4Model12Kinematics : H4PoseConvention {
  static constexpr int kGeometric = 13;
  static constexpr int kJoints = 4;
  static constexpr int kPoseDof = 4;

  std::string name() const { return "h4-model12"; }
  ParameterSet nominal(const H4Nominal& nominal) const;
  Eigen::VectorXd referencePose(const Eigen::VectorXd& geometric) const;

  template <class T>
  int inverseKinematics(const T* g, const T* R, const T* t, T* q) const {
    using std::cos;
    using std::sin;
    T ct, st;
    heading(R, &ct, &st);
    const T& Rr = g[0];
    const T& L = g[1];
    const T& l = g[2];
    const T& h = g[3];
    int unreachable = 0;
    for (int i = 0; i < 4; ++i) {
      const T ca = cos(g[5 + i]), sa = sin(g[5 + i]);
      const T eps(static_cast<double>(kH4Epsilon[i]));
      // w = A_i − P_i; the σ_i·d·y_B terms of A_i and P_i cancel (d has no influence).
      const T wx = t[0] + eps * h * (ct - T(1)) - Rr * ca;
      const T wy = t[1] + eps * h * st - Rr * sa;
      const T wz = t[2];
      const T a = wx * ca + wy * sa;
      const T b = -wz;
      const T c = (wx * wx + wy * wy + wz * wz + L * L - l * l) / (T(2) * L);
      T phi;
      if (!detail::solveElbowOut(b, a, c, &phi)) {
        unreachable |= 1 << i;
        q[i] = T(0);
        continue;
      }
      q[i] = phi - g[9 + i];
    }
    return unreachable;
  }
};

// Model 31 (paper §3.3): x2 y2 z2 x3 y3 z3 x4 y4 z4 psi1..4 beta1..4 L1..4 l1..4 q01..4 h d,
// pivot P1 at the origin of the base frame.
struct H4Model31Kinematics : H4PoseConvention {
  static constexpr int kGeometric = 31;
  static constexpr int kJoints = 4;
  static constexpr int kPoseDof = 4;

  std::string name() const { return "h4-model31"; }
  ParameterSet nominal(const H4Nominal& nominal) const;
  Eigen::VectorXd referencePose(const Eigen::VectorXd& geometric) const;

  template <class T>
  int inverseKinematics(const T* g, const T* R, const T* t, T* q) const {
    T ct, st;
    heading(R, &ct, &st);
    const T& h = g[29];
    const T& d = g[30];
    T W[4][3];
    for (int i = 0; i < 4; ++i) {
      const T eps(static_cast<double>(kH4Epsilon[i]));
      const T sig(static_cast<double>(kH4Sigma[i]));
      T P[3] = {T(0), T(0), T(0)};
      if (i > 0)
        for (int k = 0; k < 3; ++k) P[k] = g[3 * (i - 1) + k];
      // W = A_i − P_i, A_i = X + ε_i h (cosθ, sinθ, 0) + σ_i d y_B (eq. 18).
      W[i][0] = t[0] + eps * h * ct - P[0];
      W[i][1] = t[1] + eps * h * st + sig * d - P[1];
      W[i][2] = t[2] - P[2];
    }
    return detail::generalAxisJoints(W, g, {9, 13, 17, 21, 25}, q);
  }
};

// Model 31 in the camera frame (eq. 25–26): xpp1 ypp1 zpp1 .. xpp4 ypp4 zpp4, psi1..4,
// beta1..4, q01..4, l1..4, L1..4, h. The base frame is the axis-aligned camera frame; the
// nacelle direction is the effector x axis seen in that frame (k = 1).
struct H4Model31CameraKinematics : H4PoseConvention {
  static constexpr int kGeometric = 33;
  static constexpr int kJoints = 4;
  static constexpr int kPoseDof = 4;

  std::string name() const { return "h4-model31-camera"; }
  ParameterSet nominal(const H4Nominal& nominal) const;
  Eigen::VectorXd referencePose(const Eigen::VectorXd& geometric) const;

  template <class T>
  int inverseKinematics(const T* g, const T* R, const T* t, T* q) const {
    const T& h = g[32];
    T W[4][3];
    for (int i = 0; i < 4; ++i) {
      const T eps(static_cast<double>(kH4Epsilon[i]));
      // W = X + ε_i h·(R e_x) − P''_i (eq. 26 with the ε d x_H term folded into P''_i).
      for (int k = 0; k < 3; ++k) W[i][k] = t[k] + eps * h * R[k] - g[3 * i + k];
    }
    return detail::generalAxisJoints(W, g, {12, 16, 28, 24, 20}, q);
  }
};

}  // namespace mire::mechanism
