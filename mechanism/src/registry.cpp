// The table of mechanisms (registry.hpp, doc/architecture.md): the one place a model's name is spelled.
#include "mire/mechanism/registry.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

#include "mire/mechanism/delta.hpp"
#include "mire/mechanism/described.hpp"
#include "mire/mechanism/detail/parallel_kinematics.hpp"
#include "mire/mechanism/gough_stewart.hpp"
#include "mire/mechanism/gough_stewart_gains.hpp"

namespace mire::mechanism {

namespace {

RegisteredModel ofMechanism(std::shared_ptr<const Mechanism> mechanism, ExternalForm form = ExternalForm::Full) {
  ParameterSet nominal = mechanism->nominal();
  return {mechanism->name(), std::move(mechanism), std::move(nominal), form};
}

RegisteredModel h4Model(H4ModelKind kind, const H4Nominal& h4) {
  switch (kind) {
    case H4ModelKind::Model12:
      return {"", makeH4Mechanism(kind, h4), h4Model12Parameters(h4), ExternalForm::AxisAligned};
    case H4ModelKind::Model31:
      return {"", makeH4Mechanism(kind, h4), model31FromModel12(h4Model12Parameters(h4)), ExternalForm::AxisAligned};
    case H4ModelKind::Model31Camera:
      return ofMechanism(makeH4Mechanism(kind, h4), ExternalForm::CameraFrame);
  }
  throw std::logic_error("unknown H4 model kind");
}

std::vector<ModelInfo> builtInModels() {
  const auto other = [](auto make) { return [make](const H4Nominal&) { return ofMechanism(make()); }; };
  const auto h4 = [](H4ModelKind kind) { return [kind](const H4Nominal& n) { return h4Model(kind, n); }; };
  return {
      {"h4-12",
       "H4, model 12 (paper §3.2), axis-aligned mounting",
       "h4-12",
       "h4",
       true,
       "ABCD",
       'D',
       {},
       {},
       h4(H4ModelKind::Model12)},
      {"h4-31",
       "H4, model 31 in the base frame (paper §3.3), axis-aligned mounting",
       "h4-31 (base frame)",
       "h4",
       true,
       "",
       0,
       {"h4-12"},
       {"h", "l1"},
       h4(H4ModelKind::Model31)},
      {"h4-31c",
       "H4, model 31 in the camera frame (paper eq. 25-26)",
       "h4-31c",
       "h4",
       true,
       "EFGH",
       'H',
       {"h4-12"},
       {"h", "l1"},
       h4(H4ModelKind::Model31Camera)},
      {"delta",
       "Delta robot, common geometry (R r L l alpha1..3 q01..3), full mounting",
       "delta",
       "delta",
       false,
       "",
       0,
       {},
       {},
       other([] { return makeDeltaMechanism(DeltaModelKind::Simple); })},
      {"delta-legs",
       "Delta robot, per-leg geometry (24 parameters), full mounting",
       "delta-legs",
       "delta",
       false,
       "",
       0,
       {"delta"},
       {},
       other([] { return makeDeltaMechanism(DeltaModelKind::Legs); })},
      {"gough-stewart-symmetric",
       "Gough-Stewart platform, symmetric layout (rb beta_b rp beta_p rho0), full mounting",
       "gough-stewart-symmetric",
       "gough-stewart",
       false,
       "",
       0,
       {},
       {},
       other([] { return makeGoughStewartSymmetricMechanism(); })},
      {"gough-stewart",
       "Gough-Stewart platform (42 parameters), full mounting",
       "gough-stewart",
       "gough-stewart",
       false,
       "",
       0,
       {"gough-stewart-symmetric"},
       {},
       other([] { return makeGoughStewartMechanism(); })},
      {"gough-stewart-gains",
       "Gough-Stewart platform + one encoder scale per leg (48 parameters), full mounting",
       "gough-stewart-gains",
       "gough-stewart",
       false,
       "",
       0,
       {"gough-stewart"},
       {},
       other([] { return makeGoughStewartGainsMechanism(); })},
  };
}

std::vector<MechanismFamily> builtInFamilies() {
  MechanismFamily h4{"h4",
                     "H4",
                     "H4",
                     {},
                     "h4-12:A,B,C,D,h4-31c:E,F,G,H",
                     "h4-12",
                     "its 12 geometric parameters (model 12's mounting is axis-aligned: no gauge)",
                     SimulatedDefects::H4Parallelograms,
                     "an H4 whose legs differ, with tilted arm axes and imperfect parallelograms (doc/mechanisms.md)"};
  MechanismFamily delta{
      "delta",
      "Delta",
      "Delta",
      {},
      "delta,delta-legs",
      "delta-legs",
      "L1..L3 and l1..l3 (the pivots, axes and q0i are in the frame of the gauge)",
      SimulatedDefects::PlateTilt,
      "a Delta (3 rotary actuators, a plate that only translates) whose three legs differ (the `delta-legs` "
      "geometry: each leg's pivot, arm axis, arm and forearm lengths and joint offset off by about 1 mm / 0.5°) "
      "and whose imperfect parallelograms tilt the plate by 0.0116 rad per metre of travel (no Delta model "
      "represents it), moved through the 27 protocol positions of doc/mechanisms.md (a 300 × 300 × 150 mm grid "
      "around z = −0.65 m), the camera 0.68 m below the workspace centre looking up"};
  MechanismFamily hexapod{
      "gough-stewart",
      "Gough–Stewart hexapod",
      "Gough-Stewart hexapod",
      {},
      "gough-stewart,gough-stewart-gains",
      "gough-stewart",
      "rho01..rho06 (the joint centres are in the frame of the gauge)",
      SimulatedDefects::GainsAndEccentricity,
      "a Gough–Stewart hexapod (6 prismatic legs, 6 DoF) with 1 mm errors on every joint centre and leg "
      "length, per-leg encoder gains 1 ± 2·10⁻³ and 0.3 mm joint eccentricities (neither in the 42-parameter "
      "model), moved through the 81 protocol poses of doc/mechanisms.md (27 positions ±40 mm, ±30 mm in z, × 3 "
      "orientations with ±6° tilts and a yaw), the camera 0.45 m above the platform's home looking down"};
  std::vector<MechanismFamily> families{h4, delta, hexapod};
  for (MechanismFamily& family : families)
    for (const ModelInfo& model : registeredModels())
      if (model.family == family.name) family.models.push_back(model.name);
  return families;
}

template <class Entry>
std::string nameList(const std::vector<Entry>& entries) {
  std::string list;
  for (const Entry& e : entries) list += (list.empty() ? "" : ", ") + e.name;
  return list;
}

}  // namespace

const std::vector<ModelInfo>& registeredModels() {
  static const std::vector<ModelInfo> models = builtInModels();
  return models;
}

bool isDescriptionFile(const std::string& model) {
  std::string extension = std::filesystem::path(model).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".yaml" || extension == ".yml";
}

ModelInfo modelInfo(const std::string& name) {
  if (isDescriptionFile(name)) {  // a user's robot (doc/mechanisms.md, "Described mechanisms")
    const MechanismDescription description = readMechanismDescription(name);
    ModelInfo info;
    info.name = name;
    info.description = description.name + ", described in " + name + ", full mounting";
    info.label = description.name;
    info.make = [description](const H4Nominal&) { return makeDescribedModel(description); };
    return info;
  }
  for (const ModelInfo& m : registeredModels())
    if (m.name == name) return m;
  throw std::invalid_argument("unknown model '" + name + "' (known: " + registeredModelList() +
                              ", or a mechanism description file *.yaml)");
}

const ModelInfo& modelOfVariant(char letter) {
  for (const ModelInfo& m : registeredModels())
    if (letter && m.variants.find(letter) != std::string::npos) return m;
  throw std::invalid_argument(std::string("no model has the variant '") + letter + "' (A-H)");
}

std::string registeredModelList() { return nameList(registeredModels()); }

std::string variantOwnerList() {
  std::string list;
  for (const ModelInfo& m : registeredModels())
    if (!m.variants.empty())
      list += (list.empty() ? "" : ", ") + m.name + " (" + m.variants.front() + "-" + m.variants.back() + ")";
  return list;
}

const std::vector<MechanismFamily>& mechanismFamilies() {
  static const std::vector<MechanismFamily> families = builtInFamilies();
  return families;
}

std::string mechanismFamilyList() { return nameList(mechanismFamilies()); }

const MechanismFamily& mechanismFamily(const std::string& name) {
  for (const MechanismFamily& f : mechanismFamilies())
    if (f.name == name) return f;
  throw std::invalid_argument("unknown mechanism '" + name + "' (known: " + mechanismFamilyList() + ")");
}

MechanismFamily mechanismFamilyOf(const std::string& name_or_file) {
  if (!isDescriptionFile(name_or_file)) return mechanismFamily(name_or_file);
  const MechanismDescription description = readMechanismDescription(name_or_file);
  MechanismFamily family;
  family.name = name_or_file;
  family.title = "described robot '" + description.name + "' (" + std::to_string(description.legs.size()) + " legs)";
  family.plain_title = std::filesystem::path(name_or_file).stem().string();
  family.models = {name_or_file};
  family.truth_model = name_or_file;
  family.defects = SimulatedDefects::BentReadings;
  family.simulated_robot =
      "the described robot (`" + name_or_file +
      "`) drawn 0.5 mm / 0.3 deg around its description on every leg parameter, with defects no description "
      "represents: bent encoder readings and, on a translating platform, a plate tilting with travel "
      "(doc/simulation.md)";
  return family;
}

const MechanismFamily& familyWithDefects(SimulatedDefects defects) {
  const auto& families = mechanismFamilies();
  const auto it = std::find_if(families.begin(), families.end(),
                               [defects](const MechanismFamily& f) { return f.defects == defects; });
  if (it == families.end()) throw std::logic_error("no mechanism family simulates these defects");
  return *it;
}

RegisteredModel makeRegisteredModel(const std::string& name, const H4Nominal& h4) {
  RegisteredModel out = modelInfo(name).make(h4);
  out.name = name;
  return out;
}

}  // namespace mire::mechanism
