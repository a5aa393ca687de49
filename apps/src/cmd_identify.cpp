// `mire identify`: geometric + external parameters of a mechanism from measured target poses and
// encoder readings (paper §2–6; the stage is pipeline/identify.hpp), with the paper's evaluation
// criteria and an optional Monte-Carlo study over random pose subsets. Everything is computed before anything
// is written: bad input stops with a message naming the file/line and writes nothing.
#include "commands.hpp"
#include "identify_checks.hpp"
#include "identify_hand_eye.hpp"
#include "identify_legs.hpp"
#include "identify_report.hpp"
#include "model_choice.hpp"
#include "output_paths.hpp"
#include "plan_inputs.hpp"
#include "report_json.hpp"
#include "validate.hpp"

#include "mire/mechanism/described.hpp"
#include "mire/mechanism/evaluation.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/mechanism/translating_target.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/pipeline/pose_set.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/output_transaction.hpp"
#include "mire/support/progress.hpp"
#include "mire/support/side_files.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace mire::app {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

using support::kDegreesPerRadian;

struct IdentifyArguments {
  std::string poses, joints, covariances, nominal, model, variant, lines, output, report, shared;
  std::string robot_poses, mounting, robot_sigma;  // hand-eye (identify_hand_eye.hpp)
  std::string observations, legs;                  // leg observations (identify_legs.hpp)
  std::vector<std::string> fix, priors, mc;
  bool robust = false, unweighted = false, independent_poses = false;
  int mc_repeats = 100, threads = 2;
  unsigned long long mc_seed = 1;
  std::vector<std::string> command_line;  // as parsed, for report.json
};

// --prior name=value:sigma (SI).
mech::GaussianPrior parsePrior(const std::string& text) {
  const auto eq = text.find('='), colon = text.rfind(':');
  if (eq == std::string::npos || colon == std::string::npos || colon < eq)
    throw UsageError("--prior '" + text + "': expected name=value:sigma (SI units)");
  mech::GaussianPrior prior;
  prior.name = text.substr(0, eq);
  try {
    std::size_t used = 0;
    const std::string value = text.substr(eq + 1, colon - eq - 1), sigma = text.substr(colon + 1);
    prior.mean = std::stod(value, &used);
    if (used != value.size()) throw std::invalid_argument("value");
    prior.sigma = std::stod(sigma, &used);
    if (used != sigma.size()) throw std::invalid_argument("sigma");
  } catch (const std::exception&) {
    throw UsageError("--prior '" + text + "': value and sigma must be numbers (SI units)");
  }
  if (!std::isfinite(prior.mean) || !(prior.sigma > 0.0) || !std::isfinite(prior.sigma))
    throw UsageError("--prior '" + text + "': needs a finite value and a sigma > 0");
  checkPriorSigma(text, prior.sigma);
  return prior;
}

std::vector<mech::PoseResidual> residualsOf(const mech::IdentificationModel& model,
                                            const std::vector<mech::PoseObservation>& poses) {
  std::vector<mech::PoseResidual> out;
  for (const auto& p : poses) {
    const auto ikm = model.predictJoints(p.cTm);
    mech::PoseResidual r;
    r.id = p.id;
    r.residual = ikm.reachable() ? Eigen::VectorXd(p.joints - ikm.joints) : Eigen::VectorXd::Zero(p.joints.size());
    out.push_back(r);
  }
  return out;
}

double rmsOf(const std::vector<mech::PoseResidual>& residuals) {
  double sum = 0.0;
  long n = 0;
  for (const auto& r : residuals) {
    sum += r.residual.squaredNorm();
    n += r.residual.size();
  }
  return n > 0 ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

std::string human(const mech::Parameter& p, double si) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, p.unit == mech::Unit::Radian ? "%12.5f" : "%12.4f", mech::toDisplay(p.unit, si));
  return buffer;
}

