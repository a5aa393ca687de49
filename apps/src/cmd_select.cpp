// `mire select`: which model to identify (doc/plan-and-select.md). Every candidate
// model/variant is identified on the campaign and scored by k-fold cross-validated joint
// residual, with AIC/BIC, nested F-tests, condition number and rank beside it; the simplest
// model within one standard error of the best CV score is recommended. The last line printed
// is exactly "recommended: <name>".
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <regex>
#include <sstream>

#include "commands.hpp"
#include "mire/mechanism/model_selection.hpp"
#include "mire/pipeline/pose_set.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"
#include "mire/support/output_transaction.hpp"
#include "output_paths.hpp"
#include "plan_inputs.hpp"
#include "report_html.hpp"
#include "report_json.hpp"
#include "validate.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

struct SelectArguments {
  std::string poses, joints, lines, nominal, models, report, covariances;
  std::string mounting = "camera-fixed";  // or camera-on-effector (doc/mechanisms.md, "Camera on the effector")
  int folds = 10;
  unsigned seed = 1;
  std::vector<std::string> command_line;  // as parsed, for report.json
};

// The joint columns of joints.csv's header (q<i>_rad or q<i>_m): the mechanism family.
std::pair<int, mech::Unit> jointColumns(const fs::path& joints_csv) {
  std::ifstream in(joints_csv);
  std::string header;
  if (!std::getline(in, header)) throw std::runtime_error(joints_csv.string() + ":1: empty file");
  const std::regex q("q[0-9]+_(rad|m)");
  int count = 0;
  mech::Unit unit = mech::Unit::Radian;
  std::stringstream columns(header);
  for (std::string c; std::getline(columns, c, ',');) {
    while (!c.empty() && (c.back() == '\r' || c.back() == ' ')) c.pop_back();
    std::smatch m;
    if (!std::regex_match(c, m, q)) continue;
    ++count;
    unit = m[1] == "m" ? mech::Unit::Metre : mech::Unit::Radian;
  }
  if (count == 0) throw std::runtime_error(joints_csv.string() + ":1: no joint column (q1_rad or q1_m ...)");
  return {count, unit};
}

std::string scoresCsv(const mech::SelectionResult& r) {
  std::ostringstream out;
  out << "model,ok,parameters,cv_rms,cv_rms_se,fit_rms,aic,bic,condition,rank,v3_m,recommended\n";
  for (std::size_t i = 0; i < r.scores.size(); ++i) {
    const mech::ModelScore& s = r.scores[i];
    out << s.label << ',' << (s.ok ? 1 : 0) << ',' << s.parameters << ',' << support::formatNumber(s.cv_rms(), 8) << ','
        << support::formatNumber(s.cv_rms_se(), 8) << ',' << support::formatNumber(s.fit_rms, 8) << ','
        << support::formatNumber(s.aic, 8) << ',' << support::formatNumber(s.bic, 8) << ','
        << support::formatNumber(s.condition, 6) << ',' << s.rank << ','
        << (std::isfinite(s.v3) ? support::formatNumber(s.v3, 8) : std::string()) << ','
        << (static_cast<int>(i) == r.recommended ? 1 : 0) << '\n';
  }
  return out.str();
}

// Every candidate with the camera where the poses were measured from: on the effector, each is
// identified in the camera-on-effector form (as `mire identify --mounting`); the H4's variants
// assume the camera fixed (paper §4) and are refused by name.
std::vector<mech::SelectionCandidate> candidatesWithMounting(std::vector<mech::SelectionCandidate> candidates,
                                                             const std::string& mounting) {
  const bool on_effector = cameraOnEffector(mounting);
  for (mech::SelectionCandidate& c : candidates) c.model = withMounting(c.model, on_effector, "candidate " + c.label);
  return candidates;
}

