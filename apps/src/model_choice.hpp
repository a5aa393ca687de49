#pragma once
// The model a command was given (`--model`, `--variant`, `--mounting`) with its nominal geometry
// (`--nominal`; the H4 models' default is datasets/specs/h4_nominal.yaml, the others' built in).
// A bad name or combination is a UsageError naming the option (exit 2); a nominal file that
// cannot be read throws naming the file and line (exit 1).
#include <string>

#include "mire/pipeline/identify.hpp"

namespace mire::app {

pipeline::ModelChoice chooseCommandModel(const std::string& model, const std::string& variant,
                                         const std::string& mounting, const std::string& nominal);

}  // namespace mire::app
