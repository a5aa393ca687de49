// Name -> model registry (doc/mechanisms.md).
#include "mire/mechanism/registry.hpp"

#include <stdexcept>

#include "mire/mechanism/delta.hpp"
#include "mire/mechanism/gough_stewart.hpp"
#include "mire/mechanism/gough_stewart_gains.hpp"

namespace mire::mechanism {

const std::vector<ModelInfo>& registeredModels() {
  // name, description, label, takes an H4 nominal, the paper's variants and the default one.
  static const std::vector<ModelInfo> models{
      {"h4-12", "H4, model 12 (paper §3.2), axis-aligned mounting", "h4-12", true, "ABCD", 'D'},
      {"h4-31", "H4, model 31 in the base frame (paper §3.3), axis-aligned mounting", "h4-31 (base frame)", true, "", 0},
      {"h4-31c", "H4, model 31 in the camera frame (paper eq. 25-26)", "h4-31c", true, "EFGH", 'H'},
      {"delta", "Delta robot, common geometry (R r L l alpha1..3 q01..3), full mounting", "delta", false, "", 0},
      {"delta-legs", "Delta robot, per-leg geometry (24 parameters), full mounting", "delta-legs", false, "", 0},
      {"gough-stewart", "Gough-Stewart platform (42 parameters), full mounting", "gough-stewart", false, "", 0},
      {"gough-stewart-gains", "Gough-Stewart platform + one encoder scale per leg (48 parameters), full mounting",
       "gough-stewart-gains", false, "", 0},
  };
  return models;
}

const ModelInfo& modelInfo(const std::string& name) {
  for (const ModelInfo& m : registeredModels())
    if (m.name == name) return m;
  throw std::invalid_argument("unknown model '" + name + "' (known: " + registeredModelList() + ")");
}

const ModelInfo& modelOfVariant(char letter) {
  for (const ModelInfo& m : registeredModels())
    if (letter && m.variants.find(letter) != std::string::npos) return m;
  throw std::invalid_argument(std::string("no model has the variant '") + letter + "' (A-H)");
}

std::string registeredModelList() {
  std::string list;
  for (const ModelInfo& m : registeredModels()) list += (list.empty() ? "" : ", ") + m.name;
  return list;
}

RegisteredModel makeRegisteredModel(const std::string& name, const H4Nominal& h4) {
  RegisteredModel out;
  out.name = name;
  out.external_form = ExternalForm::Full;
  if (name == "h4-12") {
    out.mechanism = makeH4Mechanism(H4ModelKind::Model12, h4);
    out.nominal = h4Model12Parameters(h4);
    out.external_form = ExternalForm::AxisAligned;
  } else if (name == "h4-31") {
    out.mechanism = makeH4Mechanism(H4ModelKind::Model31, h4);
    out.nominal = model31FromModel12(h4Model12Parameters(h4));
    out.external_form = ExternalForm::AxisAligned;
  } else if (name == "h4-31c") {
    out.mechanism = makeH4Mechanism(H4ModelKind::Model31Camera, h4);
    out.nominal = out.mechanism->nominal();
    out.external_form = ExternalForm::CameraFrame;
  } else if (name == "delta" || name == "delta-legs") {
    out.mechanism = makeDeltaMechanism(name == "delta" ? DeltaModelKind::Simple : DeltaModelKind::Legs);
    out.nominal = out.mechanism->nominal();
  } else if (name == "gough-stewart") {
    out.mechanism = makeGoughStewartMechanism();
    out.nominal = out.mechanism->nominal();
  } else if (name == "gough-stewart-gains") {
    out.mechanism = makeGoughStewartGainsMechanism();
    out.nominal = out.mechanism->nominal();
  } else {
    throw std::invalid_argument("unknown model '" + name + "' (known: " + registeredModelList() + ")");
  }
  return out;
}

}  // namespace mire::mechanism
