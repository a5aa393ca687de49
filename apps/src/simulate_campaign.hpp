#pragma once
// `mire simulate campaign` (cmd_simulate_campaign.cpp): the demo's whole rendered campaign of an
// H4, a Delta or a hexapod on disk, for the user to run calibrate -> measure -> identify by hand.
#include <string>

#include "commands.hpp"

namespace mire::app {

// A subcommand of `mire simulate` and its runner (called when the subcommand was parsed).
struct SimulateSubcommand {
  CLI::App* command = nullptr;
  Runner run;
};

SimulateSubcommand addSimulateCampaignSubcommand(CLI::App& simulate);
// The campaign's robot: a family of the table (else UsageError listing them) or a description
// file (read: its errors name file, line and key).
void checkCampaignMechanism(const std::string& mechanism);
// --legs: the hexapod and the Delta with the camera fixed (else UsageError).
void checkLegsOption(const std::string& mechanism, const std::string& mounting);
// `mire simulate iso9283` (cmd_simulate_iso9283.cpp): a campaign's robot runs an identified
// model's commands through the ISO 9283 test (after compensation).
SimulateSubcommand addSimulateIso9283Subcommand(CLI::App& simulate);

}  // namespace mire::app
