// report.json of `mire demo` (doc/report-json.md, doc/demo-mechanisms.md): the calibration against
// truth with the camera's covariance, the pose measurement's precision; then the paper's study
// (the criteria per variant of Tables 1 and 3, Fig. 11, the pose-count study, the default
// variant's parameters against truth with their full covariance, the square test) or every
// model's parameters against the truth in its gauge with the full covariance, V3 and the
// positioning test before and after; the closed loop. Units in the key names where they are not
// SI; no run times (never the same twice).
#include "demo.hpp"
#include "demo_report_parts.hpp"
#include "report_json.hpp"

#include <nlohmann/json.hpp>

namespace mire::app {
namespace {

const char* kFailed = "the identification failed (see error)";

Json variantsJson(const PaperStudy& r) {
  Json list = Json::array();
  for (const DemoVariant& v : r.variants) {
    const bool ok = v.error.empty();
    Json item{{"variant", std::string(1, v.letter)}, {"error", v.error}, {"free_parameters", v.free_parameters}};
    setNumber(item, "condition_number", ok ? v.cond : NAN, kFailed);
    setNumber(item, "v1_rad", ok ? v.v1_rad : NAN, kFailed);
    setNumber(item, "v2_rad", ok ? v.v2_rad : NAN, kFailed);
    setNumber(item, "v3_m", ok ? v.v3_m : NAN, kFailed);
    setNumber(item, "v3_mean_m", ok ? v.v3_mean_m : NAN, kFailed);
    list.push_back(item);
  }
  return list;
}

Json poseCountsJson(const PaperStudy& r) {
  Json list = Json::array();
  const char* none = "no successful run";
  for (const DemoPoseCount& row : r.pose_counts) {
    Json item{{"poses", row.size}, {"runs_ok", row.runs_ok}};
    setNumber(item, "v1_mean_rad", row.v1_mean, none);
    setNumber(item, "v2_mean_rad", row.v2_mean, none);
    setNumber(item, "v2_sigma_rad", row.v2_sigma, none);
    setNumber(item, "v3_mean_m", row.v3_mean, none);
    setNumber(item, "v3_sigma_m", row.v3_sigma, none);
    setNumber(item, "median_parameter_sigma_ratio", row.median_parameter_sigma_ratio, none);
    list.push_back(item);
  }
  return list;
}

// The default variant on all poses, SI (as its identified file), with the truth and the full covariance.
Json identifiedJson(const PaperStudy& r) {
  Json out{{"variant", std::string(1, r.variant)}, {"file", r.file}, {"sigma_method", r.sigma_method}};
  setNumber(out, "chi2_per_dof", r.chi2_per_dof, "not computed");
  out["outlier_poses"] = r.outlier_count;
  demo_report::setParameterScores(out, r.identified, r.identified_covariance, "truth", "not computed");
  return out;
}

void setPaperStudy(Json& doc, const DemoResults& results) {
  const PaperStudy& r = *results.paper;
  Json before;
  setNumber(before, "v1_rad", r.nominal_v1_rad, "not computed");
  setNumber(before, "v2_rad", r.nominal_v2_rad, "not computed");
  setNumber(before, "v3_m", r.nominal_v3_m, "not computed");
  setNumber(before, "true_robot_v3_m", results.true_v3_m, "not computed");
  doc["before_identification"] = before;
  doc["variants"] = variantsJson(r);
  doc["variant_sets"] = r.variant_sets;
  doc["pose_counts"] = poseCountsJson(r);
  doc["pose_count_repeats"] = r.pose_count_repeats;
  doc["plan_and_select"] = {{"plan_candidates", r.design.plan_candidates},
                            {"plan_median_sigma_ratio_vs_random", r.design.plan_sigma_ratio},
                            {"plan_position_sigma_m", r.design.plan_position_sigma_m},
                            {"random_position_sigma_m", r.design.random_position_sigma_m},
                            {"select_folds", r.design.folds},
                            {"select_recommended", r.design.recommended}};
  doc["identified"] = identifiedJson(r);
  doc["square_test"] = {
      {"side_error_nominal_mm", numberArray(std::vector<double>(r.square_before_mm.begin(), r.square_before_mm.end()))},
      {"side_error_identified_mm", numberArray(std::vector<double>(r.square_after_mm.begin(), r.square_after_mm.end()))}};
}

Json modelJson(const DemoModelScore& s) {
  const char* none = "the model failed on this test";
  Json out{
      {"model", s.model}, {"file", s.file},   {"joint_unit", s.joint_unit},    {"free_parameters", s.free_parameters},
      {"rank", s.rank},   {"gauge", s.gauge}, {"sigma_method", s.sigma_method}};
  setNumber(out, "rms_joint_residual_nominal", s.rms_joint_before, "not computed");
  setNumber(out, "rms_joint_residual_identified", s.rms_joint_after, "not computed");
  setNumber(out, "chi2_per_dof", s.chi2_per_dof, "not computed");
  out["has_truth"] = s.has_truth;
  const char* no_truth = "the true robot is not of this model";
  demo_report::setParameterScores(out, s.identified, s.covariance, "truth_in_gauge", no_truth);
  setNumber(out, "error_over_sigma_rms", s.has_truth ? s.error_over_sigma_rms : NAN, no_truth);
  setNumber(out, "error_over_sigma_max", s.has_truth ? s.error_over_sigma_max : NAN, no_truth);
  setNumber(out, "v3_nominal_m", s.v3_before_m, none);
  setNumber(out, "v3_identified_m", s.v3_after_m, none);
  setNumber(out, "square_side_mm", s.square_side_mm, none);
  out["square_side_error_nominal_mm"] =
      numberArray(std::vector<double>(s.square_before_mm.begin(), s.square_before_mm.end()));
  out["square_side_error_identified_mm"] =
      numberArray(std::vector<double>(s.square_after_mm.begin(), s.square_after_mm.end()));
  setNumber(out, "square_rms_nominal_mm", s.square_rms_before_mm, none);
  setNumber(out, "square_rms_identified_mm", s.square_rms_after_mm, none);
  return out;
}

}  // namespace

void writeDemoReportJson(const std::filesystem::path& path, const ReportProvenance& provenance,
                         const DemoOptions& options, const DemoResults& r) {
  Json doc = reportHeader("demo", provenance);
  Json run;
  if (!r.paper) run = {{"mechanism", r.mechanism}, {"mounting", r.mounting}};  // the paper's: its robot, camera fixed
  run["quick"] = options.quick;
  run["seed"] = options.seed;
  doc["run"] = run;
  if (!r.paper) doc["true_robot_model"] = r.truth_model;
  doc["calibration"] = demo_report::calibrationJson(r.calibration);
  doc["measurement"] = demo_report::measurementJson(r.measurement);
  if (r.paper) {
    setPaperStudy(doc, r);
  } else {
    setNumber(doc, "true_robot_v3_m", r.true_v3_m, "not computed");
    Json models = Json::array();
    for (const auto& s : r.models) models.push_back(modelJson(s));
    doc["models"] = models;
  }
  if (r.closed_loop) {
    doc["closed_loop"] = demo_report::closedLoopJson(*r.closed_loop);
  } else {
    doc["closed_loop"] = nullptr;
    doc["closed_loop_null_reason"] =
        "not run with the camera on the effector: the ISO 9283 reading is made through a fixed camera";
  }
  doc["files"] = r.files;
  writeReportJson(path, doc);
}

}  // namespace mire::app
