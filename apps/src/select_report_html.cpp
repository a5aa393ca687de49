// report.html of `mire select --report` (report_html.hpp): the recommended model with its
// cross-validated score and standard error first, the scores of every candidate as a figure
// (error bars ±1 SE, the one-SE threshold drawn) and a table, the nested F-tests, the provenance.
#include "number_text.hpp"
#include "report_html.hpp"

#include <cmath>
#include <cstdio>

namespace mire::app {
namespace {

namespace rp = mire::report;
namespace mech = mire::mechanism;

// A cross-validation score is not finite when a candidate could not be fitted.
std::string formatOrNa(const char* pattern, double value) {
  return std::isfinite(value) ? format(pattern, value) : std::string("n/a");
}

}  // namespace

rp::Figure selectFigure(const mech::SelectionResult& r, mech::Unit unit) {
  rp::Panel panel;
  panel.x = rp::makeAxis("candidate (free parameters)", "");
  panel.y = rp::makeAxis("joint residual RMS", mech::displayUnitName(unit));
  panel.y.include_zero = true;
  rp::Series cv, fit;
  cv.label = "cross-validated, \xC2\xB1 1 standard error";
  cv.mark = rp::Mark::bars;
  cv.colour = "#1f77b4";
  fit.label = "fit on all poses";
  fit.mark = rp::Mark::points;
  fit.colour = "#d62728";
  for (std::size_t i = 0; i < r.scores.size(); ++i) {
    const mech::ModelScore& s = r.scores[i];
    panel.categories.push_back(s.label + " (" + std::to_string(s.parameters) + ")");
    cv.x.push_back(static_cast<double>(i));
    cv.y.push_back(s.ok ? mech::toDisplay(unit, s.cv_rms()) : NAN);
    cv.sigma.push_back(s.ok ? mech::toDisplay(unit, s.cv_rms_se()) : NAN);
    fit.x.push_back(static_cast<double>(i));
    fit.y.push_back(s.ok ? mech::toDisplay(unit, s.fit_rms) : NAN);
  }
  panel.series = {cv, fit};
  if (r.best >= 0) {
    const mech::ModelScore& best = r.scores[static_cast<std::size_t>(r.best)];
    panel.references = {
        {mech::toDisplay(unit, best.cv_rms() + best.cv_rms_se()), "one-SE threshold (best + its SE)", "#555", true}};
  }
  rp::Figure figure;
  figure.panels = {panel};
  figure.panel_width = std::max(600.0, std::min(900.0, 90.0 * static_cast<double>(r.scores.size()) + 160.0));
  figure.panel_height = 300.0;
  return figure;
}

void writeSelectReportHtml(const std::filesystem::path& path, const ReportProvenance& provenance,
                           const mech::SelectionResult& r, mech::Unit unit, int folds, const std::string& table) {
  const std::string u = mech::displayUnitName(unit);
  rp::HtmlReport page("Model selection report");
  const mech::ModelScore& rec = r.scores.at(static_cast<std::size_t>(r.recommended));
  const mech::ModelScore& best = r.scores.at(static_cast<std::size_t>(r.best));
  std::string lead = "Recommended: " + rec.label + " (" + std::to_string(rec.parameters) +
                     " free parameters), cross-validated joint residual " +
                     rp::withSigma(mech::toDisplay(unit, rec.cv_rms()), mech::toDisplay(unit, rec.cv_rms_se()), 5) +
                     " " + u + " (" + std::to_string(folds) + "-fold, \xC2\xB1 1 standard error)";
  if (r.recommended == r.best)
    lead += ", the best score.";
  else
    lead += "; the best score, " + best.label + "'s " +
            rp::withSigma(mech::toDisplay(unit, best.cv_rms()), mech::toDisplay(unit, best.cv_rms_se()), 5) + " " + u +
            ", is within one standard error of it with more parameters.";
  page.lead(lead);
  page.section("Cross-validated scores");
  page.figure(selectFigure(r, unit),
              "Held-out joint residual RMS of every candidate over " + std::to_string(folds) +
                  " folds with its standard error, beside the residual of the fit on all poses; the simplest "
                  "candidate below the dashed line (the best score plus its standard error) is recommended.");
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < r.scores.size(); ++i) {
    const mech::ModelScore& s = r.scores[i];
    if (!s.ok) {
      rows.push_back({s.label, std::to_string(s.parameters), "failed: " + s.message, "", "", "", "", "", ""});
      continue;
    }
    rows.push_back(
        {s.label + (static_cast<int>(i) == r.recommended ? " (recommended)" : ""), std::to_string(s.parameters),
         rp::withSigma(mech::toDisplay(unit, s.cv_rms()), mech::toDisplay(unit, s.cv_rms_se()), 5),
         formatOrNa("%.5f", mech::toDisplay(unit, s.fit_rms)), formatOrNa("%.1f", s.aic), formatOrNa("%.1f", s.bic),
         formatOrNa("%.1f", s.condition), std::to_string(s.rank), formatOrNa("%.4f", s.v3 * 1e3)});
  }
  page.table({"candidate", "parameters", "CV RMS \xC2\xB1 SE (" + u + ")", "fit RMS (" + u + ")", "AIC", "BIC", "cond",
              "rank", "V3 (mm)"},
             rows);
  page.section("The table as mire select printed it (with the nested F-tests)");
  page.preformatted(table + "recommended: " + r.recommendedLabel() + "\n");
  addProvenance(page, provenance);
  writeHtml(path, page);
}

}  // namespace mire::app
