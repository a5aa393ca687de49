// `mire accuracy`: the ISO 9283 test of a robot (doc/accuracy.md): commanded poses grouped by
// position, their measured target poses turned into attained effector poses through the
// identified mounting; pose accuracy and repeatability, distance accuracy, straightness, each
// with the part the measurement's own noise explains.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>

#include "accuracy_report.hpp"
#include "commands.hpp"
#include "kinematics_files.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/pipeline/accuracy.hpp"
#include "mire/support/csv.hpp"
#include "mire/support/output_transaction.hpp"
#include "mire/support/side_files.hpp"
#include "output_paths.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

struct AccuracyArguments {
  std::string params, covariance, commanded, poses, lines, output, report;
  std::vector<std::string> command_line;
};

// The measured poses and, beside them, `mire measure`'s covariance side file when it exists.
std::vector<mech::PoseRow> readMeasured(const fs::path& poses) {
  const fs::path side = support::covarianceSidePath(poses);
  return mech::readPosesCsv(poses, fs::exists(side) ? std::optional<fs::path>(side) : std::nullopt);
}

std::vector<pipeline::LinePose> readLinePoses(const fs::path& path) {
  const std::vector<mech::PoseRow> rows = readMeasured(path);
  const support::CsvTable table = support::readCsv(path);
  const std::size_t line_col = table.column("line_id");
  std::vector<pipeline::LinePose> out;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const std::string& id = table.rows[r][line_col];
    if (id.empty()) throw std::runtime_error(table.where(r) + ": empty line_id");
    out.push_back({id, rows[r]});
  }
  return out;
}

std::string mm(double metres) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", metres * 1e3);
  return text;
}

// The result first: the mean AP_p with its σ (positions independent) and the worst RP_l.
void printLead(const pipeline::AccuracyResult& r) {
  double sum = 0.0, variance = 0.0, worst_rp = 0.0;
  for (const auto& p : r.positions)
    sum += p.ap_p, variance += p.sigma_ap_p * p.sigma_ap_p, worst_rp = std::max(worst_rp, p.rp_l);
  const double n = static_cast<double>(std::max<std::size_t>(1, r.positions.size()));
  std::cout << "pose accuracy AP_p " << mm(sum / n) << " mm +/- " << mm(std::sqrt(variance) / n) << " mm (mean of "
            << r.positions.size() << " positions, 1 sigma), largest repeatability RP_l " << mm(worst_rp) << " mm\n";
}

void printSummary(const pipeline::AccuracyResult& r) {
  std::cout << "position  cycles  AP_p [mm] (sigma, noise-only p95)   RP_l [mm] (noise-only p95)\n";
  for (const auto& p : r.positions)
    std::cout << "  " << p.position << "  " << p.cycles << "  " << mm(p.ap_p) << " (" << mm(p.sigma_ap_p) << ", "
              << mm(p.noise_ap_p.p95) << ")   " << mm(p.rp_l) << " (" << mm(p.noise_rp_l.p95) << ")\n";
  for (const auto& d : r.distances)
    std::cout << "  distance " << d.from << "-" << d.to << ": AD_p " << mm(d.ad_p) << " mm (sigma " << mm(d.sigma_ad_p)
              << "), RD " << mm(d.rd) << " mm\n";
  for (const auto& l : r.lines)
    std::cout << "  line " << l.line << ": straightness RMS " << mm(l.rms) << " mm, max " << mm(l.max)
              << " mm (noise-only RMS " << mm(l.noise_rms.mean) << " mm)\n";
  const auto warn = [](const std::string& where, const std::vector<std::string>& warnings) {
    for (const auto& w : warnings) std::cout << "warning: " << where << ": " << w << "\n";
  };
  for (const auto& p : r.positions) warn("position " + p.position, p.warnings);
  for (const auto& d : r.distances) warn("distance " + d.from + "-" + d.to, d.warnings);
  for (const auto& l : r.lines) warn("line " + l.line, l.warnings);
}

