// The paper's study in `mire demo` (demo.hpp): on the measured poses of a robot whose truth model
// takes the paper's variants, Tables 1 and 3 (every variant on 71 poses, the others validate),
// Fig. 11, the pose-count study of §6.2, plan and select, the default variant on all poses
// against the truth and the square test of Table 4. The simulator's truth only scores.
#include "demo_stages.hpp"

#include "mire/datasets/iso9283_test.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/evaluation.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/mechanism/variants.hpp"
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

namespace mire::pipeline::demo {
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
                     PaperStudy& results) {
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
                                      const fs::path& poses_csv, const std::string& model) {
  PoseSetFiles files = PoseSetFiles::beside(poses_csv, campaign.joints_file());
  files.lines = campaign.lines_file();
  PoseSet set = readPoseSet(files, mechanism::makeRegisteredModel(model).mechanism->jointColumnNames());
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

// Pose-count study (paper §6.2) of the default variant: 6, 15, 71 poses, repeated.
void poseCountStudy(const DemoOptions& options, const IdentificationData& data,
                    const mechanism::IdentificationModel& initial, PaperStudy& results) {
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

}  // namespace

std::string variantLetters(const std::string& family) {
  std::string letters;
  for (const mechanism::ModelInfo& m : mechanism::registeredModels())
    if (m.family == family) letters += m.variants;
  return letters;
}

// Identification of the variants, the pose-count study, V1–V3 and the square test.
IdentifiedController paperStudyStage(const DemoOptions& options, const datasets::MechanismImageCampaign& campaign,
                                     DemoResults& results) {
  const mechanism::MechanismFamily family = mechanism::mechanismFamilyOf(options.mechanism);
  const fs::path& output = options.output;
  const IdentificationData data = identificationData(options, campaign, output / "poses.csv", family.truth_model);
  const auto& poses = data.poses;
  PaperStudy& study = results.paper.emplace();
  study.variant = mechanism::modelInfo(family.truth_model).default_variant;
  const std::string variant(1, study.variant);

  // Before identification: nominal geometry, external parameters estimated from the data.
  const auto initial = mechanism::makeH4VariantModel(study.variant, data.nominal, poses, data.identification);
  const auto before = mechanism::jointResidualCriteria(initial, poses);
  study.nominal_v1_rad = before.v1_rad;
  study.nominal_v2_rad = before.v2_rad;
  study.nominal_v3_m = mechanism::straightnessCriterion(*initial.mechanism, initial.geometricValues(), data.lines).v3_m;
  results.true_v3_m = trueStraightness(campaign, data.lines);

  // Table 3: every variant on one random set of 71 poses, the other poses validate.
  study.variant_sets = options.quick ? 4 : 25;
  const std::string letters = variantLetters(family.name);
  support::Progress progress(std::string("identification: variants ") + letters.front() + "-" + letters.back(),
                             letters.size());
  for (const char letter : letters) {
    study.variants.push_back(identifyVariant(letter, options, data, study.variant_sets));
    progress.advance();
  }
  progress.finish();
  poseCountStudy(options, data, initial, study);
  study.design = experimentDesignStage(options, family, data.nominal, poses);

  // Square test (paper §6.4): the controller runs the model with nominal, then identified (the
  // default variant, all poses) parameters; the TRUE robot draws the square.
  // The default variant on all poses, as `mire identify` runs it.
  IdentifyOptions identify_options;
  identify_options.fit = data.identification;
  const ModelChoice choice = chooseModel("", variant, data.nominal);
  const auto identified = identify(choice, poses, data.shared, identify_options).result;
  scoreIdentified(campaign, identified, study);
  study.file = "identified_" + variant + ".yaml";
  mechanism::writeParameterFile(output / study.file, identified.model.parameters, identified.sigma,
                                {{"model", choice.model}, {"variant", variant}},
                                family.title + " model 12, variant " + variant + ", identified by mire demo");
  const auto& model = *identified.model.mechanism;
  study.square_before_mm = squareSides(*campaign.robot.h4, model, initial.geometricValues());
  study.square_after_mm = squareSides(*campaign.robot.h4, model, identified.model.geometricValues());

  return {mechanism::predictionModelFrom(choice.model, identified), initial.geometricValues(), "variant " + variant};
}

}  // namespace mire::pipeline::demo
