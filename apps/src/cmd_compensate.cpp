// `mire compensate` (doc/accuracy.md, "Compensation"): what a controller loads so that the
// identified robot reaches the poses it is asked for: joint commands for desired poses (as
// `mire ikm`), or a workspace grid of pose corrections for a controller that runs its nominal
// model and interpolates a table. Frames: the identified base frame (doc/conventions.md).
#include <cmath>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "commands.hpp"
#include "compensate_report.hpp"
#include "joint_commands.hpp"
#include "kinematics_files.hpp"
#include "mire/mechanism/compensation.hpp"
#include "mire/mechanism/controller_fit.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"
#include "mire/support/side_files.hpp"
#include "output_paths.hpp"
#include "validate.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

struct CompensateArguments {
  std::string params, covariance, poses, nominal, workspace, controller_model, output, report;
  double grid = 0.0;
  std::vector<std::string> command_line;
  std::vector<PathArgument> inputs;  // as checked, for the report's provenance
};

// --report DIR: report.json and report.html (compensate_report.hpp), written after the output.
void writeReport(const CompensateArguments& args, CompensateReportData data) {
  if (args.report.empty()) return;
  data.provenance = {args.command_line, args.inputs, {{args.output, "-o"}, {args.report, "--report"}}};
  data.output = args.output;
  fs::create_directories(args.report);
  writeCompensateReportJson(fs::path(args.report) / "report.json", data);
  writeCompensateReportHtml(fs::path(args.report) / "report.html", data);
  std::cout << "wrote " << args.report << "/report.html and report.json\n";
}

// --workspace xmin,xmax,ymin,ymax,zmin,zmax [m].
std::pair<Eigen::Vector3d, Eigen::Vector3d> parseWorkspace(const std::string& text) {
  std::vector<double> v;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size() || !std::isfinite(v.back())) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw UsageError("--workspace '" + text + "': '" + item + "' is not a number");
    }
  }
  if (v.size() != 6) throw UsageError("--workspace '" + text + "': expected xmin,xmax,ymin,ymax,zmin,zmax (metres)");
  return {{v[0], v[2], v[4]}, {v[1], v[3], v[5]}};
}

// The geometry the controller runs: --nominal, or the model's default nominal (doc/mechanisms.md).
Eigen::VectorXd controllerGeometry(const std::string& model, const std::string& nominal) {
  pipeline::ModelChoice choice;
  choice.model = model;
  pipeline::applyNominal(choice, nominal);
  return choice.registered().nominal.values();
}

std::string correctionMapCsv(const mech::LoadedPredictionModel& loaded, const Eigen::VectorXd& controller,
                             const std::vector<Eigen::VectorXd>& grid, std::vector<std::string>& failed,
                             std::vector<Eigen::VectorXd>& sigmas) {
  const mech::Mechanism& m = *loaded.model.mechanism;
  const auto columns = poseColumnNames(m);
  const auto names = m.poseComponentNames();
  const auto units = m.poseComponentUnits();
  std::ostringstream out;
  out << "point_id";
  for (const auto& c : columns) out << ',' << c;
  for (const auto& c : columns) out << ",command_" << c;
  for (std::size_t k = 0; k < names.size(); ++k)
    out << ",sigma_command_" << names[k] << "_" << mech::displayUnitName(units[k]);
  out << '\n';
  for (std::size_t i = 0; i < grid.size(); ++i) {
    const std::string id = "g" + std::to_string(i + 1);
    const mech::PoseCorrection c = mech::correctedCommand(loaded.model, controller, grid[i]);
    if (!c.ok) {
      failed.push_back("grid point '" + id + "' (" + support::formatNumber(grid[i][0], 6) + ", " +
                       support::formatNumber(grid[i][1], 6) + ", " + support::formatNumber(grid[i][2], 6) +
                       " m): " + c.message);
      continue;
    }
    out << id;
    for (Eigen::Index k = 0; k < grid[i].size(); ++k) out << ',' << support::formatNumber(grid[i][k]);
    for (Eigen::Index k = 0; k < c.command.size(); ++k) out << ',' << support::formatNumber(c.command[k]);
    for (Eigen::Index k = 0; k < c.command.size(); ++k)
      out << ','
          << support::formatNumber(mech::toDisplay(units[static_cast<std::size_t>(k)],
                                                   std::sqrt(std::max(0.0, c.command_covariance(k, k)))),
                                   6);
    out << '\n';
    sigmas.push_back(c.command_covariance.diagonal().cwiseMax(0.0).cwiseSqrt());
  }
  return out.str();
}

