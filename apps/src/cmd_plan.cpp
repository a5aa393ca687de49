// `mire plan`: which poses to measure (doc/plan-and-select.md). From a model's nominal
// geometry, a workspace and a mounting guess, N poses chosen among random candidates by the
// DETMAX exchange on the Fisher information of the identification (Ds-optimal by default, the
// mounting as nuisance parameters), with the predicted σ of every parameter for the plan,
// random sets of the same size and the whole candidate set. Everything is computed before
// anything is written.
#include <cctype>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "commands.hpp"
#include "kinematics_files.hpp"
#include "mire/calibration/camera_formats.hpp"
#include "mire/mechanism/experiment_design.hpp"
#include "mire/pipeline/camera_plan.hpp"
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

struct PlanArguments {
  std::string model, nominal, workspace, output, externals, camera, target, criterion = "D", report;
  std::string mounting = "camera-fixed";  // or camera-on-effector (doc/mechanisms.md, "Camera on the effector")
  int count = 15, candidates = 10000;
  unsigned seed = 1;
  pipeline::CameraPlanOptions camera_options;
  std::vector<std::string> command_line;  // as parsed, for report.json
};

mech::DesignCriterion parseCriterion(const std::string& text) {
  if (text == "D" || text == "d") return mech::DesignCriterion::D;
  if (text == "A" || text == "a") return mech::DesignCriterion::A;
  if (text == "E" || text == "e") return mech::DesignCriterion::E;
  throw std::invalid_argument("--criterion '" + text + "': expected D, A or E");
}

// plan.csv: pose_id, the effector pose, the joints through the nominal IKM, visibility
// ("unchecked" without --camera; "yes" with it: invisible candidates are never chosen).
std::string planCsv(const mech::CandidateInformation& info, const std::vector<int>& design, bool camera) {
  const mech::Mechanism& m = *info.model.mechanism;
  std::ostringstream out;
  out << "pose_id";
  for (const std::string& c : poseColumnNames(m)) out << ',' << c;
  for (const std::string& c : m.jointColumnNames()) out << ',' << c;
  out << ",visible\n";
  char id[32];
  for (std::size_t k = 0; k < design.size(); ++k) {
    const auto j = static_cast<std::size_t>(design[k]);
    std::snprintf(id, sizeof id, "p%03zu", k + 1);
    out << id;
    for (Eigen::Index c = 0; c < info.poses[j].size(); ++c) out << ',' << support::formatNumber(info.poses[j][c]);
    for (Eigen::Index c = 0; c < info.observations[j].joints.size(); ++c)
      out << ',' << support::formatNumber(info.observations[j].joints[c]);
    out << (camera ? ",yes\n" : ",unchecked\n");
  }
  return out.str();
}

// sigma.csv of the report: per free parameter the predicted σ (SI) of the three designs, and
// the part of the plan's from the camera calibration's error shared by every pose (empty
// without a camera covariance).
std::string sigmaCsv(const mech::DesignReport& r) {
  std::ostringstream out;
  out << "name,unit,role,sigma_plan,sigma_random,sigma_all,sigma_plan_shared\n";
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    out << r.names[i] << ',' << mech::unitName(r.units[i]) << ','
        << (static_cast<int>(i) < r.geometric_free ? "geometric" : "mounting") << ','
        << support::formatNumber(r.sigma_plan[k], 6) << ',' << support::formatNumber(r.sigma_random[k], 6) << ','
        << support::formatNumber(r.sigma_all[k], 6) << ','
        << (r.sigma_plan_shared.size() > 0 ? support::formatNumber(r.sigma_plan_shared[k], 6) : std::string()) << '\n';
  }
  return out.str();
}

// The report's line on the mounting: which external transforms the plan treats as nuisance.
std::string mountingLine(bool on_effector) {
  return on_effector ? "mounting: camera-on-effector (externals eTc and bTm, cTm = cTe * eTb(X) * bTm)\n"
                     : "mounting: camera-fixed (externals cTb and eTm, cTm = cTb * bTe(X) * eTm)\n";
}

