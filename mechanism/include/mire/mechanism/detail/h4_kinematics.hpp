#pragma once
// Templated H4 IKMs (paper §3.2–3.3; doc/mechanism-models.md) for MechanismAdapter. Each returns a bit mask of the
// unreachable legs (bit i set when |T/ρ| > 1 on leg i), 0 when all legs are reachable.
// R is column-major (bTe rotation), t the effector origin, both in the model's base frame.
#include <Eigen/Geometry>

#include <cmath>
#include <string>
#include <vector>

#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/parameter_set.hpp"

namespace mire::mechanism {

namespace detail {

// Solves S·sinφ + C·cosφ = T for the elbow-out branch, φ = atan2(S, C) − acos(T/ρ)
// (doc/mechanism-models.md; the half-angle solution of eq. 21–22 written with atan2 for robustness).
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
    using std::cos;
    using std::sin;
    const T angle = pose[3] * T(amplification);
    const T c = cos(angle), s = sin(angle);
    R[0] = c;
    R[1] = s;
    R[2] = T(0);
    R[3] = -s;
    R[4] = c;
    R[5] = T(0);
    R[6] = T(0);
    R[7] = T(0);
    R[8] = T(1);
    t[0] = pose[0];
    t[1] = pose[1];
    t[2] = pose[2];
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
    using std::atan2;
    using std::cos;
    using std::sin;
    const T theta = atan2(R[1], R[0]) / T(amplification);
    const T ct = cos(theta), st = sin(theta);
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
    using std::atan2;
    using std::cos;
    using std::sin;
    const T theta = atan2(R[1], R[0]) / T(amplification);
    const T ct = cos(theta), st = sin(theta);
    const T& h = g[29];
    const T& d = g[30];
    int unreachable = 0;
    for (int i = 0; i < 4; ++i) {
      const T eps(static_cast<double>(kH4Epsilon[i]));
      const T sig(static_cast<double>(kH4Sigma[i]));
      T P[3] = {T(0), T(0), T(0)};
      if (i > 0)
        for (int k = 0; k < 3; ++k) P[k] = g[3 * (i - 1) + k];
      // W = A_i − P_i, A_i = X + ε_i h (cosθ, sinθ, 0) + σ_i d y_B (eq. 18).
      const T W[3] = {t[0] + eps * h * ct - P[0], t[1] + eps * h * st + sig * d - P[1], t[2] - P[2]};
      T phi;
      if (!detail::legAngleGeneralAxis(W, g[9 + i], g[13 + i], g[17 + i], g[21 + i], &phi)) {
        unreachable |= 1 << i;
        q[i] = T(0);
        continue;
      }
      q[i] = phi - g[25 + i];
    }
    return unreachable;
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
    int unreachable = 0;
    for (int i = 0; i < 4; ++i) {
      const T eps(static_cast<double>(kH4Epsilon[i]));
      // W = X + ε_i h·(R e_x) − P''_i (eq. 26 with the ε d x_H term folded into P''_i).
      const T W[3] = {t[0] + eps * h * R[0] - g[3 * i], t[1] + eps * h * R[1] - g[3 * i + 1],
                      t[2] + eps * h * R[2] - g[3 * i + 2]};
      T phi;
      if (!detail::legAngleGeneralAxis(W, g[12 + i], g[16 + i], g[28 + i], g[24 + i], &phi)) {
        unreachable |= 1 << i;
        q[i] = T(0);
        continue;
      }
      q[i] = phi - g[20 + i];
    }
    return unreachable;
  }
};

}  // namespace mire::mechanism
