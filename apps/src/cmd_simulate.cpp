// `mire simulate calibration|poses --spec SPEC.yaml -o DIR`: synthetic image sets with their
// ground truth (doc/simulation.md); `mire simulate campaign` is in cmd_simulate_campaign.cpp. Glue only: the
// spec and the generation live in mire::datasets.
#include "commands.hpp"
#include "output_paths.hpp"
#include "simulate_campaign.hpp"
#include "simulation_checks.hpp"
#include "validate.hpp"

#include "mire/datasets/simulation.hpp"
#include "mire/support/output_transaction.hpp"
#include "mire/support/progress.hpp"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

namespace mire::app {
namespace {

struct SimulateOptions {
  std::string spec;
  std::string output;
};

void addSpecOptions(CLI::App* command, SimulateOptions* options) {
  command->add_option("--spec", options->spec, "Simulation spec (YAML, see datasets/specs/)")->required();
  command->add_option("-o,--output", options->output, "Output folder (created if needed)")->required();
}

// The output folder is written whole or not at all: rendered into a temporary folder, then
// renamed. An existing folder is replaced only when it is empty or a previous simulation.
void checkOutputFolder(const SimulateOptions& options) {
  checkCommandPaths({{{options.spec, "--spec"}}, {}, {}, {{options.output, "-o"}}});
  const std::filesystem::path out = options.output;
  if (std::filesystem::is_directory(out) && !std::filesystem::is_empty(out) &&
      !std::filesystem::exists(out / "truth.yaml"))
    throw UsageError("-o '" + options.output +
                     "': exists, holds files and is not a previous simulation (no truth.yaml): "
                     "choose a new or empty folder");
}

int runSimulation(const SimulateOptions& options, bool calibration) {
  checkOutputFolder(options);
  const datasets::SimulationSpec spec = datasets::readSimulationSpec(options.spec);
  checkSimulationSpec(spec, !calibration);
  const std::size_t total = calibration ? static_cast<std::size_t>(spec.calibration.views * spec.images_per_view)
                                        : spec.poses.size() * static_cast<std::size_t>(spec.images_per_pose);
  support::Progress progress(calibration ? "rendering views" : "rendering poses", total);
  const auto advance = [&](std::size_t, std::size_t) { progress.advance(); };
  support::OutputTransaction outputs;
  const std::filesystem::path staged =
      outputs.stageFolder(options.output, support::OutputTransaction::FolderCommit::ReplaceWhole);
  const datasets::SimulationResult result = calibration ? datasets::simulateCalibration(spec, staged, advance)
                                                        : datasets::simulatePoses(spec, staged, advance);
  progress.finish();
  outputs.commit();
  std::cout << "mire simulate " << (calibration ? "calibration" : "poses") << ": wrote " << result.images << " images of "
            << result.views_or_poses << (calibration ? " views" : " poses") << " to " << options.output << " ("
            << std::lround(100.0 * result.visible_fraction) << " % of the features visible; truth in truth.yaml)\n";
  return kOk;
}

}  // namespace

Runner addSimulateCommand(CLI::App& app) {
  CLI::App* simulate = app.add_subcommand("simulate", "Render synthetic image sets with exact ground truth");
  simulate->require_subcommand(1);
  auto calibration_options = std::make_shared<SimulateOptions>();
  auto poses_options = std::make_shared<SimulateOptions>();
  CLI::App* calibration =
      simulate->add_subcommand("calibration", "Calibration views: DIR/images/view_XXX.png + DIR/truth.yaml");
  addSpecOptions(calibration, calibration_options.get());
  CLI::App* poses = simulate->add_subcommand(
      "poses", "Images per pose: DIR/poses/<pose_id>/img_XX.png + DIR/truth.yaml + DIR/truth_poses.csv");
  addSpecOptions(poses, poses_options.get());
  const SimulateSubcommand campaign = addSimulateCampaignSubcommand(*simulate);
  const SimulateSubcommand iso9283 = addSimulateIso9283Subcommand(*simulate);
  return [calibration, calibration_options, poses_options, campaign, iso9283] {
    if (campaign.command->parsed()) return campaign.run();
    if (iso9283.command->parsed()) return iso9283.run();
    const bool is_calibration = calibration->parsed();
    return runSimulation(is_calibration ? *calibration_options : *poses_options, is_calibration);
  };
}

}  // namespace mire::app
