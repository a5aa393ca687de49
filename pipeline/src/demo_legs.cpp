// The legs section of the mechanism demo (demo_legs.hpp, doc/demo-mechanisms.md "The legs").
#include "mire/pipeline/demo_legs.hpp"

#include "demo_stages.hpp"

#include "mire/datasets/campaign_legs.hpp"
#include "mire/mechanism/evaluation.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/legs_csv.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/pipeline/identify_legs.hpp"
#include "mire/pipeline/leg_measurement.hpp"
#include "mire/pipeline/pose_set.hpp"
#include "mire/support/atomic_file.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <thread>

namespace mire::pipeline {
namespace {

namespace mech = mire::mechanism;

// What a row scores: the identified model and its σ, whatever the observations.
struct Fit {
  mech::IdentificationModel identified;
  Eigen::VectorXd sigma;
  std::size_t free_parameters = 0;
  double chi2 = 0.0;
  int dof = 0;
};

// The legs' lengths in the model's own terms (the hexapod's ρ0_i, the Delta's L and l) against the
// truth's: the same parameter, or the mean of the true robot's per-leg values (the Delta's L_i, l_i).
std::vector<std::pair<std::string, double>> trueLengths(const datasets::TrueRobot& robot,
                                                        const mech::ParameterSet& model) {
  std::vector<std::pair<std::string, double>> lengths;
  for (const std::string name : {"L", "l", "rho01", "rho02", "rho03", "rho04", "rho05", "rho06"}) {
    if (!model.contains(name)) continue;
    if (robot.geometry.contains(name)) {
      lengths.emplace_back(name, robot.geometry.value(name));
      continue;
    }
    double mean = 0.0;
    for (int i = 1; i <= 3; ++i) mean += robot.geometry.value(name + std::to_string(i)) / 3.0;
    lengths.emplace_back(name, mean);
  }
  return lengths;
}

LegsDemoRow score(const std::string& observations, const Fit& fit, const datasets::MechanismImageCampaign& campaign,
                  const PoseSet& data, const std::string& model_name) {
  LegsDemoRow row;
  row.observations = observations;
  row.free_parameters = static_cast<int>(fit.free_parameters);
  row.chi2_per_dof = fit.chi2 / std::max(1, fit.dof);
  double sum = 0.0;
  const auto lengths = trueLengths(campaign.robot, fit.identified.parameters);
  for (const auto& [name, truth] : lengths) {
    const std::size_t i = fit.identified.parameters.index(name);
    const double error = fit.identified.parameters[i].value - truth;
    row.length_error_max_mm = std::max(row.length_error_max_mm, 1e3 * std::abs(error));
    const double z = error / fit.sigma[static_cast<Eigen::Index>(i)];
    sum += z * z;
  }
  row.length_error_over_sigma_rms = std::sqrt(sum / static_cast<double>(lengths.size()));
  // Before: the model's nominal, the same for every row (`both` starts from the target's fit).
  const mech::Mechanism& model = *fit.identified.mechanism;
  const Eigen::VectorXd nominal = mech::makeRegisteredModel(model_name).nominal.values();
  const Eigen::VectorXd identified = fit.identified.geometricValues();
  const auto lines = data.lineJoints();
  row.v3_before_mm = 1e3 * demo::straightnessOf(model, nominal, lines);
  row.v3_after_mm = 1e3 * demo::straightnessOf(model, identified, lines);
  const double side = demo::squareSide(model, nominal);
  row.square_side_mm = 1e3 * side;
  row.square_rms_before_mm = demo::rms(demo::squareSides(campaign.robot, model, nominal, side));
  row.square_rms_after_mm = demo::rms(demo::squareSides(campaign.robot, model, identified, side));
  return row;
}

// Target only: the paper's identification (identify, as `mire identify` without
// --observations and as the target stage of `both`).
Fit targetOnly(const ModelChoice& choice, const std::vector<mech::PoseObservation>& poses) {
  const Identification target = identify(choice, poses, std::nullopt);
  return {target.result.model, target.result.sigma, target.result.free_names.size(), target.result.chi2,
          target.result.dof};
}

Fit withLegs(const ModelChoice& choice, const std::vector<mech::PoseObservation>& poses,
             const std::vector<mech::LegObservation>& legs, mech::Observations observations) {
  const LegIdentification fit = identifyWithLegs(choice, poses, legs, observations);
  return {fit.result.model, fit.result.sigma, fit.result.free_names.size(), fit.result.chi2, fit.result.dof};
}

// The legs measured as `mire measure --legs` does, written to `legs_csv`; the poses where a leg was
// not measured, with why.
std::vector<std::string> measureCampaignLegs(const datasets::MechanismImageCampaign& campaign,
                                             const calibration::Camera& camera, const std::filesystem::path& legs_csv) {
  const LegsSpec spec = readLegsYaml(campaign.legs_file());
  const mech::RegisteredModel model = chooseModel(spec.model, "").registered();
  const auto joints = mech::readJointsCsv(campaign.joints_file(), model.mechanism->jointColumnNames());
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));  // all cores
  std::vector<mech::LegObservation> legs;
  std::vector<std::string> unmeasured;
  for (const PoseLegs& pose : measureLegFolders(camera, spec, joints, campaign.pose_images(), threads)) {
    legs.insert(legs.end(), pose.legs.begin(), pose.legs.end());
    for (const std::string& problem : pose.problems) unmeasured.push_back(pose.pose_id + ": " + problem);
  }
  mech::writeLegsCsv(legs_csv, legs);
  return unmeasured;
}

