#pragma once
// The Gough–Stewart platform: six prismatic legs, full 6-DoF effector. Pose
// X = (x, y, z, rx, ry, rz): bTe translation [m] and rotation vector [rad]; joints q̄1..q̄6 [m].
// Leg i joins base joint b_i (in B) to platform joint p_i (in E): ρ_i = ‖t + R·p_i − b_i‖,
// q̄_i = ρ_i − ρ0_i.
// Model `gough-stewart` (42): bx1 by1 bz1 … bx6 by6 bz6, px1 py1 pz1 … px6 py6 pz6,
// rho01 … rho06 (all free; the 12 frame gauge directions are found by the analysis).
#include <array>
#include <memory>

#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/parameter_set.hpp"

namespace mire::mechanism {

// Nominal (doc/mechanisms.md): base joints on a 0.30 m circle, platform joints on a
// 0.15 m circle, home 0.40 m above the base, level, where every encoder reads 0.05 m.
struct GoughStewartNominal {
  double base_radius = 0.30;
  double platform_radius = 0.15;
  std::array<double, 6> base_angles_deg{350, 10, 110, 130, 230, 250};
  std::array<double, 6> platform_angles_deg{310, 50, 70, 170, 190, 290};
  double home_height = 0.40;
  double home_reading = 0.05;
  // Leg-length stroke [m] (home legs are 0.451 m): about ±100 mm, wider than the
  // protocol's ±40 mm, ±30 mm in z, ±6° tilts. The IKM reports legs outside it (IkmResult).
  double leg_min = 0.35;
  double leg_max = 0.55;
};

ParameterSet goughStewartParameters(const GoughStewartNominal& nominal = {});
std::unique_ptr<Mechanism> makeGoughStewartMechanism(const GoughStewartNominal& nominal = {});

}  // namespace mire::mechanism