// The files as the options name them, poses.csv's side files by default.
pipeline::PoseSetFiles poseSetFiles(const IdentifyArguments& args) {
  pipeline::PoseSetFiles files = pipeline::PoseSetFiles::beside(args.poses, args.joints);
  if (!args.covariances.empty()) files.covariances = fs::path(args.covariances);
  if (!args.shared.empty()) files.shared = fs::path(args.shared);
  if (args.independent_poses) files.shared.reset();
  if (!args.lines.empty()) files.lines = fs::path(args.lines);
  return files;
}

// Inputs exist and are regular files; outputs clash with none of them (output_paths.hpp).
// Returns them (report.json's provenance).
CommandPaths checkPaths(const IdentifyArguments& args, const pipeline::PoseSetFiles& files) {
  CommandPaths paths;
  paths.input_files = {{args.poses, "--poses"}, {args.joints, "--joints"}};
  if (files.covariances)
    paths.input_files.push_back(
        {*files.covariances, args.covariances.empty() ? "the covariance side file" : "--pose-covariances"});
  if (!args.nominal.empty()) paths.input_files.push_back({args.nominal, "--nominal"});
  if (mech::isDescriptionFile(args.model)) paths.input_files.push_back({args.model, "--model"});
  if (files.lines) paths.input_files.push_back({*files.lines, "--lines"});
  if (files.shared)
    paths.input_files.push_back({*files.shared, args.shared.empty() ? "the shared-term side file" : "--shared-term"});
  paths.output_files = {{args.output, "-o"},
                        {support::covarianceSidePath(args.output), "the covariance side file of -o"}};
  if (mech::isDescriptionFile(args.model))
    paths.output_files.push_back({support::mechanismSidePath(args.output), "the mechanism side file of -o"});
  if (!args.report.empty()) paths.output_folders = {{args.report, "--report"}};
  checkCommandPaths(paths);
  return paths;
}

pipeline::ModelChoice chooseModel(const IdentifyArguments& args) {
  return chooseCommandModel(args.model, args.variant, args.mounting, args.nominal);
}

// Everything identify reads: the observations (with the shared calibration term and the
// straight lines when given) and the solver options.
struct IdentifyInputs {
  mech::ObservationSet observations;
  std::optional<fs::path> covariance_path;
  std::optional<mech::SharedPoseTerm> shared;
  std::vector<mech::LineRecord> lines;
  pipeline::IdentifyOptions options;
};

// The calibration error shared by every pose (doc/uncertainty.md) needs the full pose covariances
// as weights: weighting by the independent part alone moved the demo's R, l and alpha_i 5-10x
// further from the truth.
IdentifyInputs readIdentifyInputs(const IdentifyArguments& args, const pipeline::PoseSetFiles& files,
                                  const pipeline::ModelChoice& choice) {
  if (files.shared && !files.covariances && !args.unweighted)
    throw UsageError(files.shared->string() + " needs the full pose covariances (" +
                     support::covarianceSidePath(args.poses).string() +
                     " or --pose-covariances), or --independent-poses");
  const std::vector<std::string> joint_columns = choice.registered().mechanism->jointColumnNames();
  pipeline::PoseSet set = pipeline::readPoseSet(files, joint_columns);
  IdentifyInputs inputs;
  inputs.observations = std::move(set.observations);
  inputs.covariance_path = files.covariances;
  inputs.shared = std::move(set.shared);
  inputs.lines = std::move(set.lines);
  auto& poses = inputs.observations.poses;
  checkIdentifyPoses(poses, args.poses, args.unweighted);
  if (args.unweighted)
    for (auto& p : poses) p.covariance.reset();
  inputs.options.fit.fix = args.fix;
  for (const auto& text : args.priors) inputs.options.fit.priors.push_back(parsePrior(text));
  if (args.robust) inputs.options.fit.loss = mech::RobustLoss::Huber;
  return inputs;
}

// The paper's straightness criterion V3 before and after (< 0: no lines given) and the
// optional Monte-Carlo study over random pose subsets.
struct Criteria {
  std::vector<std::vector<Eigen::VectorXd>> line_joints;
  double v3_before = -1.0, v3_after = -1.0;
  std::optional<mech::MonteCarloStudy> study;
};

