#pragma once
// A user's own parallel robot, described once in a YAML file (doc/mechanisms.md, "Described
// mechanisms"): a platform that translates (x, y, z) or moves in 6 DoF (X = bTe), and one leg per
// actuated joint, each of three kinds with a closed-form IKM. With P_i = t + R·p_i (R = I for a
// translation platform), w = P_i − A_i and s_i = g_i·q̄_i + q0_i (g_i = 1 without gains):
//   prismatic  (PUS/PSS) carriage C_i = A_i + s_i·u_i, ‖P_i − C_i‖ = l_i,
//              s_i = w·u_i + branch·√(l_i² − ‖w‖² + (w·u_i)²)                          [m]
//   revolute   (RUS/RSS) elbow E_i = A_i + a_∥ + cos s_i·a_⊥ + sin s_i·(u_i × a_⊥), ‖P_i − E_i‖ = l_i,
//              with w' = w − a_∥: α = 2 w'·a_⊥, β = 2 w'·(u_i × a_⊥), γ = ‖w'‖² + ‖a_⊥‖² − l_i²,
//              s_i = atan2(β, α) + branch·acos(γ / √(α² + β²))                          [rad]
//   extensible (UPS/SPS) s_i = ‖w‖, the offset is the leg length ρ0_i at reading 0     [m]
//
// Geometric parameters, leg by leg in file order (i = 1..n; the gauge among them is found by the
// identifiability analysis, none is fixed by default):
//   ax<i> ay<i> az<i>        base point A_i in B                                   [m]
//   ua<i> ub<i>              axis tilt: u_i = (u0_i + ua·e_a + ub·e_b)/√(1 + ua² + ub²)  [rad]
//                            (prismatic, revolute; u0_i the described axis, e_a, e_b below)
//   armx<i> army<i> armz<i>  arm vector at s = 0 (revolute)                          [m]
//   l<i>                     rod length (prismatic, revolute)                        [m]
//   px<i> py<i> pz<i>        platform joint p_i in E                                 [m]
//   q0<i> | rho0<i>          offset: q0 (prismatic [m], revolute [rad]), ρ0 (extensible [m])
//   g<i>                     encoder gain (with `gains: true`)                       [1]
#include <Eigen/Core>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/parameter_set.hpp"
#include "mire/mechanism/pose.hpp"
#include "mire/mechanism/registry.hpp"

namespace mire::mechanism {

enum class LegActuator { Prismatic, Revolute, Extensible };
std::string legActuatorName(LegActuator actuator);  // "prismatic", "revolute", "extensible"

enum class DescribedPlatform { Translation, Full };
std::string describedPlatformName(DescribedPlatform platform);  // "translation", "full"

struct LegDescription {
  LegActuator actuator = LegActuator::Prismatic;
  Eigen::Vector3d base = Eigen::Vector3d::Zero();      // A_i in B [m]
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();     // u_i in B, unit norm (prismatic, revolute)
  Eigen::Vector3d arm = Eigen::Vector3d::Zero();       // arm vector at s = 0 [m] (revolute)
  double rod = 0.0;                                    // l_i [m] (prismatic, revolute)
  Eigen::Vector3d platform = Eigen::Vector3d::Zero();  // p_i in E [m]
  int branch = 1;                                      // +1 or −1 (prismatic, revolute)
  double offset = 0.0;                                 // q0_i [m or rad] or ρ0_i [m]
  double gain = 1.0;                                   // g_i, with `gains` only
  // The reading's stroke [min, max] (joints.csv's unit: m, rad for a revolute leg), optional: the
  // IKM names a pose outside it (IkmResult::out_of_stroke_joints) as for the built-in hexapod.
  std::optional<Eigen::Vector2d> stroke;
};

struct MechanismDescription {
  std::string name;  // free text, shown in reports
  DescribedPlatform platform = DescribedPlatform::Translation;
  std::vector<LegDescription> legs;  // in joints.csv's column order
  bool gains = false;                // a per-leg encoder gain g_i: s_i = g_i·q̄_i + q0_i
  // Where the FKM starts: (t, rotation vector) of bTe; the rotation is 0 on a translation
  // platform. Without it, the mechanism searches a pose where every leg assembles.
  std::optional<PoseVector> home;

  // The description as a file readMechanismDescription() reads back to the same values
  // (numbers written to round-trip), e.g. the identified geometry in an identified file.
  std::string yamlString() const;
};

// Reads a description file (keys: doc/mechanisms.md). Any YAML a person writes is accepted
// (block or flow sequences, integers for numbers, `branch: +1`). Every error is a
// std::invalid_argument naming the file, the line and the key: "robot.yaml:7: key
// 'legs[1].axis': expected 3 numbers [x, y, z], not 2".
MechanismDescription readMechanismDescription(const std::filesystem::path& file);
// Same rules, from text; `name` stands for the file name in messages.
MechanismDescription parseMechanismDescription(const std::string& text, const std::string& name);

// Checks a description built in code (leg counts, finite values, unit axes, positive rods, an
// arm not along its axis, branch ±1); throws std::invalid_argument naming the leg.
void validateMechanismDescription(const MechanismDescription& description);

// The tangent directions of a leg's axis tilts ua, ub (orthonormal, e_b = u0 × e_a): e_a is the
// base axis (x_B, then y_B, then z_B on ties) least aligned with u0, made orthogonal to it.
void axisTiltBasis(const Eigen::Vector3d& axis, Eigen::Vector3d* e_a, Eigen::Vector3d* e_b);

// The geometric parameters (names, units, nominal values from the description; all free).
ParameterSet describedParameters(const MechanismDescription& description);
// The description with the values of `geometric` (describedParameters()'s names): the axis
// tilts are folded into the axes, so the result's own tilts are 0 again.
MechanismDescription describedWithParameters(const MechanismDescription& description, const ParameterSet& geometric);

std::unique_ptr<Mechanism> makeDescribedMechanism(const MechanismDescription& description);
// A described model as the registry's models are served: name = the description's name,
// nominal = describedParameters(), external form Full (doc/mechanisms.md, "Mounting").
RegisteredModel makeDescribedModel(const MechanismDescription& description);
RegisteredModel makeDescribedModel(const std::filesystem::path& file);

}  // namespace mire::mechanism
