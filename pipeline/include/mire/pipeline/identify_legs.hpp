#pragma once
// The identification stage with leg observations (doc/legs.md): legs only, or legs and target
// together, on top of the target-only stage (identify.hpp), which stays the reference for the
// target alone.
#include <string>
#include <vector>

#include "mire/mechanism/leg_identification.hpp"
#include "mire/pipeline/identify.hpp"

namespace mire::pipeline {

struct LegIdentification {
  mechanism::IdentificationModel initial;  // the starting values
  std::vector<std::string> held;           // the parameters held (the user's --fix, the gauge)
  mechanism::LegIdentificationResult result;
};

// Legs only: the mounting from the legs' base ends (mechanism::makeLegsInitialModel), the gauge of
// mechanism::legsOnlyGauge. Both: the target-only stage first, then the fit of both with its gauge
// released and, where the legs do not see a direction of it either, that part held again (the
// pivoted-QR dependents of a first fit). `fix`: the user's --fix. Throws std::invalid_argument for
// Observations::Target (the target-only stage is pipeline::identify) and for a model without
// observable legs.
LegIdentification identifyWithLegs(const ModelChoice& choice, const std::vector<mechanism::PoseObservation>& poses,
                                   const std::vector<mechanism::LegObservation>& legs,
                                   mechanism::Observations observations, const std::vector<std::string>& fix = {});

}  // namespace mire::pipeline
