// The demo's stages: simulate the campaign, then run the real pipeline on its files
// exactly as a user would (calibrate from images, measure poses from images, identify from
// poses.csv + joints.csv), and score against the simulator's truth only at the end.
#include "demo.hpp"

#include "mire/datasets/iso9283_test.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/evaluation.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/mechanism/variants.hpp"
#include "mire/pipeline/closed_loop.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/pipeline/pose_set.hpp"
#include "mire/support/progress.hpp"
#include "mire/support/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numeric>
#include <optional>
#include <random>
#include <stdexcept>

namespace mire::app {
namespace fs = std::filesystem;

namespace {

using support::upperMedian;

// The robot's own straightness along the recorded lines: positions from the TRUE FKM.
double trueStraightness(const datasets::MechanismImageCampaign& campaign,
                        const std::vector<std::vector<Eigen::VectorXd>>& lines) {
  double total = 0.0;
  for (std::size_t l = 0; l < lines.size(); ++l) {
    std::vector<Eigen::Vector3d> points;
    datasets::H4Pose guess(campaign.lines[l].front());
    for (const auto& q : lines[l]) {
      const auto pose = campaign.robot.h4->pose(datasets::H4Joints(q), guess);
      if (!pose) continue;
      guess = *pose;
      points.emplace_back(pose->head<3>());
    }
    total += mechanism::straightness(points);
  }
  return total / static_cast<double>(lines.size());
}

std::array<double, 4> squareSides(const datasets::H4TrueKinematics& robot, const mechanism::Mechanism& model,
                                  const Eigen::VectorXd& geometric) {
  const auto command = [&](const datasets::H4Pose& pose) -> std::optional<datasets::H4Joints> {
    const auto ikm = model.inverseKinematics(geometric, model.poseToTransform(Eigen::VectorXd(pose)));
    if (!ikm.reachable()) return std::nullopt;
    return datasets::H4Joints(ikm.joints);
  };
  const auto result = datasets::squareTest(robot, command);
  std::array<double, 4> sides_mm{};
  for (int k = 0; k < 4; ++k) sides_mm[k] = 1e3 * result.side_error_m[k];
  return sides_mm;
}

// error/σ of every identified parameter against the simulator's truth (scoring only).
void scoreIdentified(const datasets::MechanismImageCampaign& campaign, const mechanism::IdentificationResult& result,
                     DemoResults& results) {
  const auto& p = result.model.parameters;
  Eigen::VectorXd truth(static_cast<Eigen::Index>(p.size()));
  truth << campaign.robot.geometry.values(), result.model.external.valuesFrom(campaign.bTc, campaign.mTe);
  truth[static_cast<Eigen::Index>(p.index("z_BC"))] +=
      truth[static_cast<Eigen::Index>(p.index("z_ME"))] - p.value("z_ME");
  for (const auto& name : result.free_names) {
    const std::size_t i = p.index(name);
    const auto unit = p[i].unit;
    const double sigma = result.sigma[static_cast<Eigen::Index>(i)], true_value = truth[static_cast<Eigen::Index>(i)];
    results.identified.push_back({name, mechanism::displayUnitName(unit), mechanism::toDisplay(unit, p[i].value),
                                  mechanism::toDisplay(unit, sigma), mechanism::toDisplay(unit, true_value),
                                  mechanism::unitName(unit), p[i].value, sigma, true_value});
  }
  results.identified_covariance = result.covariance;
  results.sigma_method = result.covarianceMethod();
  results.chi2_per_dof = result.chi2 / std::max(1, result.dof);
  results.outlier_count = result.outliers.size();
}

// What every step of stage 4 shares: the observations, the recorded lines, Table 3's split
// (one random set of 71 poses identifies, the other poses validate), the nominal and options.
struct IdentificationData {
  std::vector<mechanism::PoseObservation> poses;
  std::optional<mechanism::SharedPoseTerm> shared;  // the calibration's error every pose shares
  std::vector<std::vector<Eigen::VectorXd>> lines;
  std::vector<mechanism::PoseObservation> subset, validation;
  std::size_t train = 0;
  mechanism::H4Nominal nominal;
  mechanism::IdentificationOptions identification;
};

IdentificationData identificationData(const DemoOptions& options, const datasets::MechanismImageCampaign& campaign,
                                      const fs::path& poses_csv) {
  pipeline::PoseSetFiles files = pipeline::PoseSetFiles::beside(poses_csv, campaign.joints_file());
  files.lines = campaign.lines_file();
  pipeline::PoseSet set =
      pipeline::readPoseSet(files, mechanism::makeH4Mechanism(mechanism::H4ModelKind::Model12)->jointColumnNames());
  IdentificationData data;
  data.poses = std::move(set.observations.poses);
  data.shared = std::move(set.shared);
  data.lines = set.lineJoints();
  std::vector<mechanism::PoseObservation> shuffled = data.poses;
  std::mt19937_64 rng(options.seed);
  std::shuffle(shuffled.begin(), shuffled.end(), rng);
  data.train = std::min<std::size_t>(71, data.poses.size() - 1);
  data.subset.assign(shuffled.begin(), shuffled.begin() + static_cast<std::ptrdiff_t>(data.train));
  data.validation.assign(shuffled.begin() + static_cast<std::ptrdiff_t>(data.train), shuffled.end());
  return data;
}

// One row of Table 3: the variant identified on the subset, validated on the other poses,
// and Fig. 11's mean V3 over repeated random sets of 71 poses.
DemoVariant identifyVariant(char letter, const DemoOptions& options, const IdentificationData& data, int sets) {
  DemoVariant row;
  row.letter = letter;
  try {
    const auto identified = mechanism::identifyH4Variant(letter, data.nominal, data.subset, data.identification);
    row.free_parameters = static_cast<int>(identified.free_names.size());
    row.cond = identified.identifiability.condition_number;
    const auto criteria = mechanism::jointResidualCriteria(identified.model, data.validation);
    row.v1_rad = criteria.v1_rad;
    row.v2_rad = criteria.v2_rad;
    row.v3_m =
        mechanism::straightnessCriterion(*identified.model.mechanism, identified.model.geometricValues(), data.lines).v3_m;
    mechanism::MonteCarloOptions study;
    study.subset_sizes = {static_cast<int>(data.train)};
    study.repeats = sets;
    study.seed = options.seed + static_cast<std::uint64_t>(letter);
    study.identification = data.identification;
    const auto model = mechanism::makeH4VariantModel(letter, data.nominal, data.poses, data.identification);
    const auto summary = mechanism::runMonteCarloStudy(model, data.poses, data.lines, study).summaries.front();
    row.v3_mean_m = summary.v3_mean;
    row.v3_sigma_m = summary.v3_sigma;
  } catch (const std::exception& e) {
    row.error = e.what();
    std::cerr << "mire demo: variant " << letter << ": " << e.what() << "\n";
  }
  return row;
}

// Pose-count study (paper §6.2): 6, 15, 71 poses, repeated.
void poseCountStudy(const DemoOptions& options, const IdentificationData& data,
                    const mechanism::IdentificationModel& initial, DemoResults& results) {
  results.pose_count_repeats = options.quick ? 20 : 100;
  mechanism::MonteCarloOptions study;
  study.subset_sizes = {6, 15, static_cast<int>(data.train)};
  study.repeats = results.pose_count_repeats;
  study.seed = options.seed;
  study.identification = data.identification;
  support::Progress study_progress("identification: pose-count study",
                                   study.subset_sizes.size() * static_cast<std::size_t>(study.repeats));
  study.on_run_done = [&study_progress] { study_progress.advance(); };
  const auto counts = mechanism::runMonteCarloStudy(initial, data.poses, data.lines, study);
  study_progress.finish();
  const Eigen::VectorXd& sigma_six = counts.summaries.front().sigma;
  for (const auto& summary : counts.summaries) {
    DemoPoseCount row;
    row.size = summary.subset_size;
    row.runs_ok = summary.runs_ok;
    row.v1_mean = summary.v1_mean;
    row.v2_mean = summary.v2_mean;
    row.v2_sigma = summary.v2_sigma;
    row.v3_mean = summary.v3_mean;
    row.v3_sigma = summary.v3_sigma;
    std::vector<double> ratios;
    for (Eigen::Index k = 0; k < summary.sigma.size(); ++k)
      if (sigma_six[k] > 0.0) ratios.push_back(summary.sigma[k] / sigma_six[k]);
    row.median_parameter_sigma_ratio = upperMedian(ratios);
    results.pose_counts.push_back(row);
  }
}

// What the closing stage needs of the identification: variant D's prediction model and the
// nominal geometry it started from (the uncompensated controller's).
struct IdentifiedController {
  mechanism::PredictionModel model;
  Eigen::VectorXd nominal;
};

// Stage 4: identification of the variants, the pose-count study, V1–V3 and the square test.
IdentifiedController identifyStage(const DemoOptions& options, const datasets::MechanismImageCampaign& campaign,
                                   const fs::path& output, DemoResults& results) {
  const fs::path poses_csv = output / "poses.csv";
  const IdentificationData data = identificationData(options, campaign, poses_csv);
  const auto& poses = data.poses;

  // Before identification: nominal geometry, external parameters estimated from the data.
  const auto initial = mechanism::makeH4VariantModel('D', data.nominal, poses, data.identification);
  const auto before = mechanism::jointResidualCriteria(initial, poses);
  results.nominal_v1_rad = before.v1_rad;
  results.nominal_v2_rad = before.v2_rad;
  results.nominal_v3_m = mechanism::straightnessCriterion(*initial.mechanism, initial.geometricValues(), data.lines).v3_m;
  results.true_v3_m = trueStraightness(campaign, data.lines);

  // Table 3: every variant on one random set of 71 poses, the other poses validate.
  results.variant_sets = options.quick ? 4 : 25;
  const std::string letters = "ABCDEFGH";
  support::Progress progress("identification: variants A-H", letters.size());
  for (const char letter : letters) {
    results.variants.push_back(identifyVariant(letter, options, data, results.variant_sets));
    progress.advance();
  }
  progress.finish();
  poseCountStudy(options, data, initial, results);
  results.design = experimentDesignStage(options, data.nominal, poses);

  // Square test (paper §6.4): the controller runs model 12 with nominal, then identified (D,
  // all poses) parameters; the TRUE robot draws the square.
  // Variant D on all poses, as `mire identify` runs it.
  pipeline::IdentifyOptions identify_options;
  identify_options.fit = data.identification;
  const pipeline::ModelChoice variant_d = pipeline::chooseModel("", "D", data.nominal);
  const auto identified_d = pipeline::identify(variant_d, poses, data.shared, identify_options).result;
  scoreIdentified(campaign, identified_d, results);
  mechanism::writeParameterFile(output / "identified_D.yaml", identified_d.model.parameters, identified_d.sigma,
                                {{"model", variant_d.model}, {"variant", "D"}},
                                "H4 model 12, variant D, identified by mire demo");
  const auto& model = *identified_d.model.mechanism;
  results.square_before_mm = squareSides(*campaign.robot.h4, model, initial.geometricValues());
  results.square_after_mm = squareSides(*campaign.robot.h4, model, identified_d.model.geometricValues());

  return {mechanism::predictionModelFrom(variant_d.model, identified_d), initial.geometricValues()};
}

// Stage 5, closing the loop: the ISO 9283 test with the nominal, then the identified model's
// commands, measured through the calibrated camera.
pipeline::ClosedLoopTest closedLoopStage(const DemoOptions& options, const datasets::MechanismImageCampaign& campaign,
                                         const calibration::Camera& camera, const metrology::Target& target,
                                         const IdentifiedController& identified) {
  datasets::Iso9283Spec iso = datasets::iso9283SpecFor(campaign.robot);
  iso.seed = options.seed;
  iso.joint_repeatability = datasets::MechanismImageCampaignSpec::reference("h4").encoder_noise_rad;
  return pipeline::closedLoopTest(identified.model, identified.nominal, datasets::reachOf(campaign.robot), campaign.bTc,
                                  campaign.mTe, iso, pipeline::calibratedCameraReading(campaign.camera, camera, target));
}

}  // namespace

DemoResults runDemo(const DemoOptions& options) {
  DemoResults results;
  const fs::path& output = options.output;
  fs::create_directories(output);
  const auto stage = [&](const std::string& name, const auto& work) { timedStage(results.timings, name, work); };

  datasets::MechanismImageCampaignSpec spec = datasets::MechanismImageCampaignSpec::reference("h4");
  spec.seed = options.seed;
  if (options.quick) {
    spec.calibration_views = 15;
    spec.images_per_pose = 3;
    spec.line_points = 10;
  }
  std::optional<datasets::MechanismImageCampaign> campaign;
  stage("simulate the campaign (render images, record joints)", [&] {
    std::optional<support::Progress> progress;
    campaign =
        datasets::generateMechanismImageCampaign(spec, output / "campaign", [&](std::size_t done, std::size_t total) {
          if (!progress) progress.emplace("simulation: rendering", total);
          progress->advance(done > 0 ? 1 : 0);
        });
  });
  const metrology::Target target = metrology::Target::fromFile(campaign->target_file());
  calibration::Camera camera;
  stage("calibrate the camera from images", [&] {
    camera =
        pipeline::calibrateStage(campaign->calibration_images(), campaign->camera, target, output, results.calibration);
  });
  stage("measure 81 target poses from images", [&] {
    pipeline::measureStage(
        campaign->pose_images(), [&](const std::string& id) { return campaign->trueCameraTMarker(id); }, camera, target,
        output / "poses.csv", results.measurement);
  });
  std::optional<IdentifiedController> identified;
  stage("identify (variants A-H, pose-count study, plan and select, V1-V3, square test)",
        [&] { identified = identifyStage(options, *campaign, output, results); });
  stage("close the loop (variant D commands, ISO 9283 before / after)",
        [&] { results.closed_loop = closedLoopStage(options, *campaign, camera, target, *identified); });
  results.files = writeDemoReport(options, results);
  return results;
}

}  // namespace mire::app