LegsDemoSection identifyFromLegs(const datasets::MechanismImageCampaign& campaign, const PoseSet& data,
                                 const std::filesystem::path& legs_csv, const std::string& legs_source) {
  LegsDemoSection section;
  section.model = datasets::legsModel(campaign.robot);
  section.legs = legs_source;
  ModelChoice choice = chooseModel(section.model, "");
  applyMounting(choice, "camera-fixed");
  const std::vector<mech::LegObservation> legs = mech::readLegsCsv(legs_csv, choice.registered().mechanism->legCount());
  section.leg_lines = legs.size();
  const std::vector<mech::PoseObservation>& poses = data.observations.poses;
  const auto run = [&](const std::string& name, const auto& fit) {
    try {
      section.rows.push_back(score(name, fit(), campaign, data, section.model));
    } catch (const std::exception& e) {
      section.rows.push_back({name, e.what()});
    }
  };
  run("target", [&] { return targetOnly(choice, poses); });
  run("legs", [&] { return withLegs(choice, poses, legs, mech::Observations::Legs); });
  run("both", [&] { return withLegs(choice, poses, legs, mech::Observations::Both); });
  return section;
}

}  // namespace

LegsDemoSection legsDemoStage(const datasets::MechanismImageCampaign& campaign, const calibration::Camera& camera,
                              const std::filesystem::path& output) {
  const std::filesystem::path legs_csv = output / "legs.csv";
  const std::vector<std::string> unmeasured = measureCampaignLegs(campaign, camera, legs_csv);
  PoseSetFiles files = PoseSetFiles::beside(output / "poses.csv", campaign.joints_file());
  files.lines = campaign.lines_file();
  const PoseSet data = readPoseSet(files, campaign.robot.mechanism().jointColumnNames());
  LegsDemoSection section = identifyFromLegs(campaign, data, legs_csv, "measured on the images (legs.csv)");
  section.unmeasured = unmeasured;
  support::writeFileAtomically(output / "legs.md", legsDemoMarkdown(section));
  return section;
}

std::string legsDemoMarkdown(const LegsDemoSection& section) {
  std::ostringstream out;
  out << "## Legs: identified from the legs, the target, both\n\n"
      << "Model `" << section.model << "`; " << section.leg_lines << " leg lines: " << section.legs << "; "
      << section.unmeasured.size() << " legs or poses not measured (listed below the table).\n"
      << "Lengths: the model's leg lengths (hexapod rho0i, Delta L and l) against the truth's (the mean of its "
         "per-leg values where the model has one length for all legs). V3 and the positioning test (a "
      << (section.rows.empty() ? 0.0 : section.rows.front().square_side_mm)
      << " mm square, side errors RMS) with the nominal, then the identified geometry.\n\n"
      << "| observations | free | χ²/dof | lengths: max \\|error\\| (mm), error/σ RMS | V3 (mm) | square (mm) |\n"
      << "| --- | --- | --- | --- | --- | --- |\n";
  for (const LegsDemoRow& r : section.rows) {
    if (!r.error.empty()) {
      out << "| " << r.observations << " | not run: " << r.error << " | | | | |\n";
      continue;
    }
    out << "| " << r.observations << " | " << r.free_parameters << " | " << r.chi2_per_dof << " | "
        << r.length_error_max_mm << ", " << r.length_error_over_sigma_rms << " | " << r.v3_before_mm << " → "
        << r.v3_after_mm << " | " << r.square_rms_before_mm << " → " << r.square_rms_after_mm << " |\n";
  }
  for (const std::string& problem : section.unmeasured) out << "\n- not measured: " << problem;
  out << "\n";
  return out.str();
}

std::string legsDemoSummary(const LegsDemoSection& section) {
  std::ostringstream out;
  out << "  legs (" << section.leg_lines << " lines " << section.legs << ", " << section.unmeasured.size()
      << " legs or poses not measured):\n";
  for (const LegsDemoRow& r : section.rows) {
    out << "    " << r.observations << ": ";
    if (!r.error.empty()) {
      out << "not run: " << r.error << "\n";
      continue;
    }
    out << "lengths max |error| " << r.length_error_max_mm << " mm (error/σ RMS " << r.length_error_over_sigma_rms
        << "); V3 " << r.v3_before_mm << " -> " << r.v3_after_mm << " mm; square side RMS " << r.square_rms_before_mm
        << " -> " << r.square_rms_after_mm << " mm\n";
  }
  return out.str();
}

}  // namespace mire::pipeline
