// The identification stage with leg observations (identify_legs.hpp, doc/legs.md).
#include "mire/pipeline/identify_legs.hpp"

#include <algorithm>
#include <stdexcept>

namespace mire::pipeline {

namespace mech = mire::mechanism;

namespace {

LegIdentification legsOnly(const ModelChoice& choice, const std::vector<mech::PoseObservation>& poses,
                           const std::vector<mech::LegObservation>& legs, const std::vector<std::string>& fix) {
  const mech::RegisteredModel model = choice.registered();
  LegIdentification out;
  out.initial = mech::makeLegsInitialModel(model.mechanism, model.nominal, legs);
  out.held = mech::legsOnlyGauge(out.initial);
  for (const std::string& name : fix) {
    out.initial.parameters.at(name);  // throws naming the known ones
    out.held.push_back(name);
  }
  mech::LegIdentificationOptions options;
  options.observations = mech::Observations::Legs;
  options.fix = out.held;
  out.result = mech::identifyWithLegs(out.initial, poses, legs, options);
  return out;
}

LegIdentification both(const ModelChoice& choice, const std::vector<mech::PoseObservation>& poses,
                       const std::vector<mech::LegObservation>& legs, const std::vector<std::string>& fix) {
  IdentifyOptions target_options;
  target_options.fit.fix = fix;
  const Identification target = identify(choice, poses, std::nullopt, target_options);
  LegIdentification out;
  out.initial = target.result.model;
  mech::LegIdentificationOptions options;
  options.observations = mech::Observations::Both;
  // The target-only gauge (the frames the target cannot tell apart) is released: the legs see the
  // base frame. The user's --fix stays held.
  if (target.initial.gauge) options.release = target.initial.gauge->gauge;
  options.release.erase(
      std::remove_if(options.release.begin(), options.release.end(),
                     [&](const std::string& n) { return std::find(fix.begin(), fix.end(), n) != fix.end(); }),
      options.release.end());
  out.result = mech::identifyWithLegs(out.initial, poses, legs, options);
  if (!out.result.identifiability.fullRank()) {
    options.fix = out.result.identifiability.unidentifiable;
    out.result = mech::identifyWithLegs(out.initial, poses, legs, options);
  }
  for (const mech::Parameter& p : out.result.model.parameters.parameters())
    if (p.fixed) out.held.push_back(p.name);
  return out;
}

}  // namespace

LegIdentification identifyWithLegs(const ModelChoice& choice, const std::vector<mech::PoseObservation>& poses,
                                   const std::vector<mech::LegObservation>& legs, mech::Observations observations,
                                   const std::vector<std::string>& fix) {
  if (observations == mech::Observations::Target)
    throw std::invalid_argument("the target-only identification is pipeline::identify");
  if (choice.registered().mechanism->legCount() == 0)
    throw std::invalid_argument("--observations " + mech::observationsName(observations) + ": model " + choice.label() +
                                " has no observable legs (doc/legs.md: gough-stewart, gough-stewart-gains, delta)");
  return observations == mech::Observations::Legs ? legsOnly(choice, poses, legs, fix) : both(choice, poses, legs, fix);
}

}  // namespace mire::pipeline