int runAccuracy(const AccuracyArguments& args) {
  CommandPaths paths{{{args.params, "--params"}, {args.commanded, "--commanded"}, {args.poses, "--poses"}},
                     {},
                     {{args.output, "-o"}},
                     {}};
  if (!args.covariance.empty()) paths.input_files.push_back({args.covariance, "--covariance"});
  if (!args.lines.empty()) paths.input_files.push_back({args.lines, "--lines"});
  if (!args.report.empty()) paths.output_folders.push_back({args.report, "--report"});
  checkCommandPaths(paths);
  std::optional<fs::path> covariance;
  if (!args.covariance.empty()) covariance = fs::path(args.covariance);
  const mech::LoadedPredictionModel loaded = mech::loadPredictionModel(args.params, covariance);
  if (!loaded.has_mounting)
    throw std::runtime_error(args.params + ": no mounting (tx_CB..rz_EM) in the file nor in its side file " +
                             support::covarianceSidePath(args.params).string() +
                             ": the attained poses need the identified mounting");
  const mech::Mechanism& m = *loaded.model.mechanism;
  std::vector<pipeline::CommandedPose> commanded;
  for (const EffectorRow& row : readEffectorCsv(args.commanded, m, "position"))
    commanded.push_back({row.id, row.group, m.poseToTransform(row.pose)});
  const std::vector<mech::PoseRow> measured = readMeasured(args.poses);
  const std::vector<pipeline::LinePose> lines =
      args.lines.empty() ? std::vector<pipeline::LinePose>{} : readLinePoses(args.lines);
  const pipeline::AccuracyResult result =
      pipeline::evaluateAccuracy(loaded.model, commanded, measured, args.poses, lines);
  ReportProvenance provenance{args.command_line, paths.input_files, paths.output_files};
  // All or nothing (doc/robustness.md): accuracy.json, then the report.
  support::OutputTransaction outputs;
  writeAccuracyJson(outputs.stageFile(args.output), provenance, loaded.model.model_name, result);
  if (!args.report.empty())
    writeAccuracyReportHtml(outputs.stageFolder(args.report) / "report.html", provenance, loaded.model.model_name,
                            result);
  outputs.commit();
  printLead(result);
  std::cout << "model " << loaded.model.model_name << ": ISO 9283 figures from " << result.cycles_used
            << " measured cycles at " << result.positions.size() << " positions\n";
  printSummary(result);
  for (const auto& id : result.unmeasured)
    std::cerr << "mire accuracy: " << args.commanded << ": pose '" << id << "' has no measured pose (left out)\n";
  std::cout << "wrote " << args.output << (args.report.empty() ? "" : " and " + args.report + "/report.html") << "\n";
  return result.unmeasured.empty() ? kOk : kPartialFailure;
}

}  // namespace

Runner addAccuracyCommand(CLI::App& app) {
  auto args = std::make_shared<AccuracyArguments>();
  CLI::App* cmd =
      app.add_subcommand("accuracy", "ISO 9283 pose accuracy and repeatability of a robot from measured cycles");
  cmd->add_option("--params", args->params, "identified parameters (YAML written by mire identify): the mounting")
      ->required();
  cmd->add_option("--covariance", args->covariance,
                  "parameter covariance side file (default <params stem>_covariance.csv)");
  cmd->add_option("--commanded", args->commanded,
                  "commanded effector poses in the base frame (pose_id,position,x_m,y_m,z_m[,theta_rad | "
                  ",rx_rad,ry_rad,rz_rad]); cycle j of a position is its j-th row")
      ->required();
  cmd->add_option("--poses", args->poses, "measured target poses of the cycles (poses.csv, by pose_id)")->required();
  cmd->add_option("--lines", args->lines, "measured poses along straight-line motions (poses.csv columns + line_id)");
  cmd->add_option("-o,--output", args->output, "the figures (accuracy.json)")->required();
  cmd->add_option("--report", args->report, "report folder (report.html: the figures per position with their sigma)");
  return [args, cmd] {
    args->command_line = commandLineOf(*cmd);
    return runAccuracy(*args);
  };
}

}  // namespace mire::app
