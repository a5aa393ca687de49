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

struct ModelInfo {
  std::string name;  // as typed by users
  std::string description;
};
const std::vector<ModelInfo>& registeredModels();
std::string registeredModelList();  // "h4-12, h4-31, ..."

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
