#pragma once
// The H4 parallel robot (paper §3; doc/mechanisms.md): 4 legs, effector pose X = (x, y, z, θ).
//
// Conventions (doc/mechanisms.md, "H4 model 12"): base frame B at the nacelle centre
// in its "H" configuration raised into the arm-pivot plane, z_B up (workspace z < 0); legs (ε, σ) = 1 (+,+),
// 2 (−,+), 3 (−,−), 4 (+,−); nacelle attachment A_i = (x,y,z) + ε_i·h·(cosθ, sinθ, 0)
// + σ_i·d·(0,1,0); effector rotation = k·θ about z_B (k = amplification, default 1);
// arm angle φ_i = q̄_i + q0_i; elbow-out assembly φ_i = atan2(S, C) − acos(T/ρ).
//
// Parameter names (YAML keys, SI units):
//  model 12 (13 entries, d fixed -> 12 free): R L l h d alpha1..alpha4 q01..q04
//  model 31 (31): x2 y2 z2 x3 y3 z3 x4 y4 z4 (pivots P2..P4, P1 is the origin),
//                 psi1..psi4 beta1..beta4 (leg axis Euler angles, eq. 17), L1..L4, l1..l4,
//                 q01..q04, h, d
//  model 31 in the camera frame (33 geometric; eq. 25–26): xpp1 ypp1 zpp1 .. xpp4 ypp4 zpp4
//                 (x''_i: pivot P_i combined with the constant σ_i·d·x_H term, in the
//                 axis-aligned camera frame), psi1..4, beta1..4, q01..4, l1..4, L1..4, h.
//                 With the CameraFrame external form (psi_ME x_ME y_ME, z_ME fixed) this is
//                 the paper's 36-parameter form. Requires amplification k = 1.
#include <Eigen/Core>

#include <array>
#include <memory>
#include <string>

#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/parameter_set.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {

// Reference nominal geometry used by the datasets (doc/mechanisms.md).
struct H4Nominal {
  double R = 0.22;
  double L = 0.30;
  double l = 0.70;
  double h = 0.075;
  double d = 0.10;
  std::array<double, 4> alpha{0.25 * support::kPi, 0.75 * support::kPi, 1.25 * support::kPi, 1.75 * support::kPi};
  std::array<double, 4> q0{0.0, 0.0, 0.0, 0.0};
  double amplification = 1.0;  // effector rotation = amplification · θ
};

// Leg sign pattern (doc/mechanisms.md).
constexpr std::array<int, 4> kH4Epsilon{+1, -1, -1, +1};
constexpr std::array<int, 4> kH4Sigma{+1, +1, -1, -1};

enum class H4ModelKind { Model12, Model31, Model31Camera };
std::string h4ModelName(H4ModelKind kind);  // "h4-model12", "h4-model31", "h4-model31-camera"

// Mechanisms. nominal() returns the model's parameters at the given nominal geometry
// (model 31: the exact model-12 equivalent, ψ_i = α_i + π, β_i = π/2, P_i relative to P1;
// model 31 camera: the same seen from the base frame itself, i.e. an identity alignment —
// use model31CameraFromModel12() for values in a real camera frame).
std::unique_ptr<Mechanism> makeH4Mechanism(H4ModelKind kind, const H4Nominal& nominal = {});

// Model 12 parameter values (in nominal() order) from an H4Nominal.
ParameterSet h4Model12Parameters(const H4Nominal& nominal);

// Model 31 values equivalent to model 12 (ψ_i = α_i + π, β_i = π/2, L_i = L, l_i = l,
// P_i = pivot_i(model 12) − pivot_1(model 12)). `origin_shift` receives pivot_1 in the
// model-12 base frame: X(model 31) = X(model 12) − origin_shift.
ParameterSet model31FromModel12(const ParameterSet& m12, Eigen::Vector3d* origin_shift = nullptr);

// Camera-frame model-31 values (eq. 25–26) from base-frame model-31 values and the
// transform aligned-camera <- model-31 base frame (B' = axis-aligned camera frame). Leg
// axes are re-expressed as Z-X-Z Euler angles; a third Euler angle folds into q0_i.
ParameterSet model31CameraFromModel31(const ParameterSet& m31, const Eigen::Isometry3d& alignedCamera_T_base);

// The templated IKMs (for autodiff); see detail/h4_kinematics.hpp.
struct H4Model12Kinematics;
struct H4Model31Kinematics;
struct H4Model31CameraKinematics;

}  // namespace mire::mechanism
