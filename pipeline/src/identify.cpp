// The identification stage (identify.hpp).
#include "mire/pipeline/identify.hpp"

#include "mire/mechanism/translating_target.hpp"
#include "mire/mechanism/variants.hpp"

#include <cctype>
#include <stdexcept>

namespace mire::pipeline {
namespace mech = mire::mechanism;

namespace {

char variantLetter(const std::string& variant) {
  if (variant.empty()) return 0;
  const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(variant[0])));
  if (variant.size() != 1 || letter < 'A' || letter > 'H')
    throw std::invalid_argument("--variant '" + variant + "': expected one letter A..H");
  return letter;
}

}  // namespace

mech::RegisteredModel ModelChoice::registered() const {
  mech::RegisteredModel registered = mech::makeRegisteredModel(model, h4);
  if (nominal) registered.nominal = *nominal;
  if (camera_on_effector) registered.external_form = mech::ExternalForm::CameraOnEffector;
  return registered;
}

std::string ModelChoice::label() const {
  if (variant) return model + ", variant " + std::string(1, variant);
  return mech::modelInfo(model).label;
}

ModelChoice chooseModel(const std::string& model, const std::string& variant, const mech::H4Nominal& h4) {
  ModelChoice choice;
  choice.h4 = h4;
  const char letter = variantLetter(variant);
  // Without a model, the variant's; without either, the registry's default (its first).
  choice.model = !model.empty() ? model
                 : letter       ? mech::modelOfVariant(letter).name
                                : mech::registeredModels().front().name;
  std::optional<mech::ModelInfo> info;
  try {
    info = mech::modelInfo(choice.model);
  } catch (const std::invalid_argument& error) {  // "unknown model 'x' (known: ...)"
    throw std::invalid_argument("--model '" + choice.model + "': " + error.what());
  }
  if (letter && info->variants.empty())
    throw std::invalid_argument("--variant applies to " + mech::variantOwnerList() + ", not to " + choice.model);
  if (letter && info->variants.find(letter) == std::string::npos)
    throw std::invalid_argument(std::string("--variant ") + letter + " does not belong to --model " + choice.model +
                                " (" + mech::variantOwnerList() + ")");
  choice.variant = letter ? letter : info->default_variant;
  return choice;
}

void applyMounting(ModelChoice& choice, const std::string& mounting) {
  if (mounting != "camera-fixed" && mounting != "camera-on-effector")
    throw std::invalid_argument("--mounting '" + mounting + "': expected camera-fixed or camera-on-effector");
  choice.camera_on_effector = mounting == "camera-on-effector";
  if (choice.camera_on_effector && choice.variant)
    throw std::invalid_argument("--mounting camera-on-effector: variant " + std::string(1, choice.variant) + " of " +
                                choice.model + " assumes the camera fixed (paper §4)");
}

InitialModel initialModel(const ModelChoice& choice, const std::vector<mech::PoseObservation>& poses,
                          const mech::IdentificationOptions& options) {
  InitialModel initial;
  initial.label = choice.label();
  if (choice.variant) {
    if (choice.nominal)  // the variants start from model 12's values (mechanism/variants.hpp)
      throw std::invalid_argument("--nominal: variant " + std::string(1, choice.variant) + " of " + choice.model +
                                  " starts from model 12's values: give a " +
                                  mech::mechanismFamily(mech::modelInfo(choice.model).family).models.front() +
                                  " parameter file (R L l h d alpha1..4 q01..4)");
    initial.model = mech::makeH4VariantModel(choice.variant, choice.h4, poses, options);
  } else {
    const mech::RegisteredModel model = choice.registered();
    initial.model = mech::makeInitialModel(model.mechanism, model.nominal, poses, model.external_form);
    // The axis-aligned form's gauge is its convention (z_ME held, paper eq. 24); the others' is
    // found from the data, after the user's --fix so that the analysis keeps to it.
    if (model.external_form != mech::ExternalForm::AxisAligned) {
      for (const auto& name : options.fix) initial.model.parameters.at(name);  // names an unknown one
      initial.model.parameters.fix(options.fix);
      initial.gauge = mech::fixGauge(initial.model, poses);
    }
  }
  for (const auto& name : options.fix)
    if (!initial.model.parameters.contains(name)) initial.model.parameters.at(name);  // throws naming the known ones
  return initial;
}

mech::IdentificationModel refitStart(const ModelChoice& choice, const InitialModel& initial,
                                     const std::vector<mech::PoseObservation>& shifted, const IdentifyOptions& options) {
  if (choice.variant) return mech::makeH4VariantModel(choice.variant, choice.h4, shifted, options.fit);
  const mech::RegisteredModel model = choice.registered();
  mech::IdentificationModel start = mech::makeInitialModel(model.mechanism, model.nominal, shifted, model.external_form);
  if (!initial.gauge) return start;
  std::vector<std::string> held = options.fit.fix;
  held.insert(held.end(), initial.gauge->gauge.begin(), initial.gauge->gauge.end());
  if (options.refit_gauge == RefitGauge::HeldAtMainFit)
    for (const std::string& name : held) start.parameters.setValue(name, initial.model.parameters.value(name));
  start.parameters.fix(held);
  return start;
}

void addSharedTerm(const ModelChoice& choice, const InitialModel& initial,
                   const std::vector<mech::PoseObservation>& poses, const mech::SharedPoseTerm& shared,
                   mech::IdentificationResult& result, const IdentifyOptions& options) {
  mech::IdentificationOptions quiet = options.fit;
  quiet.compute_identifiability = false;
  mech::addSharedTermCovariance(result, poses, shared, [&](const std::vector<mech::PoseObservation>& shifted) {
    mech::IdentificationResult refit = mech::identify(refitStart(choice, initial, shifted, options), shifted, quiet);
    mech::alignTranslatingTarget(*refit.model.mechanism, refit.model.external, refit.model.parameters, shifted);
    return refit;
  });
}

mech::IdentificationResult fit(const ModelChoice& choice, const InitialModel& initial,
                               const std::vector<mech::PoseObservation>& poses,
                               const std::optional<mech::SharedPoseTerm>& shared, const IdentifyOptions& options) {
  mech::IdentificationResult result = mech::identify(initial.model, poses, options.fit);
  if (shared) addSharedTerm(choice, initial, poses, *shared, result, options);
  return result;
}

Identification identify(const ModelChoice& choice, const std::vector<mech::PoseObservation>& poses,
                        const std::optional<mech::SharedPoseTerm>& shared, const IdentifyOptions& options) {
  Identification out;
  out.initial = initialModel(choice, poses, options.fit);
  out.result = fit(choice, out.initial, poses, shared, options);
  out.mean_orientation_covariance = mech::alignTranslatingTarget(out.result, poses);
  mech::wrapPeriodicAngles(out.result.model, out.initial.model.geometricValues());
  return out;
}

}  // namespace mire::pipeline
