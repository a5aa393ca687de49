// report.json of `mire select` (doc/report-json.md): every candidate's scores (as
// select_scores.csv, at full precision, plus χ², residual count and free parameters), the
// nested F-tests and the recommendation. No covariance: select estimates none (a candidate's
// covariance comes from `mire identify`).
#include "report_json.hpp"

#include <nlohmann/json.hpp>

namespace mire::app {
namespace {

namespace mech = mire::mechanism;

Json scoreJson(const mech::ModelScore& s) {
  const std::string failed = "the identification failed: " + s.message;
  Json item{{"label", s.label},     {"model", s.model_name},      {"ok", s.ok},
            {"message", s.message}, {"parameters", s.parameters}, {"free_names", s.free_names}};
  setNumber(item, "cv_rms", s.ok ? s.cv_rms() : NAN, failed);
  setNumber(item, "cv_rms_se", s.ok ? s.cv_rms_se() : NAN, s.ok ? "fewer than 2 folds" : failed);
  setNumber(item, "fit_rms", s.ok ? s.fit_rms : NAN, failed);
  setNumber(item, "chi2", s.ok ? s.chi2 : NAN, failed);
  item["weighted"] = s.weighted;
  item["residuals"] = s.residuals;
  setNumber(item, "aic", s.ok ? s.aic : NAN, failed);
  setNumber(item, "bic", s.ok ? s.bic : NAN, failed);
  setNumber(item, "condition", s.ok ? s.condition : NAN, s.ok ? "the scaled Jacobian is singular" : failed);
  item["rank"] = s.rank;
  setNumber(item, "v3_m", s.v3, s.ok ? "no --lines given, or the model could not follow them" : failed);
  return item;
}

Json testsJson(const mech::SelectionResult& r) {
  Json list = Json::array();
  for (const mech::NestedTest& t : r.tests) {
    Json item{{"simpler", r.scores.at(static_cast<std::size_t>(t.simpler)).label},
              {"richer", r.scores.at(static_cast<std::size_t>(t.richer)).label}};
    setNumber(item, "F", t.F, "not computed");
    setNumber(item, "p_value", t.p_value, "not computed");
    item["df1"] = t.df1;
    item["df2"] = t.df2;
    list.push_back(item);
  }
  return list;
}

}  // namespace

void writeSelectReportJson(const std::filesystem::path& path, const ReportProvenance& provenance,
                           const mech::SelectionResult& result, mech::Unit joint_unit, int folds, unsigned seed) {
  Json doc = reportHeader("select", provenance);
  doc["folds"] = folds;
  doc["seed"] = seed;
  doc["score_unit"] = mech::unitName(joint_unit);
  Json scores = Json::array();
  for (const mech::ModelScore& s : result.scores) scores.push_back(scoreJson(s));
  doc["scores"] = scores;
  doc["tests"] = testsJson(result);
  doc["best"] = result.scores.at(static_cast<std::size_t>(result.best)).label;
  doc["recommended"] = result.recommendedLabel();
  writeReportJson(path, doc);
}

}  // namespace mire::app
