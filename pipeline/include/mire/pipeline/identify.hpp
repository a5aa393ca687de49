#pragma once
// The identification stage (paper §2–6; doc/uncertainty.md): initial model → gauge → weighted
// fit → the calibration's shared term by refits → the translating target's orientation. The one
// recipe `mire identify`, the demos, the benchmarks and the studies run; every σ a caller prints
// comes out of it.
#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/identification_covariance.hpp"
#include "mire/mechanism/registry.hpp"

namespace mire::pipeline {

// The model to identify: a registered model (mechanism/registry.hpp) and, for the H4's models
// 12 and 31c, the paper's variant (Table 2, mechanism/variants.hpp), whose fixed and tied
// parameters replace the gauge analysis.
struct ModelChoice {
  std::string model = mechanism::registeredModels().front().name;
  char variant = 0;         // one of the model's ModelInfo::variants, or 0
  mechanism::H4Nominal h4;  // the H4 models' nominal geometry
  // The other models' nominal geometry when not the built-in one (`--nominal`, applyNominalFile).
  std::optional<mechanism::ParameterSet> nominal;
  // `--mounting camera-on-effector` (doc/mechanisms.md, "Camera on the effector"): the camera on
  // the effector, the target fixed; the model's external form is then CameraOnEffector.
  bool camera_on_effector = false;
  std::string label() const;                      // `h4-12, variant D`, `h4-31 (base frame)`, `delta`
  mechanism::RegisteredModel registered() const;  // the mechanism, its nominal geometry and external form
};

// Completes and checks a choice made by name: the variant's model when `model` is empty (the
// registry's default without either), the model's default variant (ModelInfo::default_variant).
// Throws std::invalid_argument naming the option at fault ("--model", "--variant").
ModelChoice chooseModel(const std::string& model, const std::string& variant, const mechanism::H4Nominal& h4 = {});

// `--mounting camera-fixed|camera-on-effector` on a choice; throws std::invalid_argument for
// another word or a variant of the paper's H4 (its parameterisation assumes the camera fixed).
void applyMounting(ModelChoice& choice, const std::string& mounting);

// Sets the choice's nominal geometry from a parameter file (`--nominal`, doc/file-formats.md): a
// file of the model's own parameters sets `nominal`; for the H4 models, a file of model 12's keys
// (R L l h d alpha1..4 q01..4, amplification; no `model:` or `model: h4-12`) sets `h4`, from
// which every H4 model and variant starts. An identified file is accepted (its mounting and
// sigma_ keys are ignored); a file of another model (`model:`), an unknown key or a missing
// parameter throws std::runtime_error naming the file, the line and the key.
void applyNominalFile(ModelChoice& choice, const std::filesystem::path& file);
// applyNominalFile(`file`) when given (`--nominal`), else the model's default: the H4 models'
// datasets/specs/h4_nominal.yaml, the others' built-in nominal.
void applyNominal(ModelChoice& choice, const std::string& file);

// Where the shared term's refits hold the parameters the main fit held (its gauge, --fix):
// `HeldAtMainFit`, at the main fit's values, so that the refits measure the estimate's change
// within one gauge; `Reinitialised`, where the refit's own initialisation puts them on the
// shifted poses (the gauge then moves with the poses: kept for the studies that show why not,
// doc/uncertainty.md).
enum class RefitGauge { HeldAtMainFit, Reinitialised };

struct IdentifyOptions {
  mechanism::IdentificationOptions fit;  // --fix, --prior, --robust
  RefitGauge refit_gauge = RefitGauge::HeldAtMainFit;
};

// The model the fit starts from: nominal geometry, the mounting from the data (motion type),
// the user's fixed parameters, and the gauge the analysis held (models without a variant).
struct InitialModel {
  mechanism::IdentificationModel model;
  std::string label;
  std::optional<mechanism::GaugeAnalysis> gauge;
};
// Throws std::invalid_argument for an unknown name in options.fix.
InitialModel initialModel(const ModelChoice& choice, const std::vector<mechanism::PoseObservation>& poses,
                          const mechanism::IdentificationOptions& options = {});

// The model a shared-term refit starts from on `shifted` poses: built as `initial` was, with
// the parameters it held placed per `options.refit_gauge`.
mechanism::IdentificationModel refitStart(const ModelChoice& choice, const InitialModel& initial,
                                          const std::vector<mechanism::PoseObservation>& shifted,
                                          const IdentifyOptions& options);

// The weighted fit of `initial` on `poses`; with `shared`, its covariance G Σ_k Gᵀ added by
// central-difference refits of the whole estimator (mechanism::addSharedTermCovariance).
mechanism::IdentificationResult fit(const ModelChoice& choice, const InitialModel& initial,
                                    const std::vector<mechanism::PoseObservation>& poses,
                                    const std::optional<mechanism::SharedPoseTerm>& shared,
                                    const IdentifyOptions& options = {});

// The shared term alone, added to a result of fit() made without it.
void addSharedTerm(const ModelChoice& choice, const InitialModel& initial,
                   const std::vector<mechanism::PoseObservation>& poses, const mechanism::SharedPoseTerm& shared,
                   mechanism::IdentificationResult& result, const IdentifyOptions& options = {});

// The whole stage.
struct Identification {
  InitialModel initial;
  mechanism::IdentificationResult result;
  // A translating plate: the covariance of the mean measured orientation the target's rotation
  // was set from (mechanism/translating_target.hpp); std::nullopt otherwise.
  std::optional<Eigen::Matrix3d> mean_orientation_covariance;
};
Identification identify(const ModelChoice& choice, const std::vector<mechanism::PoseObservation>& poses,
                        const std::optional<mechanism::SharedPoseTerm>& shared, const IdentifyOptions& options = {});

}  // namespace mire::pipeline
