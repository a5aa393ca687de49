// mire: vision-based kinematic calibration of parallel mechanisms.
#include "commands.hpp"
#include "validate.hpp"

#include "mire/support/output_transaction.hpp"

#include <exception>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

// What can throw outside the try blocks is CLI11 refusing the option table, a programming
// error the apps tests catch; it should abort.
// NOLINTNEXTLINE(bugprone-exception-escape)
int main(int argc, char** argv) {
  using namespace mire::app;
  CLI::App app{"mire: calibrate a camera, measure target poses, identify a parallel mechanism"};
  app.name("mire");
  app.set_version_flag("--version", versionString());
  app.require_subcommand(1);
  app.allow_extras(false);

  const std::vector<std::pair<std::string, Runner>> commands = {{"calibrate", addCalibrateCommand(app)},
                                                                {"measure", addMeasureCommand(app)},
                                                                {"identify", addIdentifyCommand(app)},
                                                                {"simulate", addSimulateCommand(app)},
                                                                {"demo", addDemoCommand(app)},
                                                                {"convert", addConvertCommand(app)},
                                                                {"fkm", addFkmCommand(app)},
                                                                {"ikm", addIkmCommand(app)},
                                                                {"plan", addPlanCommand(app)},
                                                                {"select", addSelectCommand(app)},
                                                                {"check-mechanism", addCheckMechanismCommand(app)},
                                                                {"accuracy", addAccuracyCommand(app)},
                                                                {"compensate", addCompensateCommand(app)},
                                                                {"report", addReportCommand(app)}};

  // Name an unknown subcommand plainly (CLI11 would only say that one is required).
  if (argc > 1 && argv[1][0] != '-') {
    const std::string word = argv[1];
    bool known = false;
    for (const auto& command : commands) known = known || command.first == word;
    if (!known) {
      std::cerr << "mire: unknown subcommand '" << word << "' (run 'mire --help' for the list)\n";
      return kUsage;
    }
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // One line, then a hint: scripts can grep the first line.
    std::cerr << "mire: " << e.what() << "\n(run 'mire --help' for usage)\n";
    return kUsage;
  }

  for (const auto& [name, run] : commands) {
    if (!app.got_subcommand(name)) continue;
    mire::support::installInterruptCleanup();  // an interrupted run leaves no temporaries
    try {
      return run();
    } catch (const UsageError& e) {
      std::cerr << "mire " << name << ": " << e.what() << "\n(run 'mire " << name << " --help' for usage)\n";
      return kUsage;
    } catch (const std::bad_alloc&) {
      std::cerr << "mire " << name << ": error: out of memory (see doc/limits.md for the sizes mire handles)\n";
      return kFailure;
    } catch (const std::exception& e) {
      std::cerr << "mire " << name << ": error: " << e.what() << "\n";
      return kFailure;
    }
  }
  return kUsage;
}
