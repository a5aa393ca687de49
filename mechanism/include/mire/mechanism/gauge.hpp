#pragma once
// What the measurements cannot see, found from the data rather than hard-coded
// (paper §2.2, doc/mechanisms.md): the identifiability analysis is run on model-consistent
// poses (each measured cTm replaced by the one the model predicts from the encoders, so that
// measurement noise does not hide an exact dependence such as the target's rotation on a
// plate that never turns), then pivoted QR (Khalil & Besnard) picks a minimal identifiable
// set. Every free parameter is then reported as
//   identified        — in no unidentifiable combination;
//   combination-only  — free, but only its combination with gauge parameters is determined;
//   gauge             — held at its current value: a convention (frame choice, or no influence).
#include <string>
#include <vector>

#include "mire/mechanism/identifiability.hpp"
#include "mire/mechanism/identification.hpp"

namespace mire::mechanism {

struct GaugeAnalysis {
  IdentifiabilityReport report;  // over the model's free parameters
  std::vector<std::string> identified;
  std::vector<std::string> combination_only;
  std::vector<std::string> gauge;         // the pivoted-QR dependents
  std::vector<std::string> no_influence;  // gauge parameters whose column is zero
  std::string text() const;               // human summary with the named combinations
};

// cTm_j the model predicts from q̄_j (FKM at the current values, then the mounting).
// Throws std::runtime_error naming the poses where the FKM fails.
std::vector<PoseObservation> modelConsistentPoses(const IdentificationModel& model,
                                                  const std::vector<PoseObservation>& poses);

// The analysis at the model's current values; `keep_free` are never chosen as gauge (the
// user's choice of identified parameters) unless they are themselves undetermined.
GaugeAnalysis analyzeGauge(const IdentificationModel& model, const std::vector<PoseObservation>& poses,
                           const IdentifiabilityOptions& options = {});

// A plate that only translates: the target's rotation on the effector (eTm, full form) has
// no influence on the joints, so the identification leaves it where the initialisation put
// it. Sets it from the measured orientations and the identified camera mounting,
// eRm = cRbᵀ · mean_j(cRm_j), so that the model predicts cTm's orientation too; with the camera
// on the effector, eRc = bRm · mean_j(cRm_jᵀ). No-op for other motions or forms. (Defined in external_mounting.cpp.)
void alignTranslatingTarget(const Mechanism& mechanism, ExternalParameterization const& form, ParameterSet& parameters,
                            const std::vector<PoseObservation>& poses);

// analyzeGauge(), then fixes the gauge parameters in `model`.
GaugeAnalysis fixGauge(IdentificationModel& model, const std::vector<PoseObservation>& poses,
                       const IdentifiabilityOptions& options = {});

}  // namespace mire::mechanism
