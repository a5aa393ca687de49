// `mire ikm`: joint commands for desired effector poses in the base frame with an identified
// model (the compensation a controller needs), σ from the parameters' covariance; unreachable
// poses are named (doc/mechanisms.md).
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>

#include "commands.hpp"
#include "kinematics_files.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"
#include "mire/support/progress.hpp"
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
  const auto rows = readEffectorCsv(args.poses, m);
  checkRowCount(rows.size(), args.poses, "ikm");
  support::Progress progress("ikm", rows.size());
  const auto columns = m.jointColumnNames();
  std::ostringstream out;
  out << "pose_id";
  for (const auto& c : columns) out << ',' << c;
  for (const auto& c : columns) out << ",sigma_" << c;
  out << '\n';
  std::vector<std::string> unreachable;
  std::size_t written = 0;
  for (const auto& row : rows) {
    progress.advance();
    const mech::JointPrediction p = mech::predictJointCommands(loaded.model, m.poseToTransform(row.pose));
    if (!p.ikm.reachable()) {
      std::string legs;
      for (int j : p.ikm.unreachable_joints) legs += (legs.empty() ? "" : ", ") + std::to_string(j + 1);
      unreachable.push_back(args.poses + ":" + std::to_string(row.line) + ": pose '" + row.id +
                            "' is unreachable (joint(s) " + legs + ")");
      continue;
    }
    if (!p.ikm.withinStroke()) {  // the command would drive a leg past its end stop
      std::string legs;
      for (int j : p.ikm.out_of_stroke_joints)
        legs += (legs.empty() ? "" : ", ") + std::to_string(j + 1) + " (" + support::formatNumber(p.ikm.joints[j]) +
                " " + mech::unitName(m.jointUnits()[static_cast<std::size_t>(j)]) + ")";
      unreachable.push_back(args.poses + ":" + std::to_string(row.line) + ": pose '" + row.id +
                            "' is outside the stroke of joint(s) " + legs);
      continue;
    }
    out << row.id;
    for (Eigen::Index k = 0; k < p.ikm.joints.size(); ++k) out << ',' << support::formatNumber(p.ikm.joints[k]);
    for (Eigen::Index k = 0; k < p.ikm.joints.size(); ++k)
      out << ',' << support::formatNumber(std::sqrt(std::max(0.0, p.covariance(k, k))), 6);
    out << '\n';
    ++written;
  }
  progress.finish();
  for (const auto& u : unreachable) std::cerr << "mire ikm: " << u << "\n";
  if (written == 0) throw std::runtime_error(args.poses + ": no reachable pose; nothing written");
  support::writeFileAtomically(args.output, out.str());
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