Criteria evaluateCriteria(const IdentifyArguments& args, const IdentifyInputs& inputs,
                          const pipeline::InitialModel& initial, const mech::IdentificationResult& result) {
  const auto& poses = inputs.observations.poses;
  Criteria criteria;
  for (const auto& line : inputs.lines) criteria.line_joints.push_back(line.joints);
  if (!criteria.line_joints.empty()) {
    const auto& mechanism = *result.model.mechanism;
    const auto b = mech::straightnessCriterion(mechanism, initial.model.geometricValues(), criteria.line_joints);
    const auto a = mech::straightnessCriterion(mechanism, result.model.geometricValues(), criteria.line_joints);
    if (!a.ok) throw std::runtime_error(args.lines + ": " + a.message + " (identified model)");
    criteria.v3_before = b.ok ? b.v3_m : std::nan("");
    criteria.v3_after = a.v3_m;
  }
  if (!args.mc.empty()) {
    const mech::IdentificationModel& start = initial.model;
    mech::MonteCarloOptions mc;
    mc.subset_sizes =
        parseSubsetSizes(args.mc, start.mechanism->jointCount(), start.parameters.freeCount(), poses.size());
    mc.repeats = args.mc_repeats;
    mc.seed = args.mc_seed;
    mc.threads = args.threads;
    mc.identification = inputs.options.fit;
    support::Progress progress("Monte-Carlo identifications",
                               mc.subset_sizes.size() * static_cast<std::size_t>(mc.repeats));
    mc.on_run_done = [&progress] { progress.advance(); };
    criteria.study = mech::runMonteCarloStudy(start, poses, criteria.line_joints, mc);
    progress.finish();
  }
  return criteria;
}

// χ²/dof below 1 − 3√(2/dof), its spread for dof degrees of freedom: the weights (the pose
// covariances) are larger than the residuals show, not "consistent" with them.
bool chi2BelowItsSpread(const mech::IdentificationResult& result) {
  const double dof = std::max(1, result.dof);
  return result.chi2 / dof < 1.0 - 3.0 * std::sqrt(2.0 / dof);
}

// The gauge summary without its "unidentifiable direction" lines (each ~20 coefficients long),
// replaced by their count: the report lists them.
std::string withoutDirections(const std::string& text) {
  std::istringstream lines(text);
  std::string kept;
  int directions = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.find("unidentifiable direction:") != std::string::npos) {
      ++directions;
      continue;
    }
    kept += line + "\n";
  }
  if (directions > 0)
    kept += "  " + std::to_string(directions) + " unidentifiable directions: listed in the report (Identifiability)\n";
  return kept;
}