// The controller model's parameters fitted over a 5 × 5 × 3 grid of the --workspace box.
int runControllerFit(const CompensateArguments& args, const mech::LoadedPredictionModel& loaded) {
  const auto [low, high] = parseWorkspace(args.workspace);
  const mech::RegisteredModel controller = mech::makeRegisteredModel(args.controller_model);
  std::vector<Eigen::VectorXd> workspace;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 3; ++k) {
        Eigen::VectorXd pose = Eigen::VectorXd::Zero(controller.mechanism->poseDof());
        pose.head<3>() = low + (high - low).cwiseProduct(Eigen::Vector3d(i / 4.0, j / 4.0, k / 2.0));
        workspace.push_back(pose);
      }
  const mech::ControllerFit fit = mech::fitControllerModel(loaded.model, controller, workspace);
  if (!fit.converged) throw std::runtime_error("the controller model's fit did not converge");
  if (fit.worst_pose.size() < 3)
    throw std::runtime_error("the identified robot reaches no workspace pose with the fitted controller's commands");
  const auto mm = [](double metres) { return support::formatNumber(metres * 1e3, 4) + " mm"; };
  // The frame F travels with the parameters: the controller commands F·X for a pose X of the
  // identified base frame.
  mech::ParameterSet written = fit.parameters;
  const mech::PoseVector f = mech::toPoseVector(fit.frame);
  const char* keys[6] = {"frame_tx", "frame_ty", "frame_tz", "frame_rx", "frame_ry", "frame_rz"};
  for (int k = 0; k < 6; ++k)
    written.add({keys[k], f[k], k < 3 ? mech::Unit::Metre : mech::Unit::Radian, true,
                 "the controller's base frame from the identified one"});
  mech::writeParameterFile(args.output, written, {}, {{"model", controller.name}},
                           "controller model " + controller.name + " fitted to " + args.params + " over " +
                               std::to_string(fit.poses) + " workspace poses; predicted residual RMS " +
                               mm(fit.rms_position_error) + ", max " + mm(fit.max_position_error));
  std::cout << "controller model " << controller.name << " fitted to " << loaded.model.model_name << " over "
            << fit.poses << " poses of the workspace\n"
            << "predicted residual error (what " << controller.name << " cannot correct): RMS "
            << mm(fit.rms_position_error) << ", max " << mm(fit.max_position_error) << " at ("
            << support::formatNumber(fit.worst_pose[0], 5) << ", " << support::formatNumber(fit.worst_pose[1], 5)
            << ", " << support::formatNumber(fit.worst_pose[2], 5) << ") m; joint residual RMS "
            << support::formatNumber(fit.rms_joint_residual, 4) << '\n';
  if (fit.draws > 0)
    std::cout << "expected on the robot, with the identification's uncertainty (" << fit.draws
              << " robots drawn from its covariance, frame-free): RMS "
              << support::formatNumber(fit.expected_rms_position_error * 1e3, 3) << " ± "
              << support::formatNumber(fit.sigma_rms_position_error * 1e3, 2) << " mm\n";
  else
    std::cout << "no covariance beside " << args.params << ": the error expected on the robot is not stated\n";
  std::cout << "wrote " << args.output << "\n";
  CompensateReportData report;
  report.mode = "controller-model";
  report.model = loaded.model.model_name;
  report.has_covariance = fit.draws > 0;
  report.controller = fit;
  report.controller_model = controller.name;
  writeReport(args, report);
  return kOk;
}

