// A command's model and nominal geometry (model_choice.hpp).
#include "model_choice.hpp"

#include <stdexcept>

#include "validate.hpp"

namespace mire::app {

pipeline::ModelChoice chooseCommandModel(const std::string& model, const std::string& variant,
                                         const std::string& mounting, const std::string& nominal) {
  pipeline::ModelChoice choice;
  try {
    choice = pipeline::chooseModel(model, variant);
    if (!mounting.empty()) pipeline::applyMounting(choice, mounting);
  } catch (const std::invalid_argument& error) {  // names the option at fault
    throw UsageError(error.what());
  }
  pipeline::applyNominal(choice, nominal);
  return choice;
}

}  // namespace mire::app