// The fit's quality: poses, residual RMS before and after, conditioning, χ², σ method,
// outliers and gauge.
void writeFitSummary(const IdentifyInputs& inputs, const pipeline::InitialModel& initial, double rms_before,
                     const mech::IdentificationResult& result, bool list_combinations, std::ostream& out) {
  const bool weighted = result.weighted;
  out << "poses: " << inputs.observations.poses.size()
      << (weighted ? " (weighted by their measured covariances)" : " (unweighted)") << "; model " << initial.label
      << "; " << result.free_names.size() << " free parameters\n";
  if (!inputs.observations.unused_joint_ids.empty())
    out << "joints without a measured pose (ignored): " << inputs.observations.unused_joint_ids.size() << "\n";
  const double rms_after = result.rms_joint_residual;
  char line[256];
  // Rotary joints in deg (rad), prismatic ones (the hexapod's legs) in mm (m).
  const bool rotary = result.model.mechanism->jointUnits().front() == mech::Unit::Radian;
  const double display = rotary ? kDegreesPerRadian : 1e3;
  const char* const unit = rotary ? "deg" : "mm";
  const char* const si = rotary ? "rad" : "m";
  std::snprintf(line, sizeof line, "joint residual RMS: before %.4f %s (%.3e %s), after %.4f %s (%.3e %s)\n",
                rms_before * display, unit, rms_before, si, rms_after * display, unit, rms_after, si);
  out << line;
  std::snprintf(line, sizeof line, "condition number %.4g (%s), rank %d of %zu\n",
                result.identifiability.condition_number, result.identifiability.scaling.c_str(),
                result.identifiability.rank, result.free_names.size());
  out << line;
  // Long diagnostics go to the report when there is one (doc/plots.md).
  if (list_combinations)
    for (const auto& combination : result.identifiability.combinations) out << "  " << combination.text() << "\n";
  else if (!result.identifiability.combinations.empty())
    out << "  " << result.identifiability.combinations.size()
        << " unidentifiable directions: listed in the report (Identifiability)\n";
  const bool from_residuals = result.covarianceMethod().rfind("residual sandwich", 0) == 0;
  std::snprintf(line, sizeof line, "fit: chi2/dof %.3g (%d dof)%s\n", result.chi2 / std::max(1, result.dof), result.dof,
                !weighted        ? ""
                : from_residuals ? ": the fit's sigma term is taken from the residuals pose by pose"
                : result.covarianceScale2() > 1.0
                    ? ": misfit (the model does not explain the measured poses to their covariances)"
                : result.covarianceScale2() < 1.0 || chi2BelowItsSpread(result)
                    ? ": the pose covariances overstate the scatter"
                    : ", consistent");
  out << line;
  std::snprintf(
      line, sizeof line, "sigma: %s (covariance x %.3g)%s\n", result.covarianceMethod().c_str(),
      result.covarianceScale2(),
      inputs.shared ? "; pose noise, model misfit and the camera calibration" : "; pose noise and model misfit");
  out << line;
  if (!result.outliers.empty()) {
    out << "outlier poses:";
    for (const auto& id : result.outliers) out << ' ' << id;
    out << "\n";
  }
  if (initial.gauge) out << (list_combinations ? initial.gauge->text() : withoutDirections(initial.gauge->text()));
}

// One row per parameter: initial, identified, σ and change, in display units.
void writeParameterTable(const pipeline::InitialModel& initial, const mech::IdentificationResult& result,
                         std::ostream& out) {
  char line[256];
  out << "parameter      unit    initial        identified     sigma          change\n";
  for (std::size_t i = 0; i < result.model.parameters.size(); ++i) {
    const auto& p = result.model.parameters[i];
    const double start = initial.model.parameters[i].value;
    std::snprintf(line, sizeof line, "%-14s %-5s %s %s %s %s%s\n", p.name.c_str(),
                  mech::displayUnitName(p.unit).c_str(), human(p, start).c_str(), human(p, p.value).c_str(),
                  p.fixed ? "       (fixed)" : human(p, result.sigma[static_cast<Eigen::Index>(i)]).c_str(),
                  human(p, p.value - start).c_str(), "");
    out << line;
  }
}

// The Monte-Carlo study: the criteria per subset size, then each free parameter's spread.
void writeStudySummary(const IdentifyArguments& args, const Criteria& criteria,
                       const mech::IdentificationResult& result, std::ostream& out) {
  const mech::MonteCarloStudy& study = *criteria.study;
  char line[256];
  std::snprintf(line, sizeof line, "Monte-Carlo study: %d repeats per size, %.2f s\n", args.mc_repeats, study.seconds);
  out << line;
  for (const auto& s : study.summaries) {
    std::snprintf(line, sizeof line, "  %3d poses: %d ok, %d failed; V1 %+.4f ± %.4f deg, V2 %.4f ± %.4f deg",
                  s.subset_size, s.runs_ok, s.runs_failed, s.v1_mean * kDegreesPerRadian,
                  s.v1_sigma * kDegreesPerRadian, s.v2_mean * kDegreesPerRadian, s.v2_sigma * kDegreesPerRadian);
    out << line;
    if (criteria.line_joints.empty()) {
      out << ", V3 n/a (no --lines)\n";  // never "nan ± nan"
    } else {
      std::snprintf(line, sizeof line, ", V3 %.4f ± %.4f mm\n", s.v3_mean * 1e3, s.v3_sigma * 1e3);
      out << line;
    }
  }
  out << "  parameter spread (sigma over the runs):\n  parameter      unit";
  for (const auto& s : study.summaries) {
    std::snprintf(line, sizeof line, " %10d poses", s.subset_size);
    out << line;
  }
  out << "\n";
  for (std::size_t i = 0; i < result.model.parameters.size(); ++i) {
    const auto& p = result.model.parameters[i];
    if (p.fixed) continue;
    std::snprintf(line, sizeof line, "  %-14s %-4s", p.name.c_str(), mech::displayUnitName(p.unit).c_str());
    out << line;
    for (const auto& s : study.summaries) {
      std::snprintf(line, sizeof line, " %16.5f", mech::toDisplay(p.unit, s.sigma[static_cast<Eigen::Index>(i)]));
      out << line;
    }
    out << "\n";
  }
}

