// `mire ikm`: joint commands for desired effector poses in the base frame with an identified
// model (the compensation a controller needs), σ from the parameters' covariance; unreachable
// poses are named (doc/mechanisms.md).
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "joint_commands.hpp"
#include "kinematics_files.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"
#include "output_paths.hpp"
#include "validate.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

struct IkmArguments {
  std::string params, covariance, poses, output;
};

int runIkm(const IkmArguments& args) {
  CommandPaths paths{{{args.params, "--params"}, {args.poses, "--poses"}}, {}, {{args.output, "-o"}}, {}};
  if (!args.covariance.empty()) paths.input_files.push_back({args.covariance, "--covariance"});
  checkCommandPaths(paths);
  std::optional<fs::path> covariance;
  if (!args.covariance.empty()) covariance = fs::path(args.covariance);
  const mech::LoadedPredictionModel loaded = mech::loadPredictionModel(args.params, covariance);
  const mech::Mechanism& m = *loaded.model.mechanism;
  const std::vector<EffectorRow> rows = readEffectorCsv(args.poses, m);
  checkRowCount(rows.size(), args.poses, "ikm");
  const JointCommandTable table = jointCommandTable(loaded.model, rows, args.poses);
  const std::vector<std::string>& unreachable = table.unreachable;
  const std::size_t written = table.written;
  for (const auto& u : unreachable) std::cerr << "mire ikm: " << u << "\n";
  if (written == 0) throw std::runtime_error(args.poses + ": no reachable pose; nothing written");
  support::writeFileAtomically(args.output, table.csv);
  std::cout << "model " << loaded.model.model_name << ": joint commands for " << written << " poses"
            << (unreachable.empty()
                    ? ""
                    : ", " + std::to_string(unreachable.size()) + " unreachable or outside the strokes (named above)")
            << (loaded.has_covariance ? "" : "; no parameter covariance: sigma columns are 0") << "\nwrote "
            << args.output << "\n";
  return unreachable.empty() ? kOk : kPartialFailure;
}

}  // namespace

Runner addIkmCommand(CLI::App& app) {
  auto args = std::make_shared<IkmArguments>();
  CLI::App* cmd = app.add_subcommand("ikm", "joint commands for desired effector poses with an identified model");
  cmd->add_option("--params", args->params, "identified parameters (YAML written by mire identify)")->required();
  cmd->add_option("--covariance", args->covariance,
                  "parameter covariance side file (default <params stem>_covariance.csv)");
  cmd->add_option("--poses", args->poses,
                  "desired effector poses in the base frame (pose_id,x_m,y_m,z_m[,theta_rad | ,rx_rad,ry_rad,rz_rad])")
      ->required();
  cmd->add_option("-o,--output", args->output, "joint commands (joints.csv with sigma_ columns)")->required();
  return [args] { return runIkm(*args); };
}

}  // namespace mire::app