int runSelect(const SelectArguments& args) {
  CommandPaths paths{{{args.poses, "--poses"}, {args.joints, "--joints"}}, {}, {}, {}};
  if (!args.covariances.empty()) paths.input_files.push_back({args.covariances, "--pose-covariances"});
  if (!args.lines.empty()) paths.input_files.push_back({args.lines, "--lines"});
  if (!args.nominal.empty()) paths.input_files.push_back({args.nominal, "--nominal"});
  if (!args.report.empty()) paths.output_folders.push_back({args.report, "--report"});
  checkCommandPaths(paths);
  const auto [joint_count, unit] = jointColumns(args.joints);
  const std::string models = args.models.empty() ? mech::defaultSelectionModels(joint_count, unit) : args.models;
  const auto candidates =
      candidatesWithMounting(mech::parseSelectionCandidates(
                                 models, [&](const std::string& name) { return readDesignModel(name, args.nominal); }),
                             args.mounting);
  const mech::Mechanism& m = *candidates.front().model.registered.mechanism;
  for (const auto& c : candidates)
    if (c.model.registered.mechanism->jointCount() != m.jointCount())
      throw std::invalid_argument("--models: " + c.label + " and " + candidates.front().label +
                                  " are different mechanisms");
  pipeline::PoseSetFiles files = pipeline::PoseSetFiles::beside(args.poses, args.joints);
  if (!args.covariances.empty()) files.covariances = fs::path(args.covariances);
  files.shared.reset();  // select weighs each pose by its own covariance only
  if (!args.lines.empty()) files.lines = fs::path(args.lines);
  const pipeline::PoseSet set = pipeline::readPoseSet(files, m.jointColumnNames());
  const mech::ObservationSet& observations = set.observations;
  const std::vector<mech::LineRecord>& lines = set.lines;
  mech::SelectionOptions options;
  options.folds = args.folds;
  options.seed = args.seed;
  const mech::SelectionResult result = mech::selectModel(candidates, observations.poses, lines, options);
  if (result.recommended < 0) {
    // Why: each candidate's own failure, and what usually causes it (too few or repeated poses).
    std::string why;
    for (const auto& score : result.scores)
      if (!score.message.empty()) why += "\n  " + score.label + ": " + score.message;
    throw std::runtime_error(args.poses + ": no candidate model could be identified on these " +
                             std::to_string(observations.poses.size()) + " poses (" + std::to_string(args.folds) +
                             " folds); too few poses, or poses that repeat one another, leave the parameters "
                             "undetermined: measure more, and more varied, poses" +
                             why);
  }
  const std::string table = mech::selectionTable(result, m.jointUnits().front());
  if (!args.report.empty()) {  // all files or none (doc/robustness.md)
    support::OutputTransaction outputs;
    const fs::path dir = outputs.stageFolder(args.report);
    support::writeFileAtomically(dir / "select_report.txt", table + "recommended: " + result.recommendedLabel() + "\n");
    support::writeFileAtomically(dir / "select_scores.csv", scoresCsv(result));
    writeSvgFiles(dir, {{"select_cv.svg", selectFigure(result, m.jointUnits().front()), ""}});
    ReportProvenance provenance{args.command_line, paths.input_files, {{args.report, "--report"}}};
    if (files.covariances && args.covariances.empty())
      provenance.inputs.push_back({*files.covariances, "the covariance side file"});
    writeSelectReportJson(dir / "report.json", provenance, result, m.jointUnits().front(), args.folds, args.seed);
    writeSelectReportHtml(dir / "report.html", provenance, result, m.jointUnits().front(), args.folds, table);
    outputs.commit();
  }
  std::cout << observations.poses.size() << " poses, " << args.folds << "-fold cross-validation, " << candidates.size()
            << " candidate models (" << support::formatNumber(result.seconds, 3) << " s)\n"
            << table << "recommended: " << result.recommendedLabel() << "\n";
  return kOk;
}

}  // namespace

Runner addSelectCommand(CLI::App& app) {
  auto args = std::make_shared<SelectArguments>();
  CLI::App* cmd = app.add_subcommand("select", "choose the model to identify (cross-validation, one-SE rule)");
  cmd->add_option("--poses", args->poses, "measured target poses (poses.csv)")->required();
  cmd->add_option("--joints", args->joints, "encoder readings (joints.csv)")->required();
  cmd->add_option("--lines", args->lines, "straight-line joint records (lines.csv): V3 per model");
  cmd->add_option("--covariances", args->covariances, "pose covariance side file (default <poses stem>_covariance.csv)");
  cmd->add_option("--nominal", args->nominal, "nominal geometry (parameter YAML; default: built-in)");
  CLI::Option* models = cmd->add_option("--models", args->models,
                                        "candidates, e.g. h4-12:A,B,C,D,h4-31c:E,F,G,H or delta,delta-legs "
                                        "(default: all of the mechanism)");
  cmd->add_option("--mounting", args->mounting,
                  "camera-fixed, or camera-on-effector: the camera on the effector, the target fixed (as identify)")
      ->capture_default_str();
  cmd->add_option("--folds", args->folds, "cross-validation folds")->capture_default_str();
  cmd->add_option("--seed", args->seed, "seed of the fold assignment")->capture_default_str();
  cmd->add_option("--report", args->report,
                  "report folder (report.html, select_report.txt, select_scores.csv, select_cv.svg, report.json)");
  return [args, cmd, models] {
    // `--models ''` is a mistake (an unset variable), not a request for the default list.
    if (models->count() > 0 && args->models.empty())
      throw UsageError("--models '': an empty list of candidate models (omit --models for the default list)");
    args->command_line = commandLineOf(*cmd);
    return runSelect(*args);
  };
}

}  // namespace mire::app
