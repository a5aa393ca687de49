// `mire fkm`: what an identified model predicts from encoder readings (doc/mechanisms.md):
// the effector pose in the base frame, or the target pose cTm in the camera frame (poses.csv's
// format, with a covariance side file), each with σ propagated from the parameters' covariance.
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>

#include "commands.hpp"
#include "kinematics_files.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/csv.hpp"
#include "mire/support/output_transaction.hpp"
#include "mire/support/progress.hpp"
#include "mire/support/side_files.hpp"
#include "output_paths.hpp"
#include "validate.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

struct FkmArguments {
  std::string params, covariance, joints, output, frame = "base";
};

std::string baseFrameCsv(const mech::Mechanism& m, const std::vector<std::string>& ids,
                         const std::vector<mech::PosePrediction>& predictions) {
  std::ostringstream out;
  out << "pose_id";
  for (const std::string& c : poseColumnNames(m)) out << ',' << c;
  const auto names = m.poseComponentNames();
  const auto units = m.poseComponentUnits();
  for (std::size_t k = 0; k < names.size(); ++k) out << ",sigma_" << names[k] << "_" << mech::displayUnitName(units[k]);
  out << '\n';
  for (std::size_t j = 0; j < ids.size(); ++j) {
    const auto& p = predictions[j];
    out << ids[j];
    for (Eigen::Index k = 0; k < p.pose.size(); ++k) out << ',' << support::formatNumber(p.pose[k]);
    for (Eigen::Index k = 0; k < p.pose.size(); ++k)
      out << ','
          << support::formatNumber(
                 mech::toDisplay(units[static_cast<std::size_t>(k)], std::sqrt(std::max(0.0, p.pose_covariance(k, k)))),
                 6);
    out << '\n';
  }
  return out.str();
}

std::string cameraFrameCsv(const std::vector<std::string>& ids, const std::vector<mech::PosePrediction>& predictions) {
  std::ostringstream out;
  out << "pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,sigma_tx_mm,sigma_ty_mm,sigma_tz_mm,"
         "sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px\n";
  for (std::size_t j = 0; j < ids.size(); ++j) {
    const auto& p = predictions[j];
    out << ids[j] << ",0,0";
    for (int k = 0; k < 6; ++k) out << ',' << support::formatNumber(p.cTm[k]);
    for (int k = 0; k < 6; ++k) {
      const double s = std::sqrt(std::max(0.0, p.cTm_covariance(k, k)));
      out << ',' << support::formatNumber(k < 3 ? s * 1e3 : s * 180.0 / support::kPi, 6);
    }
    out << ",0\n";
  }
  return out.str();
}

std::string covarianceCsv(const std::vector<std::string>& ids, const std::vector<mech::PosePrediction>& predictions) {
  std::ostringstream out;
  out << "pose_id,part,row,tx,ty,tz,rx,ry,rz\n";
  const char* rows[6] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  for (std::size_t j = 0; j < ids.size(); ++j)
    for (int r = 0; r < 6; ++r) {
      out << ids[j] << ",total," << rows[r];
      for (int c = 0; c < 6; ++c) out << ',' << support::formatNumber(predictions[j].cTm_covariance(r, c));
      out << '\n';
    }
  return out.str();
}

