// The mechanism demo's stages (doc/demo-mechanisms.md): simulate the campaign of a true Delta or
// hexapod with unmodelled defects, then run the H4 demo's calibration and measurement stages on
// its images and identify each model from poses.csv + joints.csv through the library calls
// `mire identify --model NAME` makes; the truth scores only at the end.
#include "demo_mechanism.hpp"

#include "mire/datasets/iso9283_test.hpp"
#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/described.hpp"
#include "mire/mechanism/evaluation.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/model_selection.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/mechanism/translating_target.hpp"
#include "mire/pipeline/closed_loop.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/pipeline/pose_set.hpp"
#include "mire/pipeline/scored_stages.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/progress.hpp"
#include "mire/support/side_files.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <stdexcept>

namespace mire::app {
namespace fs = std::filesystem;
namespace mech = mire::mechanism;

namespace {

// Every free parameter with its σ and (when the truth has the model's parameters) error/σ
// against the truth in the gauge (display and SI units; truth NaN without).
void scoreParameters(const mech::IdentificationResult& result, const std::optional<mech::ParameterSet>& truth,
                     MechanismModelScore& score) {
  const mech::ParameterSet& p = result.model.parameters;
  score.covariance = result.covariance;
  double sum = 0.0;
  for (const auto& name : result.free_names) {
    const std::size_t i = p.index(name);
    const auto unit = p[i].unit;
    const double sigma = result.sigma[static_cast<Eigen::Index>(i)];
    const double true_value = truth ? truth->value(name) : std::nan("");
    score.identified.push_back({name, mech::displayUnitName(unit), mech::toDisplay(unit, p[i].value),
                                mech::toDisplay(unit, sigma), mech::toDisplay(unit, true_value), mech::unitName(unit),
                                p[i].value, sigma, true_value});
    if (!truth) continue;
    const double z = (p[i].value - true_value) / sigma;
    sum += z * z;
    score.error_over_sigma_max = std::max(score.error_over_sigma_max, std::abs(z));
  }
  score.error_over_sigma_rms = std::sqrt(sum / static_cast<double>(std::max<std::size_t>(1, result.free_names.size())));
}

// The positioning test in mm (datasets::positioningTestSides): a 100 mm square, scaled down with
// the protocol on a smaller robot.
double squareSide(const mech::Mechanism& model, const Eigen::VectorXd& geometric) {
  return 0.1 * std::min(1.0, datasets::protocolScale(model, geometric, model.referencePose(geometric)));
}

std::array<double, 4> squareSides(const datasets::TrueRobot& robot, const mech::Mechanism& model,
                                  const Eigen::VectorXd& geometric, double side) {
  std::array<double, 4> sides_mm = datasets::positioningTestSides(robot, model, geometric, side);
  for (double& error : sides_mm) error *= 1e3;
  return sides_mm;
}

double rms(const std::array<double, 4>& values) {
  double sum = 0.0;
  for (const double v : values) sum += v * v;
  return std::sqrt(sum / 4.0);
}

double straightnessOf(const mech::Mechanism& model, const Eigen::VectorXd& geometric,
                      const std::vector<std::vector<Eigen::VectorXd>>& lines) {
  const mech::StraightnessResult v3 = mech::straightnessCriterion(model, geometric, lines);
  return v3.ok ? v3.v3_m : std::nan("");
}

// The true robot's own straightness along the recorded (noisy) readings: its FKM.
double trueStraightness(const datasets::TrueRobot& robot, const std::vector<std::vector<Eigen::VectorXd>>& lines) {
  double total = 0.0;
  for (const auto& line : lines) {
    std::vector<Eigen::Vector3d> points;
    for (const auto& q : line) points.emplace_back(robot.fkm(q).head<3>());
    total += mech::straightness(points);
  }
  return total / static_cast<double>(lines.size());
}

// A model's name in labels and file names: a described robot's is its description's stem.
std::string modelLabel(const std::string& name) {
  return mech::isDescriptionFile(name) ? fs::path(name).stem().string() : name;
}

// One model: identified and written as identified_<model>.yaml (+ its covariance side file,
// for `mire fkm` / `mire ikm`), then scored.
MechanismModelScore identifyModel(const std::string& name, const datasets::MechanismImageCampaign& campaign,
                                  const pipeline::PoseSet& data, const fs::path& output) {
  const Stopwatch watch;
  const std::vector<mech::PoseObservation>& poses = data.observations.poses;
  pipeline::ModelChoice choice = pipeline::chooseModel(name, "");
  pipeline::applyMounting(choice, campaign.camera_on_effector ? "camera-on-effector" : "camera-fixed");
  const pipeline::Identification identification = pipeline::identify(choice, poses, data.shared);
  const pipeline::InitialModel& initial = identification.initial;
  const mech::IdentificationResult& result = identification.result;
  const auto& orientation_covariance = identification.mean_orientation_covariance;
  const bool described = mech::isDescriptionFile(name);
  MechanismModelScore score;
  score.model = modelLabel(name);
  score.seconds = watch.seconds();
  score.file = "identified_" + score.model + ".yaml";
  // A described robot's identified file travels with its description (as `mire identify` writes it).
  const fs::path description_file = support::mechanismSidePath(output / score.file);
  if (described) support::writeFileAtomically(description_file, mech::readMechanismDescription(name).yamlString());
  mech::writePredictionCovarianceCsv(support::covarianceSidePath(output / score.file),
                                     mech::predictionModelFrom(name, result, orientation_covariance));
  std::vector<std::pair<std::string, std::string>> metadata{
      {"model", described ? description_file.filename().string() : name},
      {"created_by", "mire demo --mechanism " + campaign.robot.geometry_model.name}};
  // As `mire identify` writes it: the mounting only when it is not the camera-fixed default.
  if (campaign.camera_on_effector) metadata.emplace_back("mounting", mech::mountingName(result.model.external.form()));
  mech::writeParameterFile(output / score.file, result.model.parameters, result.sigma, metadata,
                           "Identified by mire demo (" + score.model + ") from poses.csv and the campaign's joints.csv");

  const mech::Mechanism& model = *initial.model.mechanism;
  score.joint_unit = model.jointUnits().front() == mech::Unit::Radian ? "rad" : "m";
  score.free_parameters = static_cast<int>(result.free_names.size());
  score.rank = initial.gauge->report.rank;
  score.gauge = initial.gauge->gauge;
  score.rms_joint_before = mech::jointResidualCriteria(initial.model, poses).v2_rad;
  score.rms_joint_after = result.rms_joint_residual;
  score.chi2_per_dof = result.chi2 / std::max(1, result.dof);
  score.sigma_method = result.covarianceMethod();
  score.has_truth = described || name == campaign.robot.geometry_model.name;
  scoreParameters(
      result, score.has_truth ? std::optional(pipeline::truthInGauge(campaign, initial, poses)) : std::nullopt, score);
  const Eigen::VectorXd nominal = initial.model.geometricValues(), identified = result.model.geometricValues();
  const auto lines = data.lineJoints();
  score.v3_before_m = straightnessOf(model, nominal, lines);
  score.v3_after_m = straightnessOf(model, identified, lines);
  const double side = squareSide(model, nominal);
  score.square_side_mm = 1e3 * side;
  score.square_before_mm = squareSides(campaign.robot, model, nominal, side);
  score.square_after_mm = squareSides(campaign.robot, model, identified, side);
  score.square_rms_before_mm = rms(score.square_before_mm);
  score.square_rms_after_mm = rms(score.square_after_mm);
  return score;
}

datasets::MechanismImageCampaignSpec campaignSpec(const DemoOptions& options) {
  datasets::MechanismImageCampaignSpec spec = datasets::MechanismImageCampaignSpec::reference(options.mechanism);
  spec.seed = options.seed;
  spec.camera_on_effector = options.mounting == "camera-on-effector";
  if (options.quick) {  // as the H4 demo's --quick
    spec.calibration_views = 15;
    spec.images_per_pose = 3;
    spec.line_points = 10;
  }
  return spec;
}

}  // namespace

// Stages: simulate, calibrate, measure, identify each model (Delta: the simple and the per-leg
// model; hexapod: the 42-parameter model and the one with encoder scales), then the report.
MechanismDemoResults runMechanismDemo(const DemoOptions& options) {
  MechanismDemoResults results;
  results.mechanism = options.mechanism;
  const fs::path& output = options.output;
  fs::create_directories(output);
  const auto stage = [&](const std::string& name, const auto& work) { timedStage(results.timings, name, work); };
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
    camera =
        pipeline::calibrateStage(campaign->calibration_images(), campaign->camera, target, output, results.calibration);
  });
  stage("measure " + std::to_string(campaign->pose_ids.size()) + " target poses from images", [&] {
    pipeline::measureStage(
        campaign->pose_images(), [&](const std::string& id) { return campaign->trueCameraTMarker(id); }, camera, target,
        output / "poses.csv", results.measurement);
  });
  pipeline::PoseSetFiles files = pipeline::PoseSetFiles::beside(output / "poses.csv", campaign->joints_file());
  files.lines = campaign->lines_file();
  const pipeline::PoseSet data = pipeline::readPoseSet(files, campaign->robot.mechanism().jointColumnNames());
  results.true_v3_m = trueStraightness(campaign->robot, data.lineJoints());
  for (const auto& name : mechanism::selectionModelNames(mechanism::mechanismFamilyOf(options.mechanism)))
    stage("identify " + modelLabel(name) + " (shared term, V3, positioning test)",
          [&] { results.models.push_back(identifyModel(name, *campaign, data, output)); });
  results.mounting = options.mounting;
  // The ISO 9283 test reads the attained poses through a fixed camera and the identified mounting
  // (closed_loop.hpp); an identification with the camera on the effector has no such mounting.
  if (!campaign->camera_on_effector)
    stage("close the loop (" + modelLabel(results.truth_model) + " commands, ISO 9283 before / after)", [&] {
      // The file a user hands to `mire compensate`, and the geometry the uncompensated controller runs.
      // The model of the true robot's kind (a described robot: its description).
      const auto truth = std::find_if(results.models.begin(), results.models.end(),
                                      [](const MechanismModelScore& m) { return m.has_truth; });
      if (truth == results.models.end()) throw std::logic_error("demo: no identified model of the true robot's kind");
      const mech::LoadedPredictionModel identified = mech::loadPredictionModel(output / truth->file);
      datasets::Iso9283Spec spec = datasets::iso9283SpecFor(campaign->robot);
      spec.seed = options.seed;
      const datasets::MechanismImageCampaignSpec campaign_spec = campaignSpec(options);
      spec.joint_repeatability = campaign->robot.mechanism().jointUnits().front() == mech::Unit::Radian
                                     ? campaign_spec.encoder_noise_rad
                                     : campaign_spec.encoder_noise_m;
      results.closed_loop = pipeline::closedLoopTest(
          identified.model, campaign->robot.geometry_model.nominal.values(), datasets::reachOf(campaign->robot),
          campaign->bTc, campaign->mTe, spec, pipeline::calibratedCameraReading(campaign->camera, camera, target));
    });
  results.files = writeMechanismDemoReport(options, results);
  return results;
}

}  // namespace mire::app
