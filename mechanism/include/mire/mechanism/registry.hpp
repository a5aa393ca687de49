#pragma once
// Name -> model registry shared by the CLI (`--model`) and the parameter files (`model:`):
// h4-12, h4-31, h4-31c, delta, delta-legs, gough-stewart (doc/mechanisms.md).
#include <memory>
#include <string>
#include <vector>

#include "mire/mechanism/external.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/parameter_set.hpp"

namespace mire::mechanism {

// What the rest of mire asks of a model by name, so that no caller tests the name itself.
struct ModelInfo {
  std::string name;  // as typed by users
  std::string description;
  std::string label;        // in reports and on the terminal (the name, or what it adds to it)
  bool h4_nominal = false;  // its nominal geometry is an H4's (`--nominal`: a model-12 parameter file)
  std::string variants;     // the paper's Table 2 variants it takes (variants.hpp), "" for none
  char default_variant = 0;
};
const std::vector<ModelInfo>& registeredModels();  // the default model first
std::string registeredModelList();                 // "h4-12, h4-31, ..."
// Throws std::invalid_argument "unknown model 'x' (known: ...)".
const ModelInfo& modelInfo(const std::string& name);
// The model whose variants include `letter` (A–H); throws std::invalid_argument for another letter.
const ModelInfo& modelOfVariant(char letter);

struct RegisteredModel {
  std::string name;
  std::shared_ptr<const Mechanism> mechanism;
  ParameterSet nominal;        // geometric parameters, nominal values, default fixed flags
  ExternalForm external_form;  // the form identify uses for this model
};

// Throws std::invalid_argument "unknown model 'x' (known: ...)". The H4 models take their
// nominal geometry from `h4` (model 31 values are its model-12 equivalent; h4-31c's are
// expressed in the base frame itself until an identification re-expresses them).
RegisteredModel makeRegisteredModel(const std::string& name, const H4Nominal& h4 = {});

}  // namespace mire::mechanism
