// report.json of `mire demo --mechanism delta|gough-stewart` (doc/demo-mechanisms.md): the
// calibration and the pose measurement against truth, every model's parameters against the
// truth in its gauge with the full covariance, V3 and the positioning test before and after.
// Units in the key names where they are not SI; no run times (never the same twice).
#include "demo_mechanism.hpp"
#include "demo_report_parts.hpp"

#include <nlohmann/json.hpp>

namespace mire::app {
namespace {

Json modelJson(const MechanismModelScore& s) {
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

void writeMechanismDemoReportJson(const std::filesystem::path& path, const ReportProvenance& provenance,
                                  const DemoOptions& options, const MechanismDemoResults& r) {
  Json doc = reportHeader("demo", provenance);
  doc["run"] = {{"mechanism", r.mechanism}, {"mounting", r.mounting}, {"quick", options.quick}, {"seed", options.seed}};
  doc["true_robot_model"] = r.truth_model;
  doc["calibration"] = demo_report::calibrationJson(r.calibration);
  doc["measurement"] = demo_report::measurementJson(r.measurement);
  setNumber(doc, "true_robot_v3_m", r.true_v3_m, "not computed");
  Json models = Json::array();
  for (const auto& s : r.models) models.push_back(modelJson(s));
  doc["models"] = models;
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