int runFkm(const FkmArguments& args) {
  if (args.frame != "base" && args.frame != "camera")
    throw UsageError("--frame '" + args.frame + "': expected base or camera");
  const fs::path output(args.output);
  const fs::path side_out = support::covarianceSidePath(output);  // <stem>_covariance.csv
  CommandPaths paths{{{args.params, "--params"}, {args.joints, "--joints"}}, {}, {{output, "-o"}}, {}};
  if (!args.covariance.empty()) paths.input_files.push_back({args.covariance, "--covariance"});
  if (args.frame == "camera") paths.output_files.push_back({side_out, "the covariance side file of -o"});
  checkCommandPaths(paths);
  std::optional<fs::path> covariance;
  if (!args.covariance.empty()) covariance = fs::path(args.covariance);
  const mech::LoadedPredictionModel loaded = mech::loadPredictionModel(args.params, covariance);
  const mech::Mechanism& m = *loaded.model.mechanism;
  if (args.frame == "camera" && !loaded.has_mounting)
    throw std::runtime_error(args.params + ": no mounting (" + loaded.model.mounting.names().front() + ".." +
                             loaded.model.mounting.names().back() + ") in the file nor in its side file " +
                             support::covarianceSidePath(args.params).string() +
                             ": --frame camera needs the identified mounting");
  const auto rows = mech::readJointsCsv(args.joints, m.jointColumnNames());
  checkRowCount(rows.size(), args.joints, "fkm");
  checkJointUnits(rows, m, args.joints);
  std::vector<std::string> ids, failed;
  std::vector<mech::PosePrediction> predictions;
  support::Progress progress("fkm", rows.size());
  for (const auto& row : rows) {
    progress.advance();
    mech::PosePrediction p = mech::predictPose(loaded.model, row.joints);
    if (!p.converged) {
      failed.push_back(args.joints + ":" + std::to_string(row.line) + ": pose '" + row.pose_id + "': " + p.message);
      continue;
    }
    // Readings outside a leg's stroke (mechanisms that declare one) come from no real robot:
    // the pose they give is a mathematical extension, not a prediction.
    const mech::IkmResult back = m.inverseKinematics(loaded.model.geometric.values(), p.bTe);
    if (!back.withinStroke()) {
      std::string legs;
      for (int j : back.out_of_stroke_joints)
        legs += (legs.empty() ? "" : ", ") + std::to_string(j + 1) + " (" + support::formatNumber(row.joints[j], 6) +
                " " + mech::unitName(m.jointUnits()[static_cast<std::size_t>(j)]) + ")";
      failed.push_back(args.joints + ":" + std::to_string(row.line) + ": pose '" + row.pose_id +
                       "': joint(s) outside their stroke: " + legs);
      continue;
    }
    ids.push_back(row.pose_id);
    predictions.push_back(std::move(p));
  }
  progress.finish();
  if (ids.empty())
    throw std::runtime_error(args.joints + ": the FKM converged for no row (" + failed.front() +
                             "); check the joints' units (the columns are " + m.jointColumnNames().front() + ".." +
                             m.jointColumnNames().back() + ") and that they are of this mechanism");
  // All or nothing (doc/robustness.md): the side file is renamed first, out.csv last, as measure does.
  support::OutputTransaction outputs;
  if (args.frame == "camera") {
    support::writeFileAtomically(outputs.stageFile(side_out), covarianceCsv(ids, predictions));
    support::writeFileAtomically(outputs.stageFile(output), cameraFrameCsv(ids, predictions));
  } else {
    support::writeFileAtomically(outputs.stageFile(output), baseFrameCsv(m, ids, predictions));
  }
  outputs.commit();
  std::cout << "model " << loaded.model.model_name << ": " << ids.size() << " poses predicted ("
            << (args.frame == "camera" ? "camera frame, cTm" : "base frame, effector") << ")"
            << (loaded.has_covariance ? "" : "; no parameter covariance: sigma columns are 0") << "\nwrote "
            << args.output << (args.frame == "camera" ? " and " + side_out.string() : std::string()) << "\n";
  for (const auto& f : failed) std::cerr << "mire fkm: " << f << "\n";
  return failed.empty() ? kOk : kPartialFailure;
}

}  // namespace

Runner addFkmCommand(CLI::App& app) {
  auto args = std::make_shared<FkmArguments>();
  CLI::App* cmd =
      app.add_subcommand("fkm", "predict effector (or target) poses from joint readings with an identified model");
  cmd->add_option("--params", args->params, "identified parameters (YAML written by mire identify)")->required();
  cmd->add_option("--covariance", args->covariance,
                  "parameter covariance side file (default <params stem>_covariance.csv)");
  cmd->add_option("--joints", args->joints, "joint readings (joints.csv with the mechanism's q<i>_rad / q<i>_m columns)")
      ->required();
  cmd->add_option("--frame", args->frame, "base (effector pose in B) or camera (cTm in poses.csv's format)")
      ->capture_default_str();
  cmd->add_option("-o,--output", args->output, "predicted poses (CSV)")->required();
  return [args] { return runFkm(*args); };
}

}  // namespace mire::app
