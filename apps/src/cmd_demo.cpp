#include "commands.hpp"
#include "demo.hpp"
#include "output_paths.hpp"
#include "report_json.hpp"

#include <iostream>
#include <memory>

namespace mire::app {

Runner addDemoCommand(CLI::App& app) {
  auto options = std::make_shared<DemoOptions>();
  CLI::App* demo = app.add_subcommand(
      "demo", "Run the paper's H4 experiment end to end in simulation: images -> camera -> poses -> identified robot");
  demo->add_option("-o,--output", options->output, "Output folder (report.md, figures, camera.yaml, poses.csv, ...)")
      ->capture_default_str();
  demo->add_flag("--quick", options->quick, "Smaller run: 15 calibration views, 3 images per pose, fewer repeats");
  demo->add_option("--seed", options->seed, "Seed of the simulated robot, images and random subsets")->capture_default_str();
  return [options, demo] {
    options->command_line = commandLineOf(*demo);
    // The output folder (report.md, report.json, ...) is checked before the simulation starts.
    checkCommandPaths({{}, {}, {}, {{options->output, "-o"}}});
    const DemoResults results = runDemo(*options);
    std::cout << "mire demo: report written to " << (options->output / "report.md").string() << "\n";
    std::cout << "  V3 straightness: " << 1e3 * results.nominal_v3_m << " mm (nominal) -> ";
    for (const auto& row : results.pose_counts)
      if (row.size == 15) std::cout << 1e3 * row.v3_mean << " mm (15 poses, mean)";
    std::cout << "\n  square side errors (mm), nominal:";
    for (const double e : results.square_before_mm) std::cout << " " << e;
    std::cout << "; identified:";
    for (const double e : results.square_after_mm) std::cout << " " << e;
    std::cout << "\n  pose precision (median σ): " << results.measurement.median_sigma_mm.transpose() << " mm, "
              << results.measurement.median_sigma_deg.transpose() << " deg\n";
    return static_cast<int>(kOk);
  };
}

}  // namespace mire::app
