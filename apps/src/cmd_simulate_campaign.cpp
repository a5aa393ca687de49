// `mire simulate campaign --mechanism h4|delta|gough-stewart -o DIR` (or `--model robot.yaml`, a
// described robot, doc/mechanisms.md): the demo's whole rendered campaign on disk (doc/simulation.md, "Whole
// campaigns"), so that a user runs calibrate -> measure -> identify by hand with the public commands. Glue only: the
// campaign is datasets::generateMechanismImageCampaign.
#include "output_paths.hpp"
#include "simulate_campaign.hpp"
#include "validate.hpp"

#include "mire/datasets/campaign_legs.hpp"
#include "mire/datasets/iso9283_test.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/described.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"
#include "mire/support/output_transaction.hpp"
#include "mire/support/progress.hpp"
#include "mire/support/side_files.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace mire::app {
namespace {

namespace fs = std::filesystem;

struct CampaignOptions {
  std::string mechanism;  // a family of the table, or a description file (--model)
  std::string output;
  std::uint64_t seed = 2004;  // the demo's
  std::optional<int> images_per_pose, calibration_views;
  std::string mounting = "camera-fixed";  // or camera-on-effector (doc/mechanisms.md)
  bool legs = false;                      // the legs drawn as rods (doc/legs.md)
  double leg_radius_mm = 1e3 * datasets::kReferenceLegRadiusM;
};

// Bounds of the options: calibrate needs 3 usable views; beyond the upper bounds a campaign
// takes hours and gigabytes (81 poses x 100 images is 5 GB of PNG).
constexpr int kMaxImagesPerPose = 100;
constexpr int kMinCalibrationViews = 3;
constexpr int kMaxCalibrationViews = 500;
// Rods thinner than 2 mm are a few pixels wide at a metre; thicker than 30 mm they hide the robot.
constexpr double kMinLegRadiusMm = 2.0;
constexpr double kMaxLegRadiusMm = 30.0;

// The file whose presence marks a folder as a previous campaign (both generators write it).
const char* const kCampaignMarker = "truth/robot.yaml";

// Whether a campaign writes a file or folder of this name (relative to the campaign folder):
// the generators' layout (printCampaign's list; datasets/src/campaign_images.cpp). A rerun
// replaces the folder as a whole, so anything else there is a user's and must not be deleted
// (doc/robustness.md). Names, not a record of the earlier run: a rerun with fewer views also
// removes the earlier run's extra view_*.png, which a campaign did write.
bool writtenByACampaign(const fs::path& relative, bool folder) {
  std::vector<std::string> parts;
  for (const fs::path& part : relative) parts.push_back(part.string());
  const std::string extension = relative.extension().string();
  if (parts.empty()) return false;
  const std::string& top = parts.front();
  if (top == "measurement") return true;  // left by an interrupted run; the generator removes it
  if (parts.size() == 1)
    return folder ? (top == "calibration" || top == "poses" || top == "truth" || top == "iso9283")
                  : (top == "joints.csv" || top == "lines.csv" || top == "target.yaml" || top == "legs.yaml");
  if (top == "truth" || top == "iso9283")
    return parts.size() == 2 && !folder && (extension == ".yaml" || extension == ".csv");
  if (top == "calibration")
    return parts[1] == "images" && (parts.size() == 2 ? folder : parts.size() == 3 && extension == ".png");
  if (top == "poses") return parts.size() == 2 ? folder : parts.size() == 3 && !folder && extension == ".png";
  return false;
}

// Refuses (before any rendering) a previous campaign holding what a campaign does not write.
void requireOnlyCampaignFiles(const std::string& output) {
  std::vector<std::string> foreign;
  for (auto entry = fs::recursive_directory_iterator(output); entry != fs::recursive_directory_iterator(); ++entry) {
    const fs::path relative = fs::relative(entry->path(), output);
    const bool folder = entry->is_directory() && !entry->is_symlink();
    if (writtenByACampaign(relative, folder)) continue;
    foreign.push_back(relative.string());
    if (folder) entry.disable_recursion_pending();
  }
  if (foreign.empty()) return;
  std::string list;
  for (std::size_t k = 0; k < foreign.size() && k < 3; ++k) list += (k ? ", " : "") + foreign[k];
  if (foreign.size() > 3) list += ", ... (" + std::to_string(foreign.size()) + " in all)";
  throw UsageError("-o '" + output + "': the previous campaign there holds files mire did not write (" + list +
                   "); a rerun replaces the folder and would delete them: move them, or choose a new folder");
}

// What to identify: the family's truth model (truth/<model>.yaml, registry.hpp), which of its
// parameters compare with the truth directly, and the family's other models. The Delta's and
// the hexapod's joint centres and angles are identified in the frame of the mounting `mire
// identify` holds as gauge, not the simulator's (doc/demo-mechanisms.md, "Scoring"); lengths do
// not depend on the frame.

// `h4-31, h4-31c (variants E-H: --variant)`
std::string otherModels(const mechanism::MechanismFamily& family) {
  std::string list;
  for (const std::string& name : family.models) {
    if (name == family.truth_model) continue;
    const mechanism::ModelInfo& info = mechanism::modelInfo(name);
    list += (list.empty() ? "" : ", ") + name;
    if (!info.variants.empty())
      list += std::string(" (variants ") + info.variants.front() + "-" + info.variants.back() + ": --variant)";
  }
  return list;
}

void checkRange(const std::optional<int>& value, int low, int high, const std::string& option, const std::string& why) {
  if (value && (*value < low || *value > high))
    throw UsageError(option + " " + std::to_string(*value) + ": expected " + std::to_string(low) + " to " +
                     std::to_string(high) + why);
}

// Everything is checked before the rendering starts: option values, then the output folder,
// replaced only when it is empty or a previous campaign.
void checkCampaignOptions(const CampaignOptions& options) {
  if (options.mechanism.empty()) throw UsageError("give --mechanism NAME or --model robot.yaml");
  const bool described = mechanism::isDescriptionFile(options.mechanism);
  CommandPaths paths;
  paths.output_folders = {{options.output, "-o"}};
  if (described) paths.input_files = {{options.mechanism, "--model"}};
  checkCommandPaths(paths);
  checkCampaignMechanism(options.mechanism);
  if (cameraOnEffector(options.mounting) && !described &&
      mechanism::mechanismFamily(options.mechanism).defects == mechanism::SimulatedDefects::H4Parallelograms)
    throw UsageError("--mounting camera-on-effector: the H4's campaign has the camera fixed only");
  if (options.legs) checkLegsOption(options.mechanism, options.mounting);
  if (!(options.leg_radius_mm >= kMinLegRadiusMm && options.leg_radius_mm <= kMaxLegRadiusMm))
    throw UsageError("--leg-radius-mm " + support::formatNumber(options.leg_radius_mm) + ": expected " +
                     support::formatNumber(kMinLegRadiusMm) + " to " + support::formatNumber(kMaxLegRadiusMm));
  checkRange(options.images_per_pose, 1, kMaxImagesPerPose, "--images-per-pose", " images per pose");
  checkRange(options.calibration_views, kMinCalibrationViews, kMaxCalibrationViews, "--calibration-views",
             " views (calibrate needs at least 3)");
  const fs::path out = options.output;
  if (fs::is_directory(out) && !fs::is_empty(out) && !fs::exists(out / kCampaignMarker))
    throw UsageError("-o '" + options.output + "': exists, holds files and is not a previous campaign (no " +
                     kCampaignMarker + "): choose a new or empty folder");
  if (fs::is_directory(out)) requireOnlyCampaignFiles(options.output);
}

// What the summary reports of a generated campaign.
struct WrittenCampaign {
  int calibration_views = 0, images_per_pose = 0;
  std::size_t poses = 0, lines = 0;
  std::vector<std::string> joint_columns;
};

void applyOptions(const CampaignOptions& options, datasets::MechanismImageCampaignSpec& spec) {
  spec.seed = options.seed;
  if (options.images_per_pose) spec.images_per_pose = *options.images_per_pose;
  if (options.calibration_views) spec.calibration_views = *options.calibration_views;
  if (options.legs) spec.leg_radius_m = options.leg_radius_mm * 1e-3;
}

// The true geometry in the parameters `mire identify --model <model>` writes, for comparing by
// hand (truth/robot.yaml keeps the simulator's full description, defects included).
void writeTruthParameters(const fs::path& directory, const std::string& model, const mechanism::ParameterSet& truth,
                          const std::string& what) {
  mechanism::writeParameterFile(directory / "truth" / (model + ".yaml"), truth, {},
                                {{"model", model}, {"created_by", "mire simulate campaign"}}, what);
}

// The controller of the campaign's ISO 9283 test: the model at the nominal `mire identify` starts
// from (the H4's datasets/specs/h4_nominal.yaml, the others' built-in one; doc/mechanisms.md).
mechanism::RegisteredModel nominalController(const std::string& model) {
  pipeline::ModelChoice choice;
  choice.model = model;
  pipeline::applyNominal(choice, "");
  return choice.registered();
}

// The ISO 9283 test of the campaign's robot driven by its nominal controller (doc/accuracy.md, "The
// ISO 9283 test"): <dir>/iso9283/ and, for scoring, truth/iso9283.yaml (the frame of its commands).
void writeIsoTest(const fs::path& directory, const mechanism::RegisteredModel& controller,
                  const datasets::TrueRobotReach& reach, const Eigen::Isometry3d& bTc, const Eigen::Isometry3d& mTe,
                  datasets::Iso9283Spec spec, const CampaignOptions& options, const mechanism::ParameterSet& truth,
                  const std::string& model_key) {
  spec.seed = options.seed;
  const datasets::Iso9283Test test =
      datasets::simulateIso9283Test(*controller.mechanism, controller.nominal.values(), reach, bTc, mTe, spec);
  datasets::writeIso9283Test(directory / "iso9283", test, *controller.mechanism, spec);
  datasets::writeIso9283Truth(directory / "truth" / "iso9283.yaml", truth, model_key, bTc, mTe);
}

WrittenCampaign generateCampaign(const CampaignOptions& options, const fs::path& directory,
                                 const datasets::ProgressCallback& progress) {
  datasets::MechanismImageCampaignSpec spec = datasets::MechanismImageCampaignSpec::reference(options.mechanism);
  applyOptions(options, spec);
  spec.camera_on_effector = options.mounting == "camera-on-effector";
  const datasets::MechanismImageCampaign campaign = datasets::generateMechanismImageCampaign(spec, directory, progress);
  const std::string what =
      "True geometry of the simulated " + campaign.robot.title() + " (SI); its unmodelled defects are in robot.yaml";
  datasets::Iso9283Spec iso = datasets::iso9283SpecFor(campaign.robot);
  iso.joint_repeatability = campaign.robot.mechanism().jointUnits().front() == mechanism::Unit::Radian
                                ? spec.encoder_noise_rad
                                : spec.encoder_noise_m;
  const bool described = mechanism::isDescriptionFile(options.mechanism);
  writeIsoTest(
      directory, described ? campaign.robot.geometry_model : nominalController(campaign.robot.geometry_model.name),
      datasets::reachOf(campaign.robot), campaign.bTc, campaign.mTe, iso, options, campaign.robot.geometry,
      described ? support::mechanismSidePath("robot_geometry.yaml").string() : campaign.robot.geometry_model.name);
  if (described) {
    // As an identified file of a described robot: the description beside it (identify's shape).
    const fs::path truth = directory / "truth" / "robot_geometry.yaml";
    support::writeFileAtomically(support::mechanismSidePath(truth),
                                 mechanism::readMechanismDescription(options.mechanism).yamlString());
    mechanism::writeParameterFile(
        truth, campaign.robot.geometry, {},
        {{"model", support::mechanismSidePath(truth).filename().string()}, {"created_by", "mire simulate campaign"}},
        what);
  } else {
    writeTruthParameters(directory, campaign.robot.geometry_model.name, campaign.robot.geometry, what);
  }
  return {spec.calibration_views, spec.images_per_pose, campaign.pose_ids.size(), campaign.lines.size(),
          campaign.robot.mechanism().jointColumnNames()};
}

// A path as a shell word: quoted when it holds anything but plain characters.
std::string shellWord(const fs::path& path) {
  const std::string text = path.string();
  if (!text.empty() &&
      text.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_./+-=:,@%") ==
          std::string::npos)
    return text;
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// What was written, and the commands a user runs next, as on a real robot.
// The model to identify and its truth file, the comparison hint and the other models: the
// family's, or for a described robot its description and truth/robot_geometry.yaml.
struct NextSteps {
  std::string model, truth_file, comparable, others;
};

NextSteps nextSteps(const CampaignOptions& options) {
  if (mechanism::isDescriptionFile(options.mechanism))
    return {shellWord(options.mechanism), "truth/robot_geometry.yaml",
            "the leg parameters in the identified gauge (doc/mechanisms.md, \"Described mechanisms\"), or "
            "held-out predictions with mire fkm --frame camera",
            "none (a description is one model; its identified file is a nominal for --nominal)"};
  const mechanism::MechanismFamily& family = mechanism::mechanismFamily(options.mechanism);
  return {family.truth_model, "truth/" + family.truth_model + ".yaml", family.comparable, otherModels(family)};
}

void printCampaign(const CampaignOptions& options, const WrittenCampaign& written) {
  const fs::path dir = options.output;
  const NextSteps next = nextSteps(options);
  const auto in = [&](const std::string& relative) { return shellWord(dir / relative); };
  std::cout << "mire simulate campaign: a simulated " << options.mechanism << " (seed " << options.seed << ") in "
            << dir.string() << "\n"
            << "  " << in("calibration/images") << ": " << written.calibration_views << " calibration views\n"
            << "  " << in("poses") << ": " << written.poses << " poses x " << written.images_per_pose << " images\n"
            << "  " << in("joints.csv") << " (" << written.joint_columns.front() << ".." << written.joint_columns.back()
            << "), " << in("lines.csv") << " (" << written.lines << " straight lines), " << in("target.yaml") << "\n"
            << "  " << in("iso9283") << ": an ISO 9283 test (5 positions x 30 cycles, nominal controller): "
            << "commanded.csv, poses.csv (measured), joints.csv (commands)\n"
            << "  " << in("truth") << ": for scoring only (true camera, poses, robot; " << next.truth_file
            << (options.legs ? "; legs.csv, the legs' true axes" : "") << ")\n";
  if (options.legs)
    std::cout << "  " << in("legs.yaml") << ": the legs drawn as rods of radius "
              << support::formatNumber(options.leg_radius_mm)
              << " mm in the pose images (the model that predicts them, an approximate camera placement)\n";
  std::cout << "next, as on a real robot (results in the current folder):\n"
            << "  mire calibrate --target " << in("target.yaml") << " --images " << in("calibration/images")
            << " -o camera.yaml\n"
            << "  mire measure --camera camera.yaml --target " << in("target.yaml") << " --poses " << in("poses")
            << " -o poses.csv\n"
            << "  mire identify --poses poses.csv --joints " << in("joints.csv") << " --lines " << in("lines.csv")
            << " --model " << next.model
            << (options.mounting == "camera-fixed" ? "" : " --mounting " + options.mounting) << " -o identified.yaml\n"
            << "then compare identified.yaml with " << in(next.truth_file) << ": " << next.comparable
            << "; doc/simulation.md, \"Whole campaigns\"\n"
            << "other models: " << next.others << "\n"
            << "the ISO 9283 figures (in the true base frame the commands are given in):\n"
            << "  mire accuracy --params " << in("truth/iso9283.yaml") << " --commanded " << in("iso9283/commanded.csv")
            << " --poses " << in("iso9283/poses.csv") << " -o accuracy.json\n";
  if (options.mounting != "camera-fixed") return;  // the test's camera is the fixed one
  const std::string robot = mechanism::isDescriptionFile(options.mechanism) ? "--model " + shellWord(options.mechanism)
                                                                            : "--mechanism " + options.mechanism;
  std::cout << "after compensation, the same test driven by the identified model's commands:\n"
            << "  mire simulate iso9283 " << robot << " --seed " << options.seed
            << " --params identified.yaml --camera camera.yaml -o iso9283_after\n"
            << "  mire accuracy --params identified.yaml --commanded iso9283_after/commanded.csv --poses "
            << "iso9283_after/poses.csv -o accuracy_after.json\n";
}

int runCampaign(const CampaignOptions& options) {
  checkCampaignOptions(options);
  std::optional<support::Progress> progress;
  std::size_t shown = 0;
  const datasets::ProgressCallback advance = [&](std::size_t done, std::size_t total) {
    if (!progress) progress.emplace("rendering the campaign", total);
    if (done > shown) progress->advance(done - shown);
    shown = std::max(shown, done);
  };
  support::OutputTransaction outputs;
  const fs::path staged = outputs.stageFolder(options.output, support::OutputTransaction::FolderCommit::ReplaceWhole);
  const WrittenCampaign written = generateCampaign(options, staged, advance);
  if (progress) progress->finish();
  outputs.commit();
  printCampaign(options, written);
  return kOk;
}

}  // namespace

void checkCampaignMechanism(const std::string& mechanism) {
  if (mechanism::isDescriptionFile(mechanism)) {
    mechanism::readMechanismDescription(mechanism);  // file:line: key: what is wrong
    return;
  }
  try {
    mechanism::mechanismFamily(mechanism);
  } catch (const std::invalid_argument&) {
    throw UsageError("--mechanism '" + mechanism + "': unknown mechanism (valid: " + mechanism::mechanismFamilyList() +
                     "; a robot of your own: --model robot.yaml)");
  }
}

void checkLegsOption(const std::string& mechanism, const std::string& mounting) {
  if (!datasets::campaignDrawsLegs(mechanism) || cameraOnEffector(mounting))
    throw UsageError(
        "--legs: the legs are drawn for the hexapod (gough-stewart) and the Delta (delta) with the "
        "camera fixed only");
}

SimulateSubcommand addSimulateCampaignSubcommand(CLI::App& simulate) {
  auto options = std::make_shared<CampaignOptions>();
  CLI::App* campaign = simulate.add_subcommand(
      "campaign",
      "A whole campaign as mire demo renders it (doc/simulation.md): DIR/calibration/images, DIR/poses, "
      "DIR/joints.csv, DIR/lines.csv, DIR/target.yaml, DIR/truth/");
  CLI::Option* family = campaign->add_option("--mechanism", options->mechanism,
                                             mechanism::mechanismFamilyList() + " (doc/demo-mechanisms.md)");
  campaign
      ->add_option("--model", options->mechanism,
                   "A robot of your own: its description file (doc/mechanisms.md, \"Described mechanisms\")")
      ->excludes(family);
  campaign->add_option("-o,--output", options->output, "Output folder (created; replaced if a previous campaign)")
      ->required();
  campaign->add_option("--seed", options->seed, "Seed of the simulated robot, images and encoder noise")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  const datasets::MechanismImageCampaignSpec defaults;  // the reference campaigns' counts
  campaign->add_option("--images-per-pose", options->images_per_pose, "Images per pose (1 to 100)")
      ->default_str(std::to_string(defaults.images_per_pose));
  campaign->add_option("--calibration-views", options->calibration_views, "Calibration views (3 to 500)")
      ->default_str(std::to_string(defaults.calibration_views));
  campaign
      ->add_option("--mounting", options->mounting,
                   "camera-fixed, or camera-on-effector: the camera on the effector, the target fixed (not the H4)")
      ->capture_default_str();
  CLI::Option* legs = campaign->add_flag(
      "--legs", options->legs,
      "Draw the legs as rods in the pose images and write DIR/legs.yaml, DIR/truth/legs.csv (gough-stewart, delta; "
      "camera fixed; doc/legs.md)");
  campaign->add_option("--leg-radius-mm", options->leg_radius_mm, "The rods' radius (2 to 30 mm)")
      ->capture_default_str()
      ->needs(legs);
  return {campaign, [options] { return runCampaign(*options); }};
}

}  // namespace mire::app
