#pragma once
// `mire identify --observations legs|both --legs legs.csv` (doc/legs.md, doc/cli.md "identify"):
// the identification from the legs' measured axes alone, or with the target poses too
// (pipeline/identify_legs.hpp). Prints the parameters with σ and the fit, writes the parameter file.
#include <string>
#include <vector>

namespace mire::app {

struct LegIdentifyArguments {
  std::string observations;  // "legs" or "both"
  std::string legs, joints, poses, covariances, model, nominal, output;
  std::vector<std::string> fix;
};

// Exit code; bad input throws (UsageError for the command line, std::runtime_error naming the file
// and line for a file).
int runLegIdentify(const LegIdentifyArguments& args);

}  // namespace mire::app
