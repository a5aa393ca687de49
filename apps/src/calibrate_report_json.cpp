// report.json of `mire calibrate` (doc/report-json.md): the camera's parameters with σ and
// their full covariance (as camera.yaml), the solution's quality, the projection uncertainty
// and every view with its pose and, for the views used, the pose's 6×6 covariance (the view's
// block of the bundle adjustment's state covariance, marginalised over the target points).
#include "report_json.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace mire::app {
namespace {

namespace cal = mire::calibration;

// Units of the camera's parameters: pixels for fx fy cx cy, none for the distortion terms.
std::vector<std::string> parameterUnits(std::size_t count) {
  std::vector<std::string> units(count, "1");
  for (std::size_t i = 0; i < std::min<std::size_t>(4, count); ++i) units[i] = "px";
  return units;
}

Json cameraJson(const cal::CalibrationResult& result) {
  const cal::Camera& camera = result.camera;
  const std::vector<std::string> names = camera.parameterNames();
  const std::vector<std::string> units = parameterUnits(names.size());
  const std::vector<double> sigma = camera.sigmas();
  Json parameters = Json::array();
  for (std::size_t i = 0; i < names.size(); ++i) {
    const bool fixed = std::find(result.fixed_parameters.begin(), result.fixed_parameters.end(), names[i]) !=
                       result.fixed_parameters.end();
    Json item{{"name", names[i]}, {"unit", units[i]}, {"fixed", fixed}};
    setNumber(item, "value", camera.params[i], "not computed");
    setNumber(item, "sigma", i < sigma.size() ? sigma[i] : NAN, "no covariance");
    setNumber(item, "sigma_inflation", i < result.sigma_inflation.size() ? result.sigma_inflation[i] : NAN,
              "not computed");
    parameters.push_back(item);
  }
  Json out{{"model", cal::distortionModelName(result.model)},
           {"image_width", camera.width},
           {"image_height", camera.height},
           {"parameters", parameters},
           {"covariance", covarianceJson(names, units, camera.covariance)}};
  if (result.covariance_pixel_noise.rows() == static_cast<Eigen::Index>(names.size()))
    out["covariance_pixel_noise"] = covarianceJson(names, units, result.covariance_pixel_noise);
  return out;
}

// --refine-target against the rigid-target calibration (doc/calibration.md, "Weakly determined
// target refinement").
Json targetRefinementJson(const cal::TargetRefinementCheck& check, const char* outside) {
  Json out;
  out["added_unknowns"] = check.added_unknowns;
  out["rigid_target_parameters"] = check.rigid_params;
  out["rigid_target_sigmas"] = check.rigid_sigmas;
  out["shift_in_combined_sigma"] = check.shift_sigmas;
  out["sigma_growth_at_equal_pixel_noise"] = check.information_loss;
  Json rigid, refined;
  setNumber(rigid, "centre_px", check.rigid_uncertainty.centre_px, outside);
  setNumber(rigid, "edge_px", check.rigid_uncertainty.edge_px, outside);
  setNumber(rigid, "corner_px", check.rigid_uncertainty.corner_px, outside);
  setNumber(refined, "centre_px", check.refined_uncertainty.centre_px, outside);
  setNumber(refined, "edge_px", check.refined_uncertainty.edge_px, outside);
  setNumber(refined, "corner_px", check.refined_uncertainty.corner_px, outside);
  out["rigid_target_projection_uncertainty"] = rigid;
  out["refined_projection_uncertainty"] = refined;
  out["largest_intrinsic_shift_sigma"] = check.largest_intrinsic_shift_sigma;
  out["largest_uncertainty_ratio"] = check.largest_uncertainty_ratio;
  out["weakly_determined"] = check.weakly_determined;
  return out;
}

Json qualityJson(const cal::CalibrationResult& result, const cal::ProjectionUncertaintySummary& uncertainty) {
  Json out;
  setNumber(out, "rms_px", result.camera.rms_px, "not computed");
  setNumber(out, "sigma_px", result.sigma_px, "not computed");
  out["views_used"] = result.used_views;
  out["views_rejected"] = result.rejected_views;
  out["points_used"] = result.used_points;
  out["points_rejected"] = result.rejected_points;
  out["free_parameters"] = result.free_parameter_count;
  out["target_refined"] = result.target_refined;
  Json projection;
  setNumber(projection, "distance_m", result.uncertainty_distance_m, "not computed");
  const char* outside = "the pixel is outside the lens model's invertible field";
  setNumber(projection, "centre_px", uncertainty.centre_px, outside);
  setNumber(projection, "edge_px", uncertainty.edge_px, outside);
  setNumber(projection, "corner_px", uncertainty.corner_px, outside);
  out["projection_uncertainty"] = projection;
  out["warnings"] = result.warnings;
  if (result.target_refinement) out["target_refinement"] = targetRefinementJson(*result.target_refinement, outside);
  return out;
}

// The 6×6 block of view `view` in the state covariance (rotation, translation), if it has one.
std::optional<Eigen::MatrixXd> viewCovariance(const cal::CalibrationResult& result, std::size_t view) {
  const auto intrinsics = static_cast<Eigen::Index>(result.camera.params.size());
  for (std::size_t k = 0; k < result.state_view_index.size(); ++k) {
    const Eigen::Index start = intrinsics + 6 * static_cast<Eigen::Index>(k);
    if (result.state_view_index[k] == static_cast<int>(view) && result.state_covariance.rows() >= start + 6)
      return Eigen::MatrixXd(result.state_covariance.block(start, start, 6, 6));
  }
  return std::nullopt;
}

Json viewsJson(const cal::CalibrationResult& result) {
  static const std::vector<std::string> pose_names{"rx", "ry", "rz", "tx", "ty", "tz"};
  static const std::vector<std::string> pose_units{"rad", "rad", "rad", "m", "m", "m"};
  Json list = Json::array();
  for (std::size_t v = 0; v < result.views.size(); ++v) {
    const cal::CalibrationViewResult& view = result.views[v];
    Json item{{"image", view.name},
              {"used", view.used},
              {"points", view.ids.size()},
              {"inliers", std::count(view.inlier.begin(), view.inlier.end(), true)}};
    setNumber(item, "rms_px", view.rms_px, "not computed");
    setNumber(item, "tilt_deg", view.tilt_deg, "not computed");
    item["rotation_rad"] = numberArray(Eigen::VectorXd(view.rotation));
    item["translation_m"] = numberArray(Eigen::VectorXd(view.translation));
    item["rejection_reason"] = view.rejection_reason;
    if (const auto covariance = viewCovariance(result, v)) {
      item["pose_covariance"] = covarianceJson(pose_names, pose_units, *covariance);
    } else {
      item["pose_covariance"] = nullptr;
      item["pose_covariance_null_reason"] = "view not used in the solution";
    }
    list.push_back(item);
  }
  return list;
}

Json structureJson(const cal::ResidualStructure& structure) {
  Json bins = Json::array();
  for (const auto& bin : structure.bins) {
    Json item{{"radius_min_px", bin.radius_min_px},
              {"radius_max_px", bin.radius_max_px},
              {"angle_min_rad", bin.angle_min_rad},
              {"angle_max_rad", bin.angle_max_rad},
              {"points", bin.points},
              {"views", bin.views},
              {"mean_residual_px", numberArray(Eigen::VectorXd(bin.mean_px))},
              {"tested", bin.tested},
              {"significant", bin.significant}};
    setNumber(item, "t2", bin.tested ? bin.t2 : NAN, "too few views in the bin");
    setNumber(item, "p_value", bin.tested ? bin.p_value : NAN, "too few views in the bin");
    bins.push_back(item);
  }
  return Json{{"rings", structure.rings},
              {"sectors", structure.sectors},
              {"ring_edges_px", structure.ring_edges_px},
              {"tested_bins", structure.tested_bins},
              {"significant_bins", structure.significant_bins},
              {"corrected_p_value", structure.corrected_p_value},
              {"significant", structure.significant},
              {"bin_mean_rms_px", structure.structured_rms_px},
              {"bins", bins}};
}

Json nestedJson(const cal::NestedModelTest& test) {
  return Json{{"model", test.model},
              {"held_at_zero", test.fixed},
              {"terms", test.terms},
              {"values", test.values},
              {"sigmas", test.sigmas},
              {"design_effect", test.design_effect},
              {"likelihood_ratio", test.statistic},
              {"dof", test.dof},
              {"p_value", test.p_value},
              {"significant", test.significant},
              {"rms_px", test.rms_px},
              {"intrinsics", test.intrinsics},
              {"intrinsic_shift_sigma", test.intrinsic_shift_sigma},
              {"suggestion", test.suggestion}};
}

Json holdoutJson(const cal::HoldoutCheck& holdout) {
  Json out{{"folds", holdout.folds},
           {"views", holdout.views},
           {"measured_rms_px", holdout.measured_rms_px},
           {"predicted_rms_px", holdout.predicted_rms_px},
           {"noise_only_rms_px", holdout.noise_only_rms_px},
           {"ratio", holdout.ratio},
           {"t_statistic", holdout.t_statistic},
           {"p_value", holdout.p_value},
           {"significant", holdout.significant}};
  setNumber(out, "calibration_sigma_scale", holdout.calibration_sigma_scale, "held-out error not above pixel noise");
  Json jackknife = Json::array();
  for (std::size_t i = 0; i < holdout.names.size(); ++i) {
    Json item{{"name", holdout.names[i]}, {"sigma", holdout.jackknife_sigma[i]}};
    setNumber(item, "ratio_to_printed_sigma", holdout.jackknife_ratio[i], "fixed parameter");
    jackknife.push_back(item);
  }
  out["jackknife"] = jackknife;
  return out;
}

Json modelCheckJson(const cal::ModelCheck& check) {
  Json nested = Json::array();
  for (const auto& test : check.nested) nested.push_back(nestedJson(test));
  Json out{{"verdict", check.verdictLine()},
           {"adequate", check.adequate},
           {"level", check.level},
           {"reasons", check.reasons},
           {"suggestions", check.suggestions},
           {"structure", structureJson(check.structure)},
           {"nested", nested}};
  out["holdout"] = check.holdout ? holdoutJson(*check.holdout) : Json(nullptr);
  return out;
}

}  // namespace

void writeCalibrateReportJson(const std::filesystem::path& path, const ReportProvenance& provenance,
                              const cal::CalibrationResult& result,
                              const cal::ProjectionUncertaintySummary& uncertainty, const cal::ModelCheck& check) {
  Json doc = reportHeader("calibrate", provenance);
  doc["camera"] = cameraJson(result);
  doc["quality"] = qualityJson(result, uncertainty);
  doc["views"] = viewsJson(result);
  doc["model_check"] = modelCheckJson(check);
  writeReportJson(path, doc);
}

}  // namespace mire::app
