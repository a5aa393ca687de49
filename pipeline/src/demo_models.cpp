// The identification part of `mire demo` on a robot whose models do not take the paper's variants
// (doc/demo-mechanisms.md): each model of the family's selection identified from poses.csv +
// joints.csv through the library calls `mire identify --model NAME` makes, written as it writes
// them, then scored (V3, the positioning test, the parameters against the truth in the gauge).
#include "demo_stages.hpp"

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/described.hpp"
#include "mire/mechanism/evaluation.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/model_selection.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/mechanism/translating_target.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/pipeline/pose_set.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/progress.hpp"
#include "mire/support/side_files.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <optional>
#include <stdexcept>

namespace mire::pipeline::demo {
namespace fs = std::filesystem;
namespace mech = mire::mechanism;

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

namespace {

// Every free parameter with its σ and (when the truth has the model's parameters) error/σ
// against the truth in the gauge (display and SI units; truth NaN without).
void scoreParameters(const mech::IdentificationResult& result, const std::optional<mech::ParameterSet>& truth,
                     DemoModelScore& score) {
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
DemoModelScore identifyModel(const std::string& name, const datasets::MechanismImageCampaign& campaign,
                             const PoseSet& data, const fs::path& output) {
  const Stopwatch watch;
  const std::vector<mech::PoseObservation>& poses = data.observations.poses;
  ModelChoice choice = chooseModel(name, "");
  applyMounting(choice, campaign.camera_on_effector ? "camera-on-effector" : "camera-fixed");
  const Identification identification = identify(choice, poses, data.shared);
  const InitialModel& initial = identification.initial;
  const mech::IdentificationResult& result = identification.result;
  const auto& orientation_covariance = identification.mean_orientation_covariance;
  const bool described = mech::isDescriptionFile(name);
  DemoModelScore score;
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
  scoreParameters(result, score.has_truth ? std::optional(truthInGauge(campaign, initial, poses)) : std::nullopt, score);
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

}  // namespace

std::optional<IdentifiedController> modelStages(const DemoOptions& options,
                                                const datasets::MechanismImageCampaign& campaign, DemoResults& results) {
  const fs::path& output = options.output;
  const auto stage = [&](const std::string& name, const auto& work) { timedStage(results.timings, name, work); };
  PoseSetFiles files = PoseSetFiles::beside(output / "poses.csv", campaign.joints_file());
  files.lines = campaign.lines_file();
  const PoseSet data = readPoseSet(files, campaign.robot.mechanism().jointColumnNames());
  results.true_v3_m = trueStraightness(campaign.robot, data.lineJoints());
  for (const auto& name : mechanism::selectionModelNames(mechanism::mechanismFamilyOf(options.mechanism)))
    stage("identify " + modelLabel(name) + " (shared term, V3, positioning test)",
          [&] { results.models.push_back(identifyModel(name, campaign, data, output)); });
  // The ISO 9283 test reads the attained poses through a fixed camera and the identified mounting
  // (closed_loop.hpp); an identification with the camera on the effector has no such mounting.
  if (campaign.camera_on_effector) return std::nullopt;
  // The file a user hands to `mire compensate`, and the geometry the uncompensated controller runs.
  // The model of the true robot's kind (a described robot: its description).
  const auto truth =
      std::find_if(results.models.begin(), results.models.end(), [](const DemoModelScore& m) { return m.has_truth; });
  if (truth == results.models.end()) throw std::logic_error("demo: no identified model of the true robot's kind");
  return IdentifiedController{mech::loadPredictionModel(output / truth->file).model,
                              campaign.robot.geometry_model.nominal.values(), modelLabel(results.truth_model)};
}

}  // namespace mire::pipeline::demo
