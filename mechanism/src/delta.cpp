// Delta models `delta` and `delta-legs`, and the Gough–Stewart model (doc/mechanisms.md).
#include "mire/mechanism/delta.hpp"

#include <cmath>
#include <stdexcept>

#include "mire/mechanism/detail/parallel_kinematics.hpp"
#include "mire/mechanism/gough_stewart.hpp"
#include "mire/mechanism/mechanism_adapter.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {

namespace {

using support::kPi;

std::string indexed(const std::string& base, int i) { return base + std::to_string(i + 1); }

}  // namespace

ParameterSet deltaParameters(const DeltaNominal& n) {
  ParameterSet set;
  set.add(positiveLength("R", n.R, "radius of the arm pivots' circle"));
  set.add(positiveLength("r", n.r, "radius of the plate joints' circle (only R - r enters)", true));
  set.add(positiveLength("L", n.L, "arm length"));
  set.add(positiveLength("l", n.l, "forearm (parallelogram) length"));
  for (int i = 0; i < 3; ++i)
    set.add({indexed("alpha", i), n.alpha[static_cast<std::size_t>(i)], Unit::Radian, i == 0,
             "direction of arm pivot " + std::to_string(i + 1) + " about z_B" + (i == 0 ? " (defines x_B)" : "")});
  for (int i = 0; i < 3; ++i)
    set.add({indexed("q0", i), n.q0[static_cast<std::size_t>(i)], Unit::Radian, false,
             "joint offset " + std::to_string(i + 1)});
  return set;
}

ParameterSet deltaLegsFromDelta(const ParameterSet& d) {
  ParameterSet set;
  const double reach = d.value("R") - d.value("r");
  for (int i = 0; i < 3; ++i) {
    const double a = d.value(indexed("alpha", i));
    const std::string leg = " of leg " + std::to_string(i + 1);
    set.add({indexed("px", i), reach * std::cos(a), Unit::Metre, false, "effective pivot x" + leg});
    set.add({indexed("py", i), reach * std::sin(a), Unit::Metre, false, "effective pivot y" + leg});
    set.add({indexed("pz", i), 0.0, Unit::Metre, false, "effective pivot z" + leg});
    // In (−π, π], where every parameter-file reader takes it (a leg at α = 240° has ψ = 60°).
    set.add({indexed("psi", i), std::remainder(a + kPi, 2.0 * kPi), Unit::Radian, false, "arm axis azimuth" + leg});
    set.add({indexed("beta", i), 0.5 * kPi, Unit::Radian, false, "arm axis tilt" + leg});
    set.add(positiveLength(indexed("L", i), d.value("L"), "arm length" + leg));
    set.add(positiveLength(indexed("l", i), d.value("l"), "forearm length" + leg));
    set.add({indexed("q0", i), d.value(indexed("q0", i)), Unit::Radian, false, "joint offset" + leg});
  }
  return set;
}

std::unique_ptr<Mechanism> makeDeltaMechanism(DeltaModelKind kind, const DeltaNominal& nominal) {
  if (!(nominal.l > nominal.L && nominal.L > 0.0 && nominal.R > nominal.r))
    throw std::invalid_argument("delta nominal: expected l > L > 0 and R > r");
  const ParameterSet simple = deltaParameters(nominal);
  // The built-in Delta's reference pose is 0.65 m below its base, 4 % below its level-arm depth.
  constexpr double kBuiltInHomeZ = -0.65;
  const double home_ratio = kBuiltInHomeZ / DeltaKinematics::levelDepth(deltaParameters(DeltaNominal{}).values());
  if (kind == DeltaModelKind::Simple) {
    DeltaKinematics k;
    k.home_ratio = home_ratio;
    return std::make_unique<MechanismAdapter<DeltaKinematics>>(k, simple);
  }
  DeltaLegsKinematics k;
  k.home_ratio = home_ratio;
  return std::make_unique<MechanismAdapter<DeltaLegsKinematics>>(k, deltaLegsFromDelta(simple));
}

ParameterSet goughStewartParameters(const GoughStewartNominal& n) {
  ParameterSet set;
  constexpr double kDeg = kPi / 180.0;
  const char* axes[3] = {"x", "y", "z"};
  for (int i = 0; i < 6; ++i) {
    const double a = n.base_angles_deg[static_cast<std::size_t>(i)] * kDeg;
    const double v[3] = {n.base_radius * std::cos(a), n.base_radius * std::sin(a), 0.0};
    for (int k = 0; k < 3; ++k)
      set.add({std::string("b") + axes[k] + std::to_string(i + 1), v[k], Unit::Metre, false,
               std::string("base joint ") + std::to_string(i + 1) + " in B, " + axes[k]});
  }
  for (int i = 0; i < 6; ++i) {
    const double a = n.platform_angles_deg[static_cast<std::size_t>(i)] * kDeg;
    const double v[3] = {n.platform_radius * std::cos(a), n.platform_radius * std::sin(a), 0.0};
    for (int k = 0; k < 3; ++k)
      set.add({std::string("p") + axes[k] + std::to_string(i + 1), v[k], Unit::Metre, false,
               std::string("platform joint ") + std::to_string(i + 1) + " in E, " + axes[k]});
  }
  for (int i = 0; i < 6; ++i) {
    const double ab = n.base_angles_deg[static_cast<std::size_t>(i)] * kDeg;
    const double ap = n.platform_angles_deg[static_cast<std::size_t>(i)] * kDeg;
    const Eigen::Vector3d d(n.platform_radius * std::cos(ap) - n.base_radius * std::cos(ab),
                            n.platform_radius * std::sin(ap) - n.base_radius * std::sin(ab), n.home_height);
    set.add({indexed("rho0", i), d.norm() - n.home_reading, Unit::Metre, false,
             "leg " + std::to_string(i + 1) + " length at encoder zero"});
  }
  return set;
}

std::unique_ptr<Mechanism> makeGoughStewartMechanism(const GoughStewartNominal& nominal) {
  return std::make_unique<MechanismAdapter<GoughStewartKinematics>>(hexapodKinematics<GoughStewartKinematics>(nominal),
                                                                    goughStewartParameters(nominal));
}

}  // namespace mire::mechanism