// The camera and the target of --camera/--target (both or neither), validated.
struct CameraInputs {
  calibration::Camera camera;
  std::optional<metrology::Target> target;
};
CameraInputs readCameraInputs(const PlanArguments& args) {
  CameraInputs in;
  if (args.camera.empty()) return in;
  in.camera = calibration::readCamera(args.camera);
  checkCamera(in.camera, args.camera);
  in.target = metrology::Target::fromFile(args.target);
  checkTargetSize(*in.target, args.target);
  const pipeline::CameraPlanOptions& o = args.camera_options;
  if (!(o.visibility.margin_px >= 0.0)) throw UsageError("--margin-px must be >= 0");
  if (!(o.visibility.max_tilt_deg > 0.0 && o.visibility.max_tilt_deg <= 90.0))
    throw UsageError("--max-tilt-deg must be in (0, 90]");
  if (o.prediction.images < 1) throw UsageError("--images-per-pose must be >= 1");
  if (!(o.prediction.pixel_sigma >= 0.0) || !(o.prediction.systematic_px >= 0.0) || !(o.prediction.featureSigma() > 0.0))
    throw UsageError("--pixel-sigma and --systematic-px must be >= 0, not both 0");
  // A detector's noise is never 0 (measured: 0.01-0.1 px, doc/plan-and-select.md); 0 would
  // promise poses known exactly.
  if (!(o.prediction.pixel_sigma > 0.0))
    throw UsageError("--pixel-sigma 0: a camera's pixel noise is never 0 (measured ones are 0.01-0.1 px)");
  if (!(o.prediction.systematic_mean_px >= 0.0) || !(o.prediction.systematic_grid_px >= 0.0) ||
      !(o.prediction.systematic_grid_px <= o.prediction.systematic_mean_px) ||
      !(o.prediction.systematic_mean_px + o.prediction.pixel_sigma > 0.0))
    throw UsageError("--systematic-board A,B needs 0 <= B <= A, and A or --pixel-sigma > 0");
  return in;
}

// Without a camera: the candidates as drawn. With one: the visible ones (counted in
// `summary`), or an error (exit 1) when fewer than --count remain.
std::vector<Eigen::VectorXd> plannableCandidates(const PlanArguments& args, const CameraInputs& in,
                                                 const mech::Mechanism& m, const mech::MountingGuess& mounting,
                                                 std::vector<Eigen::VectorXd> poses,
                                                 pipeline::CameraPlanSummary* summary) {
  if (!in.target) return poses;
  pipeline::CameraCandidates seen =
      pipeline::visibleCandidates(m, mounting, in.camera, *in.target, poses, args.camera_options);
  if (static_cast<int>(seen.visible.size()) < args.count)
    throw std::runtime_error("--camera " + args.camera + ": only " + std::to_string(seen.visible.size()) + " of " +
                             std::to_string(poses.size()) + " candidate poses show the whole target (" +
                             std::to_string(seen.outside) + " outside the image or its margin, " +
                             std::to_string(seen.oblique) + " too oblique; first: " + seen.example_reason +
                             "), fewer than --count " + std::to_string(args.count) +
                             ": check the mounting guess (--externals), the workspace, --margin-px, --max-tilt-deg");
  summary->options = args.camera_options;
  summary->drawn = poses.size();
  summary->visible = seen.visible.size();
  summary->outside = seen.outside;
  summary->oblique = seen.oblique;
  return std::move(seen.visible);
}

