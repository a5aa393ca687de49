// `mire simulate iso9283 --mechanism NAME --seed S --params identified.yaml -o DIR`: the ISO 9283
// test after compensation (doc/accuracy.md, "The ISO 9283 test"). The true robot of the campaign
// `mire simulate campaign` drew for the same mechanism and seed runs the identified model's joint
// commands (what `mire compensate --poses` gives) to the test's 5 positions, 30 cycles; the camera
// measures each stop. With the campaign's own iso9283/ (the nominal controller), the test before
// and after. Glue only: datasets::trueRobotOf and datasets::simulateIso9283Test.
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

#include "mire/calibration/camera_formats.hpp"
#include "mire/datasets/iso9283_test.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/described.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/pipeline/closed_loop.hpp"
#include "mire/support/output_transaction.hpp"
#include "output_paths.hpp"
#include "simulate_campaign.hpp"
#include "validate.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;
namespace mech = mire::mechanism;

struct IsoAfterOptions {
  std::string mechanism;  // a family of the table, or a description file (--model)
  std::uint64_t seed = 2004;
  std::string params, camera, output;
};

// The campaign's true robot, its mountings, camera and target, and the test's spec, as `mire
// simulate campaign` drew them for this mechanism and seed (no image rendered). The robot is kept
// here: `reach` refers to it.
struct CampaignRig {
  datasets::TrueRobot robot;
  datasets::TrueRobotReach reach;
  Eigen::Isometry3d bTc = Eigen::Isometry3d::Identity(), mTe = Eigen::Isometry3d::Identity();
  datasets::Iso9283Spec iso;
  std::vector<mech::Unit> joint_units;
  fs::path camera_file, target_file;
};

std::unique_ptr<CampaignRig> campaignRig(const IsoAfterOptions& options) {
  datasets::MechanismImageCampaignSpec spec = datasets::MechanismImageCampaignSpec::reference(options.mechanism);
  spec.seed = options.seed;
  auto rig = std::make_unique<CampaignRig>();
  rig->robot = datasets::trueRobotOf(spec);
  rig->reach = datasets::reachOf(rig->robot);
  rig->bTc = datasets::mechanismBaseTCamera(spec.mechanism);
  rig->mTe = datasets::mechanismMarkerTEffector(spec.mechanism, metrology::Target::fromFile(spec.target_file));
  rig->iso = datasets::iso9283SpecFor(rig->robot);
  rig->joint_units = rig->robot.mechanism().jointUnits();
  rig->iso.joint_repeatability =
      rig->joint_units.front() == mech::Unit::Radian ? spec.encoder_noise_rad : spec.encoder_noise_m;
  rig->camera_file = spec.camera_file;
  rig->target_file = spec.target_file;
  return rig;
}

void checkOptions(const IsoAfterOptions& options) {
  if (options.mechanism.empty()) throw UsageError("give --mechanism NAME or --model robot.yaml");
  CommandPaths paths{{{options.params, "--params"}}, {}, {}, {{options.output, "-o"}}};
  if (!options.camera.empty()) paths.input_files.push_back({options.camera, "--camera"});
  if (mech::isDescriptionFile(options.mechanism)) paths.input_files.push_back({options.mechanism, "--model"});
  checkCommandPaths(paths);
  checkCampaignMechanism(options.mechanism);
}

int runIsoAfter(const IsoAfterOptions& options) {
  checkOptions(options);
  const mech::LoadedPredictionModel identified = mech::loadPredictionModel(options.params);
  const mech::Mechanism& controller = *identified.model.mechanism;
  if (identified.model.mounting_form == mech::ExternalForm::CameraOnEffector)
    throw std::invalid_argument(options.params +
                                ": identified with the camera on the effector; the ISO 9283 test is measured by a "
                                "fixed camera (the campaign's), which this file's mounting cannot read");
  const std::unique_ptr<CampaignRig> rig = campaignRig(options);
  if (controller.jointUnits() != rig->joint_units)
    throw std::invalid_argument(options.params + ": model " + identified.model.model_name + " drives " +
                                std::to_string(controller.jointCount()) +
                                " joints that are not those of the simulated " + options.mechanism + " (" +
                                std::to_string(rig->joint_units.size()) + ")");
  // Through the user's calibrated camera, when given: the identification absorbed its error, and
  // the test is read through that same camera (pipeline/closed_loop.hpp).
  datasets::CameraReading reading;
  if (!options.camera.empty())
    reading = pipeline::calibratedCameraReading(calibration::readCamera(rig->camera_file),
                                                calibration::readCamera(options.camera),
                                                metrology::Target::fromFile(rig->target_file));
  datasets::Iso9283Spec iso = rig->iso;
  iso.seed = options.seed + 1;  // new cycles: not the scatter and noise of the campaign's test before
  const datasets::Iso9283Test test = datasets::simulateIso9283Test(controller, identified.model.geometric.values(),
                                                                   rig->reach, rig->bTc, rig->mTe, iso, reading);
  support::OutputTransaction outputs;
  datasets::writeIso9283Test(outputs.stageFolder(options.output), test, controller, iso);
  outputs.commit();
  const fs::path dir = options.output;
  std::cout << "mire simulate iso9283: the simulated " << options.mechanism << " (seed " << options.seed
            << ") driven by the commands of " << options.params << " (" << identified.model.model_name
            << "), 5 positions x " << iso.cycles << " cycles, measured "
            << (options.camera.empty() ? "by the true camera" : "through " + options.camera) << ", in " << dir.string()
            << "\n"
            << "the ISO 9283 figures after compensation (in the identified base frame):\n"
            << "  mire accuracy --params " << options.params << " --commanded " << (dir / "commanded.csv").string()
            << " --poses " << (dir / "poses.csv").string() << " -o accuracy_after.json\n";
  return kOk;
}

}  // namespace

SimulateSubcommand addSimulateIso9283Subcommand(CLI::App& simulate) {
  auto options = std::make_shared<IsoAfterOptions>();
  CLI::App* cmd = simulate.add_subcommand(
      "iso9283",
      "The ISO 9283 test after compensation: the robot of `simulate campaign` (same mechanism and seed) runs the "
      "identified model's commands; DIR/commanded.csv, poses.csv, joints.csv");
  CLI::Option* family = cmd->add_option("--mechanism", options->mechanism, mech::mechanismFamilyList());
  cmd->add_option("--model", options->mechanism, "A robot of your own: its description file")->excludes(family);
  cmd->add_option("--seed", options->seed, "The campaign's seed (its true robot)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--params", options->params, "identified parameter file (mire identify -o): its commands")->required();
  cmd->add_option("--camera", options->camera,
                  "the calibrated camera the identification's poses were measured with (default: the true camera)");
  cmd->add_option("-o,--output", options->output, "Output folder (created)")->required();
  return {cmd, [options] { return runIsoAfter(*options); }};
}

}  // namespace mire::app
