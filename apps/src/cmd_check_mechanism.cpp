// `mire check-mechanism MODEL|DESCRIPTION [--nominal FILE]`: what is wrong with a mechanism
// before a campaign is recorded, and what a campaign on it can identify (doc/mechanisms.md,
// "Checking a description"). Glue only: the checks are pipeline::checkMechanism.
#include "commands.hpp"
#include "model_choice.hpp"
#include "output_paths.hpp"
#include "validate.hpp"

#include "mire/mechanism/described.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/pipeline/mechanism_check.hpp"
#include "mire/support/csv.hpp"

#include <iostream>
#include <memory>
#include <string>

namespace mire::app {
namespace {

namespace mech = mire::mechanism;

struct CheckArguments {
  std::string model, nominal;
  bool combinations = false;
};

pipeline::ModelChoice chooseModel(const CheckArguments& args) {
  CommandPaths paths;
  if (mech::isDescriptionFile(args.model)) paths.input_files.push_back({args.model, "MECHANISM"});
  if (!args.nominal.empty()) paths.input_files.push_back({args.nominal, "--nominal"});
  checkCommandPaths(paths);
  // A description that cannot be read is bad input (exit 1, file:line: key), not a usage error.
  if (mech::isDescriptionFile(args.model)) mech::readMechanismDescription(args.model);
  return chooseCommandModel(args.model, "", "", args.nominal);
}

std::string vectorText(const Eigen::VectorXd& values) {
  std::string text;
  for (Eigen::Index k = 0; k < values.size(); ++k) text += (k ? " " : "") + support::formatNumber(values[k], 6);
  return text;
}

void printList(const std::string& label, const std::vector<std::string>& names) {
  std::cout << "  " << label << " (" << names.size() << "):";
  for (const std::string& name : names) std::cout << " " << name;
  std::cout << "\n";
}

void printCheck(const mech::Mechanism& mechanism, const pipeline::MechanismCheck& check, bool show_combinations) {
  std::cout << "mire check-mechanism: " << check.label << ": " << check.joints << " joints ("
            << mechanism.jointColumnNames().front() << ".." << mechanism.jointColumnNames().back() << "), "
            << mech::motionTypeName(mechanism.motionType()) << " platform (" << check.pose_dof << " DoF)\n";
  if (check.home.size()) {
    std::cout << "  home (";
    for (const std::string& name : mechanism.poseComponentNames())
      std::cout << (name == mechanism.poseComponentNames().front() ? "" : " ") << name;
    std::cout << "): " << vectorText(check.home) << "\n  joints at home: " << vectorText(check.home_joints) << "\n";
  }
  if (check.home_condition > 0)
    std::cout << "  condition number of dq/dX at home (unit-norm columns): "
              << support::formatNumber(check.home_condition, 4) << "\n";
  if (check.protocol_poses)
    std::cout << "  protocol poses around home: " << check.protocol_reachable << " of " << check.protocol_poses
              << " reachable (the built-in robot's protocol scaled by "
              << support::formatNumber(check.protocol_scale, 3) << ")\n";
  if (check.gauge) {
    const mech::GaugeAnalysis& gauge = *check.gauge;
    std::cout << "  parameters: " << check.geometric_free << " geometric + " << check.external_free
              << " mounting; expected identifiable rank " << check.expectedRank()
              << " (noise-free campaign at the protocol poses)\n";
    printList("identified alone", gauge.identified);
    printList("identified in combinations only", gauge.combination_only);
    printList("gauge (held at their starting values)", gauge.gauge);
    if (!gauge.no_influence.empty()) printList("of which without any influence", gauge.no_influence);
    if (show_combinations)
      for (const mech::UnidentifiableCombination& c : gauge.report.combinations) std::cout << "  " << c.text() << "\n";
    else if (!gauge.report.combinations.empty())
      std::cout << "  " << gauge.report.combinations.size()
                << " unidentifiable directions (--combinations lists them with their coefficients)\n";
  }
  for (const std::string& warning : check.warnings) std::cout << "warning: " << warning << "\n";
  for (const std::string& error : check.errors) std::cerr << "error: " << error << "\n";
  std::cout << (check.ok()
                    ? "verdict: usable"
                    : "verdict: not usable as described (" + std::to_string(check.errors.size()) + " error(s) above)")
            << "\n";
}

int runCheck(const CheckArguments& args) {
  const pipeline::ModelChoice choice = chooseModel(args);
  const pipeline::MechanismCheck check = pipeline::checkMechanism(choice);
  printCheck(*choice.registered().mechanism, check, args.combinations);
  return check.ok() ? kOk : kFailure;
}

}  // namespace

Runner addCheckMechanismCommand(CLI::App& app) {
  auto args = std::make_shared<CheckArguments>();
  CLI::App* cmd = app.add_subcommand(
      "check-mechanism",
      "Check a mechanism (a description file, doc/mechanisms.md, or a model name) before recording a campaign: "
      "home pose, legs' branches, singularity, protocol reach, expected identifiable rank and gauge");
  cmd->add_option("mechanism", args->model, "A description file (robot.yaml) or " + mech::registeredModelList())->required();
  cmd->add_option("--nominal", args->nominal, "The model's nominal geometry (a parameter or identified file)");
  cmd->add_flag("--combinations", args->combinations, "List every unidentifiable direction with its coefficients");
  return [args] { return runCheck(*args); };
}

}  // namespace mire::app
