// report.json of `mire plan` (doc/report-json.md): the chosen poses (as plan.csv), the
// predicted σ of every free parameter for the plan, random sets of the same size and the
// whole candidate set (as plan_sigma.csv, at full precision), the plan's full predicted
// covariance (the inverse of its Fisher information) and the predicted position σ.
#include "kinematics_files.hpp"
#include "mire/pipeline/camera_plan.hpp"
#include "report_json.hpp"

#include <nlohmann/json.hpp>

namespace mire::app {
namespace {

namespace mech = mire::mechanism;

const char* kNoInformation = "the design carries no information on this parameter (singular information matrix)";

Json posesJson(const mech::CandidateInformation& info, const std::vector<int>& design) {
  const mech::Mechanism& m = *info.model.mechanism;
  const std::vector<std::string> pose_columns = poseColumnNames(m), joint_columns = m.jointColumnNames();
  Json list = Json::array();
  char id[32];
  for (std::size_t k = 0; k < design.size(); ++k) {
    const auto j = static_cast<std::size_t>(design[k]);
    std::snprintf(id, sizeof id, "p%03zu", k + 1);
    Json pose, joints;
    for (std::size_t c = 0; c < pose_columns.size(); ++c)
      pose[pose_columns[c]] = info.poses[j][static_cast<Eigen::Index>(c)];  // finite: writeReportJson checks
    for (std::size_t c = 0; c < joint_columns.size(); ++c)
      joints[joint_columns[c]] = info.observations[j].joints[static_cast<Eigen::Index>(c)];
    list.push_back({{"pose_id", id}, {"candidate", design[k]}, {"pose", pose}, {"joints", joints}});
  }
  return list;
}

Json parametersJson(const mech::DesignReport& r) {
  Json list = Json::array();
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    Json item{{"name", r.names[i]},
              {"unit", mech::unitName(r.units[i])},
              {"role", static_cast<int>(i) < r.geometric_free ? "geometric" : "mounting"}};
    setNumber(item, "sigma_plan", r.sigma_plan[k], kNoInformation);
    setNumber(item, "sigma_random", r.sigma_random[k], kNoInformation);
    setNumber(item, "sigma_all", r.sigma_all[k], kNoInformation);
    if (r.sigma_plan_shared.size() > 0) setNumber(item, "sigma_plan_shared", r.sigma_plan_shared[k], kNoInformation);
    list.push_back(item);
  }
  return list;
}

Json summaryJson(const mech::DesignReport& r) {
  Json out;
  setNumber(out, "median_ratio_plan_random", r.median_ratio_plan_random, kNoInformation);
  setNumber(out, "position_sigma_plan_rms_m", r.position_sigma_plan_rms, kNoInformation);
  setNumber(out, "position_sigma_plan_max_m", r.position_sigma_plan_max, kNoInformation);
  setNumber(out, "position_sigma_random_rms_m", r.position_sigma_random_rms, kNoInformation);
  out["random_designs_used"] = r.random_designs_used;
  return out;
}

// With --camera: the visibility limits and counts, the pose noise assumed and the predicted
// σ of cTm per planned pose (SI: m, rad), in plan.csv's order.
Json cameraJson(const pipeline::CameraPlanSummary& c) {
  const pipeline::CameraPlanOptions& o = c.options;
  Json sigmas = Json::array();
  const char* keys[6] = {"sigma_tx_m", "sigma_ty_m", "sigma_tz_m", "sigma_rx_rad", "sigma_ry_rad", "sigma_rz_rad"};
  char id[32];
  for (std::size_t k = 0; k < c.sigmas.size(); ++k) {
    std::snprintf(id, sizeof id, "p%03zu", k + 1);
    Json item{{"pose_id", id}};
    for (int i = 0; i < 6; ++i) setNumber(item, keys[i], c.sigmas[k][i], "the pose is not observable from the target");
    sigmas.push_back(item);
  }
  return {
      {"margin_px", o.visibility.margin_px},
      {"max_tilt_deg", o.visibility.max_tilt_deg},
      {"pixel_sigma_px", o.prediction.pixel_sigma},
      {"images_per_pose", o.prediction.images},
      {"systematic_model", o.prediction.systematic_model == metrology::SystematicModel::Constant ? "constant" : "board"},
      {"systematic_px", o.prediction.systematic_px},
      {"systematic_reference_square_px", o.prediction.reference_square_px},
      {"systematic_mean_px", o.prediction.systematic_mean_px},
      {"systematic_grid_px", o.prediction.systematic_grid_px},
      {"candidates_drawn", c.drawn},
      {"candidates_visible", c.visible},
      {"shared_calibration_term", c.shared_term},
      {"excluded_outside", c.outside},
      {"excluded_oblique", c.oblique},
      {"predicted_pose_sigma", sigmas}};
}

}  // namespace

void writePlanReportJson(const std::filesystem::path& path, const PlanReportSettings& settings,
                         const mech::CandidateInformation& info, const mech::DesignReport& report) {
  writePlanReportJson(path, settings, info, report, nullptr);
}

void writePlanReportJson(const std::filesystem::path& path, const PlanReportSettings& settings,
                         const mech::CandidateInformation& info, const mech::DesignReport& report,
                         const pipeline::CameraPlanSummary* camera) {
  Json doc = reportHeader("plan", settings.provenance);
  doc["model"] = settings.model;
  doc["mounting"] = settings.mounting;
  doc["criterion"] = mech::designCriterionName(report.criterion);
  doc["count"] = report.design.size();
  doc["candidates"] = settings.candidates;
  doc["seed"] = settings.seed;
  doc["poses"] = posesJson(info, report.design);
  doc["parameters"] = parametersJson(report);
  std::vector<std::string> units;
  for (const mech::Unit unit : report.units) units.push_back(mech::unitName(unit));
  const Eigen::MatrixXd covariance = mech::designCovariance(info, report.design);
  if (covariance.allFinite()) {
    doc["covariance_plan"] = covarianceJson(report.names, units, covariance);
  } else {
    doc["covariance_plan"] = nullptr;
    doc["covariance_plan_null_reason"] = "the plan's information matrix is singular";
  }
  doc["summary"] = summaryJson(report);
  if (camera != nullptr) doc["camera"] = cameraJson(*camera);
  writeReportJson(path, doc);
}

}  // namespace mire::app