int runCompensate(CompensateArguments args) {
  const int modes = !args.poses.empty() + (args.grid > 0.0) + !args.controller_model.empty();
  if (modes != 1) throw UsageError("give one of --poses, --grid STEP (with --workspace), --controller-model");
  if ((args.grid > 0.0 || !args.controller_model.empty()) && args.workspace.empty())
    throw UsageError("--grid and --controller-model need --workspace xmin,xmax,ymin,ymax,zmin,zmax");
  if (!args.poses.empty() && !args.workspace.empty())
    throw UsageError("--workspace goes with --grid or --controller-model");
  if (args.grid <= 0.0 && !args.nominal.empty()) throw UsageError("--nominal goes with --grid");
  CommandPaths paths{{{args.params, "--params"}}, {}, {{args.output, "-o"}}, {}};
  if (!args.poses.empty()) paths.input_files.push_back({args.poses, "--poses"});
  if (!args.covariance.empty()) paths.input_files.push_back({args.covariance, "--covariance"});
  if (!args.nominal.empty()) paths.input_files.push_back({args.nominal, "--nominal"});
  if (!args.report.empty()) paths.output_folders.push_back({args.report, "--report"});
  checkCommandPaths(paths);
  args.inputs = paths.input_files;
  std::optional<fs::path> covariance;
  if (!args.covariance.empty()) covariance = fs::path(args.covariance);
  const mech::LoadedPredictionModel loaded = mech::loadPredictionModel(args.params, covariance);
  if (loaded.has_covariance && args.covariance.empty())  // read beside the parameters: an input too
    args.inputs.push_back({support::covarianceSidePath(args.params), "the covariance side file"});
  const mech::Mechanism& m = *loaded.model.mechanism;
  const std::string sigma_note = loaded.has_covariance ? "" : "; no parameter covariance: sigma columns are 0";
  if (!args.controller_model.empty()) return runControllerFit(args, loaded);
  if (!args.poses.empty()) {
    const JointCommandTable table = jointCommandTable(loaded.model, readEffectorCsv(args.poses, m), args.poses);
    for (const auto& u : table.unreachable) std::cerr << "mire compensate: " << u << "\n";
    if (table.written == 0) throw std::runtime_error(args.poses + ": no reachable pose; nothing written");
    support::writeFileAtomically(args.output, table.csv);
    std::cout << "model " << loaded.model.model_name << ": joint commands for " << table.written << " poses"
              << (table.unreachable.empty() ? ""
                                            : ", " + std::to_string(table.unreachable.size()) + " not (named above)")
              << sigma_note << "\nwrote " << args.output << "\n";
    CompensateReportData report{{},
                                "poses",
                                loaded.model.model_name,
                                "",
                                m.jointColumnNames(),
                                m.jointUnits(),
                                table.sigmas,
                                table.unreachable,
                                loaded.has_covariance,
                                std::nullopt,
                                ""};
    writeReport(args, report);
    return table.unreachable.empty() ? kOk : kPartialFailure;
  }
  const auto [low, high] = parseWorkspace(args.workspace);
  std::vector<Eigen::VectorXd> grid;
  try {
    grid = mech::workspaceGrid(m, low, high, args.grid);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--grid/--workspace: ") + e.what());
  }
  const Eigen::VectorXd controller = controllerGeometry(loaded.model.model_name, args.nominal);
  std::vector<std::string> failed;
  std::vector<Eigen::VectorXd> sigmas;
  const std::string csv = correctionMapCsv(loaded, controller, grid, failed, sigmas);
  for (const auto& f : failed) std::cerr << "mire compensate: " << f << "\n";
  if (failed.size() == grid.size()) throw std::runtime_error("no grid point is reachable; nothing written");
  support::writeFileAtomically(args.output, csv);
  std::cout << "model " << loaded.model.model_name << ": pose corrections for the "
            << (args.nominal.empty() ? "nominal" : args.nominal) << " controller at " << grid.size() - failed.size()
            << " grid points" << (failed.empty() ? "" : ", " + std::to_string(failed.size()) + " not (named above)")
            << sigma_note << "\nwrote " << args.output << "\n";
  CompensateReportData report{{},
                              "grid",
                              loaded.model.model_name,
                              "",
                              m.poseComponentNames(),
                              m.poseComponentUnits(),
                              sigmas,
                              failed,
                              loaded.has_covariance,
                              std::nullopt,
                              ""};
  writeReport(args, report);
  return failed.empty() ? kOk : kPartialFailure;
}

}  // namespace

Runner addCompensateCommand(CLI::App& app) {
  auto args = std::make_shared<CompensateArguments>();
  CLI::App* cmd = app.add_subcommand(
      "compensate", "what a controller loads: joint commands for desired poses, or a grid of pose corrections");
  cmd->add_option("--params", args->params, "identified parameters (YAML written by mire identify)")->required();
  cmd->add_option("--covariance", args->covariance,
                  "parameter covariance side file (default <params stem>_covariance.csv)");
  cmd->add_option("--poses", args->poses,
                  "desired effector poses in the identified base frame (pose_id,x_m,y_m,z_m[,theta_rad | "
                  ",rx_rad,ry_rad,rz_rad]): joint commands");
  cmd->add_option("--grid", args->grid, "grid step [m]: pose corrections over --workspace (correction_map.csv)");
  cmd->add_option("--workspace", args->workspace, "the grid's box in the base frame: xmin,xmax,ymin,ymax,zmin,zmax [m]");
  cmd->add_option("--controller-model", args->controller_model,
                  "the model the controller runs (a model name or description file): its parameters fitted over "
                  "--workspace (controller.yaml)");
  cmd->add_option("--nominal", args->nominal,
                  "the geometry the controller runs (parameter YAML; default the model's nominal)");
  cmd->add_option("-o,--output", args->output,
                  "commands.csv (--poses), correction_map.csv (--grid) or controller.yaml (--controller-model)")
      ->required();
  cmd->add_option("--report", args->report,
                  "report folder (report.html: the result with the commands' sigma; report.json)");
  return [args, cmd] {
    args->command_line = commandLineOf(*cmd);
    return runCompensate(*args);
  };
}

}  // namespace mire::app
