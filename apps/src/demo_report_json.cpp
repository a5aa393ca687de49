// report.json of `mire demo` (doc/report-json.md): the calibration against truth with the
// camera's covariance, the pose measurement's precision, the criteria per variant (Tables 1
// and 3, Fig. 11), the pose-count study, the variant-D parameters against truth with their full
// covariance, and the square test. Units in the key names where they are not SI; no run times.
#include "demo_report_parts.hpp"
#include "report_json.hpp"

#include <nlohmann/json.hpp>

namespace mire::app {
namespace {

const char* kFailed = "the identification failed (see error)";

Json variantsJson(const DemoResults& r) {
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

Json poseCountsJson(const DemoResults& r) {
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

// Variant D on all poses, SI (as identified_D.yaml), with the truth and the full covariance.
Json identifiedJson(const DemoResults& r) {
  Json out{{"variant", "D"}, {"file", "identified_D.yaml"}, {"sigma_method", r.sigma_method}};
  setNumber(out, "chi2_per_dof", r.chi2_per_dof, "not computed");
  out["outlier_poses"] = r.outlier_count;
  demo_report::setParameterScores(out, r.identified, r.identified_covariance, "truth", "not computed");
  return out;
}

}  // namespace

void writeDemoReportJson(const std::filesystem::path& path, const ReportProvenance& provenance,
                         const DemoOptions& options, const DemoResults& r) {
  Json doc = reportHeader("demo", provenance);
  doc["run"] = {{"quick", options.quick}, {"seed", options.seed}};
  doc["calibration"] = demo_report::calibrationJson(r.calibration);
  doc["measurement"] = demo_report::measurementJson(r.measurement);
  Json before;
  setNumber(before, "v1_rad", r.nominal_v1_rad, "not computed");
  setNumber(before, "v2_rad", r.nominal_v2_rad, "not computed");
  setNumber(before, "v3_m", r.nominal_v3_m, "not computed");
  setNumber(before, "true_robot_v3_m", r.true_v3_m, "not computed");
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
  if (r.closed_loop) doc["closed_loop"] = demo_report::closedLoopJson(*r.closed_loop);
  doc["files"] = r.files;
  writeReportJson(path, doc);
}

}  // namespace mire::app
