#pragma once
// The simulated true robot of every mechanism of the table (registry.hpp): its true geometry in
// its family's truth model and the defects none of its models represent, one kind per family
// (SimulatedDefects; doc/studies/2026-11-23-mechanisms-sigma-and-defects.md, "Unmodelled defects"):
//  - H4: per-leg geometry, tilted arm axes and imperfect parallelograms that tilt the nacelle
//    (h4_true_robot.hpp, doc/mechanisms.md "The simulated true H4"); its geometry is the
//    model-12 part of that robot.
//  - Delta: per-leg geometry (the `delta-legs` model: pivots, arm axes, L_i, l_i, q0_i all
//    differing by leg) and imperfect parallelograms that tilt the plate: the plate turns by
//    ω = κ·z_B × (X − X0) (κ rad per metre of travel from the levelling pose X0), which the
//    camera sees and no Delta model represents; the joints follow the plate centre.
//  - Gough–Stewart: per-leg encoder gains q̄_i = g_i·(ρ_i − ρ0_i) and joint eccentricities
//    (each base joint centre offset by ε perpendicular to its leg, in the horizontal plane).
// Both give the encoder readings at a pose and the pose (FKM, Newton) at readings.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "mire/datasets/h4_true_robot.hpp"
#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/delta.hpp"
#include "mire/mechanism/h4.hpp"

namespace mire::datasets {

struct TrueRobot {
  RegisteredModel geometry_model;  // its family's truth model (registry.hpp)
  ParameterSet geometry;           // true values (the H4's: the model-12 part of its legs)
  // The H4's legs and nacelle (its kinematics replace the truth model's; mountings included).
  std::optional<H4TrueKinematics> h4;
  double tilt_per_m = 0.0;  // Delta plate tilt κ [rad/m]
  Eigen::Vector3d level_pose = Eigen::Vector3d(0, 0, -0.65);
  std::vector<double> encoder_gain;  // hexapod, per leg
  double eccentricity = 0.0;         // hexapod [m]
  // Described robots: each encoder's reading bends away from the leg's true coordinate,
  // q̄_i = q_i + c_i·(q_i − q_i,home)² (c_i per m or per rad), which no description represents.
  std::vector<double> encoder_curvature;
  Eigen::VectorXd curvature_origin;

  const Mechanism& mechanism() const { return *geometry_model.mechanism; }
  // What the truth parameter files call it: the H4 in model 12's parameters, the others their
  // truth model's name.
  std::string title() const { return h4 ? "H4 in model 12's parameters" : geometry_model.name; }

  // The true effector transform at pose X (Delta: plate centre + tilt; H4: nacelle tilt).
  Eigen::Isometry3d effector(const Eigen::VectorXd& X) const;

  // Encoder readings at pose X; empty when unreachable.
  Eigen::VectorXd joints(const Eigen::VectorXd& X) const;

  // q with the described robots' bent readings (encoder_curvature) applied.
  Eigen::VectorXd bentReadings(Eigen::VectorXd q) const;

  // The pose whose readings are q (Newton with a central-difference Jacobian; the H4's own FKM
  // from the centre of its protocol grid).
  Eigen::VectorXd fkm(const Eigen::VectorXd& q) const;
};

// An H4 drawn as makeTrueGeometry(nominal, sizes, seed) (h4_true_robot.hpp: bit-identical for a
// seed) with its camera and target mountings; its geometry is the model-12 part of that draw.
TrueRobot makeTrueH4(const H4ErrorSizes& sizes, std::uint64_t seed, const Eigen::Isometry3d& base_T_camera,
                     const Eigen::Isometry3d& marker_T_effector);

// A Delta whose legs differ (`metre` / `radian` per leg on every per-leg parameter when
// `legs_differ`, else only the common-geometry errors of that size) and whose plate tilts by κ.
TrueRobot makeDefectiveDelta(unsigned seed, bool legs_differ, double tilt_per_m = 0.0116, double metre = 1e-3,
                             double radian = 0.5 * kCampaignDeg);

// A hexapod with `metre` (1 mm) errors on every joint centre and length, encoder gains
// 1 ± 2·10⁻³ and 0.3 mm joint eccentricities. The eccentricity is perpendicular to the leg,
// so it changes the leg length by only ε²/(2ρ) (0.1 µm for 0.3 mm: doc/mechanisms.md).
TrueRobot makeDefectiveHexapod(unsigned seed, double gain_error = 2e-3, double eccentricity = 0.3e-3,
                               double metre = 1e-3);

// A described robot (mechanism/described.hpp) drawn `metre` / `radian` (0.5 mm / 0.3°) around its
// description on every leg parameter, with defects no description represents: bent encoder
// readings, |c_i| up to 0.1 /m on prismatic and extensible legs (10 µm at 10 mm from home) and
// 0.02 /rad on revolute ones (0.2 mrad at 0.1 rad), and, on a translation platform, the Delta's
// plate tilt κ about its home.
TrueRobot makeDefectiveDescribed(const RegisteredModel& model, unsigned seed, bool defects = true,
                                 double metre = 0.5e-3, double radian = 0.3 * kCampaignDeg);

// Measured campaign of a defective robot at the protocol poses (+ `extra` random ones), their
// positions spread `spread` times as far from the reference pose (a protocol over more of the
// workspace; orientations unchanged).
Campaign simulateDefectiveCampaign(const TrueRobot& robot, const std::string& model_name, unsigned seed,
                                   double noise_t = 0.2e-3, double noise_r = 0.03 * kCampaignDeg, int extra = 0,
                                   double spread = 1.0);

// The poses X (the robot's pose coordinates) a campaign measures: the H4's 81 of paper §6 (its
// protocol grid, h4_true_robot.hpp), the others' protocolPoses() at their true geometry.
std::vector<Eigen::VectorXd> protocolCoordinates(const TrueRobot& robot);

// The two straight lines of criterion V3 (paper §6.1) through the reference pose, as the
// benchmark and the mechanism demo record them: from −(a, ±a, dz) to +(a, ±a, dz) in `points`
// poses; `reach` scales the half-extents (Delta 120 / 50 mm, hexapod 40 / 25 mm, scaled as the
// protocol with protocolScale()).
std::array<std::vector<Eigen::VectorXd>, 2> straightLinePoses(const TrueRobot& robot, int points, double reach = 1.0);

// The positioning test (the square test generalised, doc/mechanisms.md): a `side` square at the
// model's reference pose commanded through its IKM at `geometric`, reached by the true robot;
// the 3-D side-length errors [m] (frame-invariant: the model's base frame is a gauge). Throws
// when a corner is unreachable for the model.
std::array<double, 4> positioningTestSides(const TrueRobot& robot, const Mechanism& model,
                                           const Eigen::VectorXd& geometric, double side = 0.1);

}  // namespace mire::datasets
