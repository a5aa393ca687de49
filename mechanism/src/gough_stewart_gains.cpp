// Model `gough-stewart-gains`: Gough–Stewart with one encoder scale per leg (doc/mechanisms.md).
#include "mire/mechanism/gough_stewart_gains.hpp"

#include <string>

#include "mire/mechanism/detail/gough_stewart_gains_kinematics.hpp"
#include "mire/mechanism/mechanism_adapter.hpp"

namespace mire::mechanism {

ParameterSet goughStewartGainsParameters(const GoughStewartNominal& nominal) {
  ParameterSet set = goughStewartParameters(nominal);
  for (int i = 1; i <= 6; ++i)
    set.add({"s" + std::to_string(i), 1.0, Unit::Dimensionless, false,
             "leg " + std::to_string(i) + " encoder scale (leg length per reading: rho = rho0 + s q)"});
  return set;
}

std::unique_ptr<Mechanism> makeGoughStewartGainsMechanism(const GoughStewartNominal& nominal) {
  return std::make_unique<MechanismAdapter<GoughStewartGainsKinematics>>(
      hexapodKinematics<GoughStewartGainsKinematics>(nominal), goughStewartGainsParameters(nominal));
}

}  // namespace mire::mechanism
