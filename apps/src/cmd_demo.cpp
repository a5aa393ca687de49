#include "commands.hpp"
#include "demo.hpp"
#include "output_paths.hpp"
#include "report_json.hpp"
#include "simulate_campaign.hpp"
#include "validate.hpp"

#include "mire/mechanism/registry.hpp"

#include <algorithm>
#include <iostream>
#include <memory>

namespace mire::app {
namespace {

// The summary: V3 and the square test (the paper's study), or per model V3 and the positioning
// test, before -> after; then the pose precision.
int printDemo(const DemoResults& results, const std::filesystem::path& output) {
  std::cout << "mire demo: report written to " << (output / "report.md").string() << "\n";
  if (results.paper) {
    const PaperStudy& r = *results.paper;
    std::cout << "  V3 straightness: " << 1e3 * r.nominal_v3_m << " mm (nominal) -> ";
    for (const auto& row : r.pose_counts)
      if (row.size == 15) std::cout << 1e3 * row.v3_mean << " mm (15 poses, mean)";
    std::cout << "\n  square side errors (mm), nominal:";
    for (const double e : r.square_before_mm) std::cout << " " << e;
    std::cout << "; identified:";
    for (const double e : r.square_after_mm) std::cout << " " << e;
    std::cout << "\n";
  }
  for (const auto& m : results.models)
    std::cout << "  " << m.model << ": V3 " << 1e3 * m.v3_before_m << " mm (nominal) -> " << 1e3 * m.v3_after_m
              << " mm; square side RMS " << m.square_rms_before_mm << " mm -> " << m.square_rms_after_mm << " mm\n";
  std::cout << "  pose precision (median σ): " << results.measurement.median_sigma_mm.transpose() << " mm, "
            << results.measurement.median_sigma_deg.transpose() << " deg\n";
  if (results.legs)
    std::cout << pipeline::legsDemoSummary(*results.legs) << "  (" << (output / "legs.md").string() << ")\n";
  return static_cast<int>(kOk);
}

// The families the camera on the effector runs with, for the message that refuses the others.
std::string familiesWithoutPaperVariants() {
  std::string list;
  for (const mechanism::MechanismFamily& family : mechanism::mechanismFamilies())
    if (!pipeline::takesPaperVariants(family)) list += (list.empty() ? "" : ", ") + family.name;
  return list;
}

}  // namespace

DemoResults runDemo(const DemoOptions& options) {
  DemoResults results = pipeline::runDemoStages(options);
  results.files = writeDemoReport(options, results);
  return results;
}

Runner addDemoCommand(CLI::App& app) {
  auto options = std::make_shared<DemoOptions>();
  CLI::App* demo = app.add_subcommand(
      "demo", "Run the paper's H4 experiment end to end in simulation: images -> camera -> poses -> identified robot");
  demo->add_option("-o,--output", options->output, "Output folder (report.md, figures, camera.yaml, poses.csv, ...)")
      ->capture_default_str();
  demo->add_flag("--quick", options->quick, "Smaller run: 15 calibration views, 3 images per pose, fewer repeats");
  demo->add_option("--seed", options->seed, "Seed of the simulated robot, images and random subsets")->capture_default_str();
  std::vector<std::string> mechanisms;
  for (const mechanism::MechanismFamily& family : mechanism::mechanismFamilies()) mechanisms.push_back(family.name);
  const CLI::Validator family_or_description(
      [mechanisms](std::string& value) -> std::string {
        if (mechanism::isDescriptionFile(value) ||
            std::find(mechanisms.begin(), mechanisms.end(), value) != mechanisms.end())
          return {};
        return "unknown mechanism '" + value + "' (known: " + mechanism::mechanismFamilyList() +
               ", or a description file robot.yaml)";
      },
      "MECHANISM|FILE.yaml");
  demo->add_option(
          "--mechanism", options->mechanism,
          "The paper's experiment on the first, or another robot of the table: " + mechanism::mechanismFamilyList() +
              ", or your own robot's description file (doc/demo-mechanisms.md, doc/mechanisms.md)")
      ->check(family_or_description)
      ->capture_default_str();
  demo->add_option("--mounting", options->mounting,
                   "camera-fixed, or camera-on-effector: the camera rides on the effector and looks at the board fixed "
                   "in the workspace (Delta, hexapod, described robots; not the H4)")
      ->capture_default_str();
  demo->add_flag("--legs", options->legs,
                 "gough-stewart, delta: draw the legs as rods and identify from the legs only, the target only and "
                 "both (legs.md; doc/legs.md)");
  return [options, demo] {
    options->command_line = commandLineOf(*demo);
    // The paper's study identifies the paper's variants, whose mounting assumes the camera fixed
    // (paper §4), as `mire identify` and `mire select` refuse them.
    if (cameraOnEffector(options->mounting) && !mechanism::isDescriptionFile(options->mechanism) &&
        pipeline::takesPaperVariants(mechanism::mechanismFamily(options->mechanism)))
      throw UsageError(
          "--mounting camera-on-effector: the H4 demo identifies the paper's variants, which assume the "
          "camera fixed (paper §4); the camera on the effector runs with --mechanism " +
          familiesWithoutPaperVariants() + " or a description file");
    if (options->legs) checkLegsOption(options->mechanism, options->mounting);
    // The output folder (report.md, report.json, ...) is checked before the simulation starts.
    // A description file is read before the simulation starts too.
    CommandPaths paths{{}, {}, {}, {{options->output, "-o"}}};
    if (mechanism::isDescriptionFile(options->mechanism)) paths.input_files = {{options->mechanism, "--mechanism"}};
    checkCommandPaths(paths);
    return printDemo(runDemo(*options), options->output);
  };
}

}  // namespace mire::app