int runPlan(const PlanArguments& args) {
  if (args.camera.empty() != args.target.empty()) throw UsageError("--camera and --target go together");
  const mech::DesignCriterion criterion = parseCriterion(args.criterion);
  CommandPaths paths{{{args.workspace, "--workspace"}}, {}, {{args.output, "-o"}}, {}};
  if (!args.nominal.empty()) paths.input_files.push_back({args.nominal, "--nominal"});
  if (!args.externals.empty()) paths.input_files.push_back({args.externals, "--externals"});
  if (!args.camera.empty()) paths.input_files.push_back({args.camera, "--camera"});
  if (!args.target.empty()) paths.input_files.push_back({args.target, "--target"});
  if (!args.report.empty()) paths.output_folders.push_back({args.report, "--report"});
  checkCommandPaths(paths);
  if (args.count < 1) throw UsageError("--count must be >= 1");
  if (args.candidates < args.count) throw UsageError("--candidates must be >= --count");
  if (args.candidates > kMaxPlanCandidates)
    throw UsageError("--candidates " + std::to_string(args.candidates) + ": at most " +
                     std::to_string(kMaxPlanCandidates) + " (doc/limits.md; the default " +
                     std::to_string(PlanArguments{}.candidates) + " is enough for a plan of up to a few hundred poses)");
  const bool on_effector = cameraOnEffector(args.mounting);
  const CameraInputs camera = readCameraInputs(args);

  const mech::DesignModel model = withMounting(readDesignModel(args.model, args.nominal), on_effector, "model");
  const mech::Mechanism& m = *model.registered.mechanism;
  const mech::Workspace workspace = readWorkspaceYaml(args.workspace, m);
  const mech::MountingGuess mounting = args.externals.empty() ? mech::defaultMountingGuess(workspace, on_effector)
                                                              : readMountingYaml(args.externals, on_effector);
  mech::DesignOptions options;
  options.criterion = criterion;
  options.count = args.count;
  options.seed = args.seed;
  pipeline::CameraPlanSummary camera_summary;
  const auto poses = plannableCandidates(
      args, camera, m, mounting,
      mech::generateCandidatePoses(m, model.registered.nominal.values(), workspace, args.candidates, args.seed),
      &camera_summary);
  const pipeline::CameraPoseModel camera_model =
      camera.target ? pipeline::cameraPoseModel(camera.camera, *camera.target, args.camera_options)
                    : pipeline::CameraPoseModel{};
  const mech::CandidateInformation info =
      mech::candidateInformation(model, mounting, poses, options, camera_model.covariance, camera_model.shared);
  camera_summary.shared_term = info.hasSharedTerm();
  const mech::DesignReport report = mech::planExperiment(info, options);
  if (camera.target)
    camera_summary.sigmas =
        pipeline::plannedPoseSigmas(info, report.design, camera.camera, *camera.target, args.camera_options);
  const std::string camera_text = camera.target ? pipeline::cameraPlanText(camera_summary) : std::string();
  const std::string text = "model " + args.model + ": " + std::to_string(poses.size()) + " candidate poses, " +
                           std::to_string(info.free_names.size()) + " free parameters (" +
                           std::to_string(info.geometric_free) + " geometric)\n" + mountingLine(on_effector) +
                           camera_text + mech::designReportText(report);
  // All or nothing (doc/robustness.md): plan.csv, then the report.
  support::OutputTransaction outputs;
  support::writeFileAtomically(outputs.stageFile(args.output), planCsv(info, report.design, camera.target.has_value()));
  if (!args.report.empty()) {
    const fs::path dir = outputs.stageFolder(args.report);
    support::writeFileAtomically(dir / "plan_report.txt", text);
    support::writeFileAtomically(dir / "plan_sigma.csv", sigmaCsv(report));
    PlanReportSettings settings{
        {args.command_line, paths.input_files, paths.output_files}, args.model, args.candidates, args.seed, args.mounting};
    settings.provenance.outputs.push_back({args.report, "--report"});
    writePlanReportJson(dir / "report.json", settings, info, report, camera.target ? &camera_summary : nullptr);
    writePlanReportHtml(dir / "report.html", settings, report, text);
  }
  outputs.commit();
  std::cout << text << "wrote " << args.output
            << (args.report.empty() ? "" : " and " + args.report + "/report.html, plan_report.txt, plan_sigma.csv")
            << "\n";
  return kOk;
}

}  // namespace

