// report.json of `mire identify` (doc/report-json.md): the model, the fit's quality, every
// parameter with its σ, the full covariance of the free parameters, the per-pose residuals,
// the identifiability and the Monte-Carlo study. SI units throughout (m, rad).
#include "identify_report.hpp"

#include <nlohmann/json.hpp>

#include <cmath>

namespace mire::app {
namespace {

namespace mech = mire::mechanism;

const char* kNoLines = "no --lines given";

Json fitJson(const IdentifyReportData& data) {
  const mech::IdentificationResult& r = data.result;
  Json fit;
  fit["poses"] = r.poses.size();
  fit["weighted"] = r.weighted;
  fit["free_parameters"] = r.free_names.size();
  fit["converged"] = r.converged;
  setNumber(fit, "chi2", r.chi2, "not computed");
  fit["dof"] = r.dof;
  setNumber(fit, "chi2_per_dof", r.chi2 / std::max(1, r.dof), "not computed");
  fit["covariance_method"] = r.covarianceMethod();
  setNumber(fit, "covariance_scale2", r.covarianceScale2(), "not computed");
  setNumber(fit, "rms_joint_residual", r.rms_joint_residual, "not computed");
  fit["outliers"] = r.outliers;
  setNumber(fit, "v3_before_m", data.v3_before_m >= 0.0 ? data.v3_before_m : NAN,
            data.v3_before_m < 0.0 ? kNoLines : "the nominal model could not follow the lines");
  setNumber(fit, "v3_after_m", data.v3_after_m >= 0.0 ? data.v3_after_m : NAN, kNoLines);
  return fit;
}

// Every parameter in model order: SI value before and after, σ (0 when fixed).
Json parametersJson(const IdentifyReportData& data) {
  const mech::ParameterSet& parameters = data.result.model.parameters;
  Json list = Json::array();
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    const mech::Parameter& p = parameters[i];
    Json item{{"name", p.name}, {"unit", mech::unitName(p.unit)}, {"fixed", p.fixed}};
    setNumber(item, "initial", data.initial[i].value, "not computed");
    setNumber(item, "value", p.value, "not computed");
    setNumber(item, "sigma", data.result.sigma[static_cast<Eigen::Index>(i)], "not computed");
    list.push_back(item);
  }
  return list;
}

Json covarianceOf(const mech::IdentificationResult& r) {
  std::vector<std::string> units;
  for (const std::string& name : r.free_names) units.push_back(mech::unitName(r.model.parameters.at(name).unit));
  return covarianceJson(r.free_names, units, r.covariance);
}

// Each term of the covariance (doc/uncertainty.md, "How the terms add up") with its σ per free
// parameter: what each error source contributes (the σ add in quadrature to `covariance`'s).
Json covarianceTermsJson(const mech::IdentificationResult& r) {
  Json list = Json::array();
  for (const mech::CovarianceTerm& term : r.covariance_terms) {
    Json item{{"name", term.name}};
    if (!term.method.empty()) item["method"] = term.method;
    Json sigma;
    for (std::size_t f = 0; f < r.free_names.size(); ++f) {
      const auto k = static_cast<Eigen::Index>(f);
      setNumber(sigma, r.free_names[f], std::sqrt(term.covariance(k, k)), "negative variance");
    }
    item["sigma"] = sigma;
    list.push_back(item);
  }
  return list;
}

// Joint residuals q̄ − f per pose [joint units], before (initial model) and after.
Json posesJson(const IdentifyReportData& data) {
  Json list = Json::array();
  for (std::size_t k = 0; k < data.result.poses.size(); ++k) {
    const mech::PoseResidual& p = data.result.poses[k];
    Json item{{"id", p.id}, {"residual", numberArray(p.residual)}};
    if (k < data.residuals_before.size() && data.residuals_before[k].id == p.id)
      item["residual_before"] = numberArray(data.residuals_before[k].residual);
    setNumber(item, "chi2", p.chi2, "not computed");
    item["outlier"] = p.outlier;
    item["used"] = p.used;
    list.push_back(item);
  }
  return list;
}

Json identifiabilityJson(const mech::IdentifiabilityReport& report) {
  Json out{{"parameters", report.parameter_names}, {"scaling", report.scaling}};
  out["singular_values"] = numberArray(report.singular_values);
  setNumber(out, "condition_number", report.condition_number, "the scaled Jacobian is singular");
  out["rank"] = report.rank;
  out["identifiable"] = report.identifiable;
  out["unidentifiable"] = report.unidentifiable;
  Json combinations = Json::array();
  for (const auto& c : report.combinations) combinations.push_back(c.text());
  out["combinations"] = combinations;
  return out;
}

// Per subset size: the criteria and every parameter's spread (sample σ over the runs, SI).
Json studyJson(const IdentifyReportData& data) {
  const mech::MonteCarloStudy& study = *data.study;
  const bool lines = data.v3_after_m >= 0.0;
  Json subsets = Json::array();
  for (const auto& s : study.summaries) {
    Json item{{"poses", s.subset_size}, {"runs_ok", s.runs_ok}, {"runs_failed", s.runs_failed}};
    setNumber(item, "v1_mean", s.v1_mean, "no successful run");
    setNumber(item, "v1_sigma", s.v1_sigma, "fewer than 2 successful runs");
    setNumber(item, "v2_mean", s.v2_mean, "no successful run");
    setNumber(item, "v2_sigma", s.v2_sigma, "fewer than 2 successful runs");
    setNumber(item, "v3_mean_m", lines ? s.v3_mean : NAN, lines ? "no successful run" : kNoLines);
    setNumber(item, "v3_sigma_m", lines ? s.v3_sigma : NAN, lines ? "fewer than 2 successful runs" : kNoLines);
    Json sigma;
    for (std::size_t i = 0; i < study.parameter_names.size(); ++i)
      setNumber(sigma, study.parameter_names[i], s.sigma[static_cast<Eigen::Index>(i)], "fewer than 2 successful runs");
    item["parameter_sigma"] = sigma;
    subsets.push_back(item);
  }
  return {{"subsets", subsets}};
}

}  // namespace

void writeIdentifyReportJson(const std::filesystem::path& path, const IdentifyReportData& data) {
  Json doc = reportHeader("identify", data.provenance);
  doc["model"] = {{"name", data.model_name},
                  {"variant", data.variant},
                  {"label", data.model_label},
                  {"external_form", mech::externalFormName(data.result.model.external.form())}};
  doc["fit"] = fitJson(data);
  doc["parameters"] = parametersJson(data);
  doc["covariance"] = covarianceOf(data.result);
  doc["covariance_terms"] = covarianceTermsJson(data.result);
  doc["poses"] = posesJson(data);
  if (data.pose_covariance_file.empty()) {
    doc["pose_covariances_file"] = nullptr;
    doc["pose_covariances_file_null_reason"] =
        "no 6x6 pose covariances read (sigma_ columns of poses.csv, or --unweighted)";
  } else {
    doc["pose_covariances_file"] = data.pose_covariance_file;
  }
  doc["identifiability"] = identifiabilityJson(data.result.identifiability);
  if (data.study) doc["monte_carlo"] = studyJson(data);
  writeReportJson(path, doc);
}

}  // namespace mire::app
