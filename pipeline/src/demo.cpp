// `mire demo`'s stages (demo.hpp): simulate the campaign, calibrate the camera and measure the
// poses from its images, identify (the paper's study or each model of the family's selection, as
// the mechanism's table entry says), close the loop; the truth scores only at the end.
#include "demo_stages.hpp"

#include "mire/datasets/campaign_legs.hpp"
#include "mire/datasets/iso9283_test.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/support/progress.hpp"

#include <optional>

namespace mire::pipeline {
namespace fs = std::filesystem;

namespace {

datasets::MechanismImageCampaignSpec campaignSpec(const DemoOptions& options) {
  datasets::MechanismImageCampaignSpec spec = datasets::MechanismImageCampaignSpec::reference(options.mechanism);
  spec.seed = options.seed;
  spec.camera_on_effector = options.mounting == "camera-on-effector";
  if (options.legs) spec.leg_radius_m = datasets::kReferenceLegRadiusM;
  if (options.quick) {
    spec.calibration_views = 15;
    spec.images_per_pose = 3;
    spec.line_points = 10;
  }
  return spec;
}

// The ISO 9283 test with the nominal, then the identified model's commands, measured through the
// calibrated camera; the robot's repeatability is the campaign's encoder noise.
ClosedLoopTest closedLoopStage(const DemoOptions& options, const datasets::MechanismImageCampaign& campaign,
                               const calibration::Camera& camera, const metrology::Target& target,
                               const demo::IdentifiedController& identified) {
  datasets::Iso9283Spec iso = datasets::iso9283SpecFor(campaign.robot);
  iso.seed = options.seed;
  const datasets::MechanismImageCampaignSpec spec = campaignSpec(options);
  iso.joint_repeatability = campaign.robot.mechanism().jointUnits().front() == mechanism::Unit::Radian
                                ? spec.encoder_noise_rad
                                : spec.encoder_noise_m;
  return closedLoopTest(identified.model, identified.nominal, datasets::reachOf(campaign.robot), campaign.bTc,
                        campaign.mTe, iso, calibratedCameraReading(campaign.camera, camera, target));
}

}  // namespace

bool takesPaperVariants(const mechanism::MechanismFamily& family) {
  return !mechanism::isDescriptionFile(family.truth_model) &&
         mechanism::modelInfo(family.truth_model).default_variant != 0;
}

DemoResults runDemoStages(const DemoOptions& options) {
  DemoResults results;
  results.mechanism = options.mechanism;
  results.mounting = options.mounting;
  const fs::path& output = options.output;
  fs::create_directories(output);
  const auto stage = [&](const std::string& name, const auto& work) { demo::timedStage(results.timings, name, work); };
  std::optional<datasets::MechanismImageCampaign> campaign;
  stage("simulate the campaign (render images, record joints)", [&] {
    std::optional<support::Progress> progress;
    campaign = datasets::generateMechanismImageCampaign(campaignSpec(options), output / "campaign",
                                                        [&](std::size_t done, std::size_t total) {
                                                          if (!progress)
                                                            progress.emplace("simulation: rendering", total);
                                                          progress->advance(done > 0 ? 1 : 0);
                                                        });
  });
  results.truth_model = campaign->robot.geometry_model.name;
  const metrology::Target target = metrology::Target::fromFile(campaign->target_file());
  calibration::Camera camera;
  stage("calibrate the camera from images", [&] {
    camera = calibrateStage(campaign->calibration_images(), campaign->camera, target, output, results.calibration);
  });
  stage("measure " + std::to_string(campaign->pose_ids.size()) + " target poses from images", [&] {
    measureStage(
        campaign->pose_images(), [&](const std::string& id) { return campaign->trueCameraTMarker(id); }, camera, target,
        output / "poses.csv", results.measurement);
  });
  std::optional<demo::IdentifiedController> identified;
  const mechanism::MechanismFamily family = mechanism::mechanismFamilyOf(options.mechanism);
  if (takesPaperVariants(family)) {
    const std::string letters = demo::variantLetters(family.name);
    stage(std::string("identify (variants ") + letters.front() + "-" + letters.back() +
              ", pose-count study, plan and select, V1-V3, square test)",
          [&] { identified = demo::paperStudyStage(options, *campaign, results); });
  } else {
    identified = demo::modelStages(options, *campaign, results);
  }
  if (options.legs)
    stage("measure the legs, identify from the legs, the target and both",
          [&] { results.legs = legsDemoStage(*campaign, camera, output); });
  if (identified)
    stage("close the loop (" + identified->label + " commands, ISO 9283 before / after)",
          [&] { results.closed_loop = closedLoopStage(options, *campaign, camera, target, *identified); });
  return results;
}

}  // namespace mire::pipeline