Runner addPlanCommand(CLI::App& app) {
  auto args = std::make_shared<PlanArguments>();
  CLI::App* cmd = app.add_subcommand("plan", "choose the poses to measure (optimal experiment design)");
  cmd->add_option("--model", args->model, mech::registeredModelList())->required();
  cmd->add_option("--nominal", args->nominal,
                  "nominal geometry (a parameter YAML or an identified file; default: built in)");
  cmd->add_option("--workspace", args->workspace, "workspace YAML (x_m, y_m, z_m ranges, rotations)")->required();
  cmd->add_option("--count", args->count, "number of poses to choose")->required();
  cmd->add_option("-o,--output", args->output, "plan.csv")->required();
  cmd->add_option("--mounting", args->mounting,
                  "camera-fixed, or camera-on-effector: the camera on the effector, the target fixed (as identify)")
      ->capture_default_str();
  cmd->add_option("--externals", args->externals,
                  "mounting guess YAML (tx_CB..rz_CB, tx_EM..rz_EM; camera on the effector: tx_EC..rz_EC, "
                  "tx_BM..rz_BM)");
  cmd->add_option(
      "--camera", args->camera,
      "camera.yaml: exclude poses where the target is not seen whole, weight by the predicted pose covariance");
  cmd->add_option("--target", args->target, "target.yaml (with --camera)");
  pipeline::CameraPlanOptions& camera = args->camera_options;
  cmd->add_option("--images-per-pose", camera.prediction.images, "images per pose (with --camera)")->capture_default_str();
  cmd->add_option("--pixel-sigma", camera.prediction.pixel_sigma,
                  "detector noise per feature per image, px (with --camera)")
      ->capture_default_str();
  cmd->add_option_function<std::string>(
         "--systematic-model",
         [&camera](const std::string& name) {
           camera.prediction.systematic_model =
               name == "constant" ? metrology::SystematicModel::Constant : metrology::SystematicModel::BoardImage;
         },
         "detector systematic error: board (default: from the board's projected square size and edge angle) or "
         "constant (--systematic-px) (with --camera)")
      ->check(CLI::IsMember({"board", "constant"}));
  cmd->add_option("--systematic-px", camera.prediction.systematic_px,
                  "constant model: detector systematic error per feature, px, does not average (with --camera)")
      ->capture_default_str();
  cmd->add_option_function<std::vector<double>>(
         "--systematic-board",
         [&camera](const std::vector<double>& ab) {
           camera.prediction.systematic_mean_px = ab[0];
           camera.prediction.systematic_grid_px = ab[1];
         },
         "board model: A,B of sigma_sys = (20 px / square px) (A + B cos 4 edge angle), px (with --camera; "
         "default 0.0278,0.0045)")
      ->expected(2)
      ->delimiter(',');
  cmd->add_option("--margin-px", camera.visibility.margin_px,
                  "features at least this far inside the image (with --camera)")
      ->capture_default_str();
  cmd->add_option("--max-tilt-deg", camera.visibility.max_tilt_deg,
                  "largest angle between the target normal and the line of sight (with --camera)")
      ->capture_default_str();
  cmd->add_option("--criterion", args->criterion, "D (Ds-optimal, default), A or E")->capture_default_str();
  cmd->add_option("--candidates", args->candidates, "candidate poses drawn in the workspace")->capture_default_str();
  cmd->add_option("--seed", args->seed, "random seed of the candidates and the random comparison sets")
      ->capture_default_str();
  cmd->add_option("--report", args->report, "report folder (report.html, plan_report.txt, plan_sigma.csv, report.json)");
  return [args, cmd] {
    args->command_line = commandLineOf(*cmd);
    return runPlan(*args);
  };
}

}  // namespace mire::app
