#pragma once
// Each subcommand of `mire` lives in its own file and registers itself on the CLI11 app.
#include <CLI/CLI.hpp>

#include <functional>
#include <string>

namespace mire::app {

// Process exit codes, documented in README.md.
enum ExitCode : int {
  kOk = 0,
  kFailure = 1,        // bad input or a failed computation: nothing (or nothing more) written
  kUsage = 2,          // wrong command line, or a subcommand that is not implemented yet
  kPartialFailure = 3  // some items (poses, views) failed; the others were processed and written
};

using Runner = std::function<int()>;

// Each function adds its subcommand (options bound to captured state) and returns the
// function that runs it once the command line is parsed.
Runner addCalibrateCommand(CLI::App& app);
Runner addMeasureCommand(CLI::App& app);
Runner addIdentifyCommand(CLI::App& app);
Runner addSimulateCommand(CLI::App& app);
Runner addDemoCommand(CLI::App& app);
Runner addConvertCommand(CLI::App& app);
Runner addFkmCommand(CLI::App& app);
Runner addIkmCommand(CLI::App& app);
Runner addPlanCommand(CLI::App& app);
Runner addSelectCommand(CLI::App& app);
Runner addCheckMechanismCommand(CLI::App& app);
Runner addAccuracyCommand(CLI::App& app);
Runner addCompensateCommand(CLI::App& app);
Runner addReportCommand(CLI::App& app);

// The version string printed by `mire --version`.
std::string versionString();

}  // namespace mire::app
