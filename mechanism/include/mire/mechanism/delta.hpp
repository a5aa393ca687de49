#pragma once
// The Delta robot (Clavel): three rotary actuators, parallelogram forearms, a travelling
// plate that keeps the base orientation. Pose X = (x, y, z) of the plate centre [m];
// joints q̄1..q̄3 [rad]. Frames and formulas: doc/mechanisms.md.
//
// Model `delta` (10 entries; r and alpha1 fixed by default -> 8 free):
//   R      radius of the circle through the arm pivots          [m]
//   r      radius of the circle through the plate joints        [m] (only R − r enters: fixed)
//   L      arm length, l forearm (parallelogram) length          [m]
//   alpha1..alpha3  direction of leg i's pivot about z_B          [rad] (alpha1 = 0 defines x_B)
//   q01..q03        joint offsets: arm angle φ_i = q̄_i + q0_i     [rad]
//   u_i = (cos α_i, sin α_i, 0), P_i = R·u_i, elbow B_i = P_i + L·(cos φ_i·u_i − sin φ_i·z_B),
//   plate joint A_i = X + r·u_i, constraint ‖A_i − B_i‖ = l (elbow-out branch).
//
// Model `delta-legs` (24 = 8 per leg, after Vischer & Clavel's per-leg model):
//   px<i> py<i> pz<i>  effective pivot of leg i in B: arm pivot minus the plate-joint
//                      offset (the plate never turns, so only their difference enters) [m]
//   psi<i> beta<i>     arm axis direction, arm V_i = Rz(ψ_i)·Rx(β_i)·Rz(φ_i)·(−1, 0, 0) [rad]
//   L<i> l<i>          arm and forearm lengths [m]
//   q0<i>              joint offset [rad]
//   The simple model is ψ_i = α_i + π, β_i = π/2, p_i = (R − r)·u_i.
#include <array>
#include <memory>

#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/parameter_set.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {

// Reference nominal geometry of the datasets (doc/mechanisms.md).
struct DeltaNominal {
  double R = 0.20;
  double r = 0.05;
  double L = 0.35;
  double l = 0.80;
  std::array<double, 3> alpha{0.0, 2.0 * support::kPi / 3.0, 4.0 * support::kPi / 3.0};
  std::array<double, 3> q0{0.0, 0.0, 0.0};
};

enum class DeltaModelKind { Simple, Legs };

ParameterSet deltaParameters(const DeltaNominal& nominal);
// Per-leg values equivalent to the simple model's (exact: same IKM everywhere).
ParameterSet deltaLegsFromDelta(const ParameterSet& delta);
std::unique_ptr<Mechanism> makeDeltaMechanism(DeltaModelKind kind, const DeltaNominal& nominal = {});

}  // namespace mire::mechanism