// What the stages computed, for the summary and the outputs.
struct IdentifyRun {
  pipeline::ModelChoice choice;
  IdentifyInputs inputs;
  pipeline::Identification identification;
  std::vector<mech::PoseResidual> before;  // q̄ − f per pose, initial model
  Criteria criteria;
  CommandPaths paths;  // as checked
};

// The human summary (mm, deg) printed and repeated in the report.
std::string summaryText(const IdentifyArguments& args, const IdentifyRun& run) {
  const Criteria& criteria = run.criteria;
  std::ostringstream out;
  // The result and its uncertainty first, then how well the fit went.
  writeParameterTable(run.identification.initial, run.identification.result, out);
  writeFitSummary(run.inputs, run.identification.initial, rmsOf(run.before), run.identification.result,
                  args.report.empty(), out);
  if (criteria.v3_after >= 0.0) {
    char line[256];
    std::snprintf(line, sizeof line, "straightness V3 (%zu lines): before %.4f mm, after %.4f mm\n",
                  run.inputs.lines.size(), criteria.v3_before * 1e3, criteria.v3_after * 1e3);
    out << line;
  }
  if (criteria.study) writeStudySummary(args, criteria, run.identification.result, out);
  return out.str();
}

// All or nothing (doc/robustness.md): the parameters, their covariance side file, then the
// report; written only now that every computation succeeded.
void writeIdentifyOutputs(const IdentifyArguments& args, const std::string& command_line, const IdentifyRun& run,
                          const std::string& summary) {
  const mech::IdentificationResult& result = run.identification.result;
  const pipeline::InitialModel& initial = run.identification.initial;
  // A described mechanism travels with its parameters: a copy of its description beside -o.
  const bool described = mech::isDescriptionFile(run.choice.model);
  const fs::path description_output = support::mechanismSidePath(args.output);
  std::vector<std::pair<std::string, std::string>> metadata{
      {"model", described ? description_output.filename().string() : run.choice.model},
      {"variant", run.choice.variant ? std::string(1, run.choice.variant) : std::string("-")},
      {"external_form", mech::externalFormName(result.model.external.form())},
  };
  // The camera-fixed files stay as they were: the mounting is written when it is the other one.
  if (run.choice.camera_on_effector) metadata.push_back({"mounting", mech::mountingName(result.model.external.form())});
  metadata.insert(metadata.end(), {{"poses", std::to_string(run.inputs.observations.poses.size())},
                                   {"rms_joint_residual_rad", std::to_string(result.rms_joint_residual)},
                                   {"condition_number", std::to_string(result.identifiability.condition_number)},
                                   {"created_by", "mire identify"}});
  IdentifyReportData data;
  if (!args.report.empty()) {
    data.command_line = command_line;
    data.model_label = initial.label;
    data.residuals_before = run.before;
    data.residuals_after = result.poses;
    data.result = result;
    data.initial = initial.model.parameters;
    data.v3_before_m = run.criteria.v3_before;
    data.v3_after_m = run.criteria.v3_after;
    data.study = run.criteria.study ? &*run.criteria.study : nullptr;
    data.summary_text = summary;
    data.gauge_text = initial.gauge ? initial.gauge->text() : std::string();
    data.provenance = {args.command_line, run.paths.input_files, run.paths.output_files};
    data.provenance.outputs.push_back({args.report, "--report"});
    data.model_name = run.choice.model;
    data.variant = run.choice.variant ? std::string(1, run.choice.variant) : std::string();
    if (run.inputs.covariance_path && !args.unweighted)
      data.pose_covariance_file = run.inputs.covariance_path->string();
  }
  const mech::PredictionModel prediction =
      mech::predictionModelFrom(run.choice.model, result, run.identification.mean_orientation_covariance);
  const fs::path covariance_output = support::covarianceSidePath(args.output);
  support::OutputTransaction outputs;
  mech::writePredictionCovarianceCsv(outputs.stageFile(covariance_output), prediction);
  if (described)
    support::writeFileAtomically(outputs.stageFile(description_output),
                                 mech::readMechanismDescription(run.choice.model).yamlString());
  mech::writeParameterFile(outputs.stageFile(args.output), result.model.parameters, result.sigma, metadata,
                           "Identified by mire identify (" + initial.label + ") from " + args.poses + " and " +
                               args.joints + "\nsigma_<name>: standard deviation of the estimate (same unit as <name>)");
  if (!args.report.empty()) writeIdentifyReport(outputs.stageFolder(args.report), data);
  outputs.commit();
  std::cout << summary << "wrote " << args.output << ", " << covariance_output.string() << " (full parameter covariance)"
            << (args.report.empty() ? "" : " and the report in " + args.report) << "\n";
}

