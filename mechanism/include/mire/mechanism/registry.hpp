#pragma once
// The table of mechanisms (doc/architecture.md, "Adding a mechanism"): every built-in model and
// every robot mire simulates, with what the rest of mire asks of them, so that no other file
// tests or spells a model's name. The CLI (`--model`, `--mechanism`), the parameter files
// (`model:`), select, simulate, the demos and Python read it.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "mire/mechanism/external.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/parameter_set.hpp"

namespace mire::mechanism {

struct RegisteredModel {
  std::string name;
  std::shared_ptr<const Mechanism> mechanism;
  ParameterSet nominal;        // geometric parameters, nominal values, default fixed flags
  ExternalForm external_form;  // the form identify uses for this model
};

// One built-in model.
struct ModelInfo {
  std::string name;  // as typed by users
  std::string description;
  std::string label;        // in reports and on the terminal (the name, or what it adds to it)
  std::string family;       // the robot it describes (MechanismFamily::name)
  bool h4_nominal = false;  // its nominal geometry is an H4's (`--nominal`: a model-12 parameter file)
  std::string variants;     // the paper's Table 2 variants it takes (variants.hpp), "" for none
  char default_variant = 0;
  // Nesting for select's F-tests: the simpler models this one contains, and the parameters a
  // variant of this one must free for the containment to hold (doc/mechanisms.md, "Families and nesting").
  std::vector<std::string> contains;
  std::vector<std::string> contains_when_free;
  // Its kinematics and nominal geometry (the H4 models from `h4`, the others ignore it).
  std::function<RegisteredModel(const H4Nominal& h4)> make;
};

// How a simulated robot of a family departs from its models (datasets/mechanism_true_robots.hpp).
enum class SimulatedDefects {
  H4Parallelograms,      // per-leg H4 geometry, tilted arm axes, bar mismatch (datasets/h4_true_robot.hpp)
  PlateTilt,             // legs that differ, a plate tilting with travel
  GainsAndEccentricity,  // per-leg encoder gains, joint eccentricities
  BentReadings,          // a described robot: bent encoder readings, a plate tilt on translating platforms
};

// A robot mire simulates (`demo --mechanism`, `simulate campaign --mechanism`) and its models.
struct MechanismFamily {
  std::string name;
  std::string title;                // in reports
  std::string plain_title;          // ASCII, for the charts' Hershey fonts
  std::vector<std::string> models;  // its registered models, simplest first
  std::string selection;            // select's default `--models` for its joints (the demo identifies these)
  // The model its simulated robot's true geometry is written in (truth/<model>.yaml) and which
  // of that model's parameters compare with the truth directly (the others are in the gauge's frame).
  std::string truth_model;
  std::string comparable;
  SimulatedDefects defects = SimulatedDefects::H4Parallelograms;
  std::string simulated_robot;  // the demo report's description of the simulated robot
};

const std::vector<ModelInfo>& registeredModels();  // the default model first
std::string registeredModelList();                 // the names, comma-separated
// A model name that is a mechanism description file (`*.yaml`, `*.yml`: described.hpp).
bool isDescriptionFile(const std::string& model);
// A built-in model's row, or a described model's (read from the file: no family, no variants).
// Throws std::invalid_argument "unknown model 'x' (known: ...)", or naming the description
// file's line and key.
ModelInfo modelInfo(const std::string& name);
// The model whose variants include `letter` (A–H); throws std::invalid_argument for another letter.
const ModelInfo& modelOfVariant(char letter);
// The models that take the paper's variants, for messages: `h4-12 (A-D), h4-31c (E-H)`.
std::string variantOwnerList();

const std::vector<MechanismFamily>& mechanismFamilies();  // the paper's robot first
std::string mechanismFamilyList();
// Throws std::invalid_argument "unknown mechanism 'x' (known: ...)".
const MechanismFamily& mechanismFamily(const std::string& name);
// A built-in family by name, or the family of one described robot (a description file): its
// description is its only model and its truth, with BentReadings defects. Throws as
// mechanismFamily, or naming the description file's line and key.
MechanismFamily mechanismFamilyOf(const std::string& name_or_file);
const MechanismFamily& familyWithDefects(SimulatedDefects defects);

// Throws as modelInfo(). The H4 models take their
// nominal geometry from `h4` (model 31 values are its model-12 equivalent; the camera-frame
// model's are expressed in the base frame itself until an identification re-expresses them).
RegisteredModel makeRegisteredModel(const std::string& name, const H4Nominal& h4 = {});

}  // namespace mire::mechanism