// Stages: paths and model choice, inputs, initial model, the fit, the criteria, the summary,
// then the outputs.
int runIdentify(const IdentifyArguments& args, const std::string& command_line) {
  IdentifyRun run;
  const pipeline::PoseSetFiles files = poseSetFiles(args);
  run.paths = checkPaths(args, files);
  run.choice = chooseModel(args);
  run.inputs = readIdentifyInputs(args, files, run.choice);
  const auto& poses = run.inputs.observations.poses;
  try {
    run.identification = pipeline::identify(run.choice, poses, run.inputs.shared, run.inputs.options);
  } catch (const mech::PosesRejectedError& error) {  // the library does not know the files' names
    throw std::runtime_error(args.poses + " with " + args.joints + ": " + error.what());
  }
  if (!run.identification.result.converged)
    std::cerr << "mire identify: warning: the solver did not report convergence\n";
  run.before = residualsOf(run.identification.initial.model, poses);
  run.criteria = evaluateCriteria(args, run.inputs, run.identification.initial, run.identification.result);
  writeIdentifyOutputs(args, command_line, run, summaryText(args, run));
  return kOk;
}

}  // namespace

Runner addIdentifyCommand(CLI::App& app) {
  auto args = std::make_shared<IdentifyArguments>();
  CLI::App* cmd = app.add_subcommand(
      "identify", "identify a mechanism's geometry (H4, Delta, Gough-Stewart) from poses.csv and joints.csv");
  cmd->add_option("--poses", args->poses,
                  "measured target poses (poses.csv, doc/file-formats.md); required but with --observations legs");
  cmd->add_option("--observations", args->observations,
                  "target (default), legs or both: what the camera measured (doc/legs.md)");
  cmd->add_option("--legs", args->legs, "the legs' measured axes (legs.csv, doc/file-formats.md)");
  cmd->add_option("--joints", args->joints,
                  "encoder readings (joints.csv: pose_id,q1_<rad|m>..qN_<rad|m> per the mechanism)");
  CLI::Option* robot = cmd->add_option(
      "--robot-poses", args->robot_poses,
      "hand-eye calibration of a robot that reports its pose: robot_poses.csv (bTe per pose), instead of --joints");
  cmd->add_option(
      "--mounting", args->mounting,
      "camera-fixed (default) or camera-on-effector (the target fixed in the workspace; doc/mechanisms.md)");
  cmd->add_option("--robot-sigma", args->robot_sigma,
                  "with --robot-poses: the robot pose sigma T_MM,R_DEG (per component) for rows without their own")
      ->needs(robot);
  cmd->add_option("--pose-covariances", args->covariances,
                  "6x6 pose covariances (default: <poses>_covariance.csv beside poses.csv when it exists, "
                  "else the sigma_ columns)");
  cmd->add_flag("--unweighted", args->unweighted, "ignore the pose covariances (plain least squares)")
      ->excludes("--pose-covariances");
  cmd->add_option("--nominal", args->nominal,
                  "nominal geometry: a parameter YAML or an identified file (the H4 models: model 12's keys, default "
                  "datasets/specs/h4_nominal.yaml; the others: their own parameters, default built in)");
  cmd->add_option("--model", args->model,
                  mech::registeredModelList() + " (doc/mechanisms.md); default: the variant's model, else " +
                      mech::registeredModels().front().name);
  cmd->add_option("--variant", args->variant,
                  "paper Table 2 variant A..H of " + mech::variantOwnerList() + " (default: the model's own)");
  cmd->add_option("--fix", args->fix, "also hold these parameters at their nominal values")->delimiter(',');
  cmd->add_option("--prior", args->priors, "Gaussian prior name=value:sigma (SI units); repeatable");
  cmd->add_flag("--robust", args->robust, "Huber loss (3 sigma) and outlier report");
  cmd->add_option("--shared-term", args->shared,
                  "the calibration term shared by every pose (default: <poses>_shared.csv beside poses.csv when it "
                  "exists; doc/uncertainty.md)");
  cmd->add_flag("--independent-poses", args->independent_poses,
                "ignore the shared calibration term (treat the pose errors as independent)")
      ->excludes("--shared-term");
  CLI::Option* mc =
      cmd->add_option("--mc", args->mc, "Monte-Carlo study: subset sizes, e.g. 6,15,71 (the other poses validate)");
  cmd->add_option("--mc-repeats", args->mc_repeats, "identifications per subset size")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000))
      ->needs(mc);
  cmd->add_option("--mc-seed", args->mc_seed, "seed of the subset draws")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber)
      ->needs(mc);
  cmd->add_option("--threads", args->threads, "worker threads of the Monte-Carlo study")
      ->capture_default_str()
      ->check(CLI::Range(1, kMaxThreads));
  cmd->add_option("--lines", args->lines, "straight-line joint records for V3 (lines.csv: line_id,q1_rad..q4_rad)");
  cmd->add_option("-o,--output", args->output, "identified parameters (YAML, SI, with sigma_<name>)")->required();
  cmd->add_option("--report", args->report, "folder for report.html, report.md, its PNG charts and report.json");
  return [args, cmd] {
    if (!args->observations.empty() && args->observations != "target") {
      for (const char* other : {"--robot-poses", "--variant", "--prior", "--lines", "--mc", "--shared-term", "--report",
                                "--robust", "--unweighted", "--mounting"})
        if (cmd->count(other) > 0)
          throw UsageError(std::string(other) + " does not apply to --observations " + args->observations);
      if (args->joints.empty()) throw UsageError("--observations " + args->observations + " needs --joints");
      return runLegIdentify({args->observations, args->legs, args->joints, args->poses, args->covariances, args->model,
                             args->nominal, args->output, args->fix});
    }
    if (!args->legs.empty()) throw UsageError("--legs needs --observations legs or both");
    if (args->poses.empty()) throw UsageError("--poses is required (poses.csv), but with --observations legs");
    if (!args->robot_poses.empty()) {
      for (const char* other : {"--joints", "--model", "--variant", "--nominal", "--fix", "--prior", "--lines", "--mc",
                                "--shared-term", "--report", "--robust", "--unweighted"})
        if (cmd->count(other) > 0)
          throw UsageError(std::string(other) + " does not apply to --robot-poses (hand-eye calibration)");
      return runHandEyeIdentify(
          {args->robot_poses, args->poses, args->covariances, args->mounting, args->robot_sigma, args->output});
    }
    if (args->joints.empty()) throw UsageError("--joints is required (or --robot-poses for a hand-eye calibration)");
    args->command_line = commandLineOf(*cmd);
    std::string command_line = "mire identify --poses " + args->poses + " --joints " + args->joints + " --model " +
                               (args->model.empty() ? "(default)" : args->model) +
                               (args->variant.empty() ? "" : " --variant " + args->variant) + " -o " + args->output;
    return runIdentify(*args, command_line);
  };
}

}  // namespace mire::app
