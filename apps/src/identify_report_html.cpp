// report.html of `mire identify --report` (identify_report.hpp): the identified parameters with
// their σ first, then the fit, the joint residuals per leg (the mechanism's own legs and joint
// units) with the σ band the pose covariances predict, the identifiability, the Monte-Carlo
// spreads beside the analytic σ, and the provenance.
#include "identify_report.hpp"
#include "number_text.hpp"
#include "report_html.hpp"

#include "mire/report/figure.hpp"
#include "mire/report/ticks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace mire::app {
namespace {

namespace rp = mire::report;
namespace mech = mire::mechanism;

// One symmetric y range for every leg of the same unit (display units, widened to a nice tick) so
// the legs compare at a glance.
std::vector<double> sharedLimits(const std::vector<mech::PoseResidual>& residuals,
                                 const std::vector<Eigen::VectorXd>& sigmas, const std::vector<mech::Unit>& units) {
  std::map<mech::Unit, double> largest;
  for (std::size_t k = 0; k < residuals.size(); ++k)
    for (Eigen::Index leg = 0; leg < residuals[k].residual.size() && leg < static_cast<Eigen::Index>(units.size());
         ++leg) {
      const mech::Unit unit = units[static_cast<std::size_t>(leg)];
      double v = std::abs(residuals[k].residual[leg]);
      if (k < sigmas.size()) v = std::max(v, sigmas[k][leg]);
      largest[unit] = std::max(largest[unit], mech::toDisplay(unit, v));
    }
  std::vector<double> out;
  for (const mech::Unit unit : units) {
    const double m = std::max(1.05 * largest[unit], 1e-12);  // a point on the limit stays whole
    out.push_back(rp::linearTicks(-m, m, 7).high);
  }
  return out;
}

// One panel per leg: the residual of every pose (x: pose number in file order), in the joint's
// display unit (deg or mm), on a symmetric axis; with `sigmas`, the ±1σ band.
rp::Figure residualFigure(const std::vector<mech::PoseResidual>& residuals, const std::vector<Eigen::VectorXd>& sigmas,
                          const std::vector<mech::Unit>& units, const std::string& series_label,
                          const std::string& colour) {
  rp::Figure figure;
  const int legs = static_cast<int>(units.size());
  figure.columns = legs <= 4 ? std::min(legs, 2) : 3;
  if (legs == 3) figure.columns = 3;
  figure.panel_width = 780.0 / figure.columns;
  figure.panel_height = legs <= 3 ? 280.0 : 250.0;
  const std::vector<double> limit_display = sharedLimits(residuals, sigmas, units);
  for (int leg = 0; leg < legs; ++leg) {
    const mech::Unit unit = units[static_cast<std::size_t>(leg)];
    rp::Panel panel;
    panel.title = "leg " + std::to_string(leg + 1);
    panel.x = rp::makeAxis("pose", "");
    panel.y = rp::makeAxis("q\xCC\x84 \xE2\x88\x92 f", mech::displayUnitName(unit));
    panel.y.symmetric = true;
    rp::Series points;
    points.label = series_label;
    points.mark = rp::Mark::points;
    points.colour = colour;
    rp::Band band;
    band.label =
        "\xC2\xB1"
        "1\xCF\x83 (pose covariances)";
    for (std::size_t k = 0; k < residuals.size(); ++k) {
      if (residuals[k].residual.size() <= leg) continue;
      points.x.push_back(static_cast<double>(k + 1));
      points.y.push_back(mech::toDisplay(unit, residuals[k].residual[leg]));
      if (k < sigmas.size()) {
        const double s = mech::toDisplay(unit, sigmas[k][leg]);
        band.x.push_back(static_cast<double>(k + 1));
        band.low.push_back(-s);
        band.high.push_back(s);
      }
    }
    if (leg > 0) points.label.clear(), band.label.clear();  // one legend, under the first leg
    panel.series = {points};
    if (!band.x.empty()) panel.bands = {band};
    panel.y.min = -limit_display[static_cast<std::size_t>(leg)],
    panel.y.max = limit_display[static_cast<std::size_t>(leg)];
    panel.references = {{0.0, "", "#555", false}};
    figure.panels.push_back(panel);
  }
  return figure;
}

// Singular values of the scaled Jacobian on a log axis, numbered; their dominant parameters are
// in the table below the figure (one label per bar repeated the same names).
rp::Figure singularValueFigure(const mech::IdentifiabilityReport& report) {
  rp::Panel panel;
  panel.x = rp::makeAxis("direction (descending singular value)", "");
  panel.y = rp::makeAxis("singular value of the scaled J", "", rp::Scale::log10);
  rp::Series bars;
  bars.mark = rp::Mark::bars;
  bars.colour = "#1f77b4";
  for (Eigen::Index k = 0; k < report.singular_values.size(); ++k) {
    panel.categories.push_back(std::to_string(k + 1));
    bars.x.push_back(static_cast<double>(k));
    bars.y.push_back(std::max(report.singular_values[k], report.singular_values[0] * 1e-16));
  }
  panel.series = {bars};
  rp::Figure figure;
  figure.panels = {panel};
  figure.panel_width = 760.0;
  figure.panel_height = 300.0;
  return figure;
}

// Monte-Carlo σ per free parameter and subset size, one panel per unit (never mm and deg on one
// axis), log axis, with the analytic σ of the full fit beside.
rp::Figure spreadFigure(const mech::MonteCarloStudy& study, const mech::IdentificationResult& result, std::size_t poses) {
  std::map<std::string, std::vector<std::size_t>> by_unit;
  const auto& parameters = result.model.parameters;
  for (std::size_t i = 0; i < parameters.size(); ++i)
    if (!parameters[i].fixed) by_unit[mech::displayUnitName(parameters[i].unit)].push_back(i);
  rp::Figure figure;
  figure.panel_width = 780.0;
  figure.panel_height = 300.0;
  for (const auto& [unit, indices] : by_unit) {
    rp::Panel panel;
    panel.title = "parameters in " + (unit.empty() ? std::string("no unit") : unit);
    panel.x = rp::makeAxis("parameter", "");
    panel.y = rp::makeAxis("\xCF\x83", unit, rp::Scale::log10);
    for (const std::size_t i : indices) panel.categories.push_back(parameters[i].name);
    for (const auto& summary : study.summaries) {
      rp::Series bars;
      bars.mark = rp::Mark::bars;
      bars.label = "Monte-Carlo, " + std::to_string(summary.subset_size) + " poses";
      for (std::size_t c = 0; c < indices.size(); ++c) {
        bars.x.push_back(static_cast<double>(c));
        bars.y.push_back(
            mech::toDisplay(parameters[indices[c]].unit, summary.sigma[static_cast<Eigen::Index>(indices[c])]));
      }
      panel.series.push_back(bars);
      // What that spread should be from the analytic σ: subsets of n of the same N poses share
      // most of them (delete-d jackknife), σ·√(N/n − 1).
      const double factor = std::sqrt(std::max(0.0, static_cast<double>(poses) / summary.subset_size - 1.0));
      rp::Series expected = bars;
      expected.label =
          "analytic \xCF\x83\xC2\xB7\xE2\x88\x9A(N/n \xE2\x88\x92 1), n = " + std::to_string(summary.subset_size);
      expected.colour = "#9a9a9a";
      for (std::size_t c = 0; c < indices.size(); ++c)
        expected.y[c] =
            factor * mech::toDisplay(parameters[indices[c]].unit, result.sigma[static_cast<Eigen::Index>(indices[c])]);
      panel.series.push_back(expected);
    }
    rp::Series analytic;
    analytic.mark = rp::Mark::bars;
    analytic.label = "analytic \xCF\x83, all " + std::to_string(poses) + " poses";
    analytic.colour = "#333333";
    for (std::size_t c = 0; c < indices.size(); ++c) {
      analytic.x.push_back(static_cast<double>(c));
      analytic.y.push_back(
          mech::toDisplay(parameters[indices[c]].unit, result.sigma[static_cast<Eigen::Index>(indices[c])]));
    }
    panel.series.push_back(analytic);
    figure.panels.push_back(panel);
  }
  return figure;
}

std::string display(const mech::Parameter& p, double si) {
  return format(p.unit == mech::Unit::Radian ? "%.5f" : "%.4f", mech::toDisplay(p.unit, si));
}

void addParameters(rp::HtmlReport& page, const IdentifyReportData& data) {
  const mech::IdentificationResult& result = data.result;
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < result.model.parameters.size(); ++i) {
    const auto& p = result.model.parameters[i];
    const double start = data.initial[i].value;
    const double sigma = p.fixed ? 0.0 : mech::toDisplay(p.unit, result.sigma[static_cast<Eigen::Index>(i)]);
    rows.push_back({p.name, mech::displayUnitName(p.unit),
                    p.fixed ? display(p, p.value) + " (fixed)" : rp::withSigma(mech::toDisplay(p.unit, p.value), sigma),
                    display(p, start), display(p, p.value - start)});
  }
  page.table({"parameter", "unit", "identified \xC2\xB1 1\xCF\x83", "initial", "change"}, rows);
}

// χ²/dof against its spread for `dof` degrees of freedom (≈ 1 ± √(2/dof)): below, the pose
// covariances overstate the scatter; above, a misfit.
std::string chi2Reading(const mech::IdentificationResult& result) {
  if (!result.weighted) return "unweighted fit (\xCF\x83 from the residuals)";
  const double ratio = result.chi2 / std::max(1, result.dof), spread = std::sqrt(2.0 / std::max(1, result.dof));
  if (ratio < 1.0 - 3.0 * spread) return "below 1: the pose covariances overstate the scatter";
  if (ratio > 1.0 + 3.0 * spread) return "above 1: the model does not explain the poses to their covariances";
  return "consistent with the pose covariances";
}

void addFit(rp::HtmlReport& page, const IdentifyReportData& data) {
  const mech::IdentificationResult& result = data.result;
  const auto& id = result.identifiability;
  std::string outliers;
  for (const auto& o : result.outliers) outliers += (outliers.empty() ? "" : ", ") + o;
  page.keyValues(
      {{"model", data.model_label},
       {"poses", std::to_string(result.poses.size()) + (result.weighted ? " (weighted by their covariances)" : "")},
       {"free parameters", std::to_string(result.free_names.size())},
       {"\xCF\x87\xC2\xB2/dof", format("%.3g", result.chi2 / std::max(1, result.dof)) + " (" +
                                    std::to_string(result.dof) + " dof): " + chi2Reading(result)},
       {"\xCF\x83 method", result.covarianceMethod() + format(" (covariance \xC3\x97 %.3g)", result.covarianceScale2())},
       {"condition number", format("%.4g", id.condition_number) + " (" + id.scaling + "), rank " +
                                std::to_string(id.rank) + " of " + std::to_string(id.parameter_names.size())},
       {"outlier poses", outliers.empty() ? "none" : outliers}});
}

void addIdentifiability(rp::HtmlReport& page, const mech::IdentifiabilityReport& id) {
  std::vector<std::vector<std::string>> rows;
  for (Eigen::Index k = 0; k < id.singular_values.size(); ++k)
    rows.push_back({std::to_string(k + 1), format("%.4g", id.singular_values[k]),
                    static_cast<std::size_t>(k) < id.dominant_parameters.size()
                        ? id.dominant_parameters[static_cast<std::size_t>(k)]
                        : ""});
  page.table({"direction", "singular value", "dominant parameter"}, rows);
  if (id.combinations.empty()) return;
  page.subsection("Unidentifiable directions");
  std::vector<std::vector<std::string>> combinations;
  for (const auto& c : id.combinations) combinations.push_back({c.dependent, c.text()});
  page.table({"dependent", "what the data identify"}, combinations);
}

// The paper's criteria over the Monte-Carlo runs per subset size (mean ± σ over the runs).
void addStudyTable(rp::HtmlReport& page, const mech::MonteCarloStudy& study, bool lines) {
  const double deg = mech::toDisplay(mech::Unit::Radian, 1.0);
  std::vector<std::vector<std::string>> rows;
  for (const auto& s : study.summaries)
    rows.push_back({std::to_string(s.subset_size), std::to_string(s.runs_ok) + " / " + std::to_string(s.runs_failed),
                    rp::withSigma(s.v1_mean * deg, s.v1_sigma * deg), rp::withSigma(s.v2_mean * deg, s.v2_sigma * deg),
                    lines ? rp::withSigma(s.v3_mean * 1e3, s.v3_sigma * 1e3) : "n/a (no --lines)"});
  page.table({"poses per subset", "runs ok / failed", "V1 (deg)", "V2 (deg)", "V3 (mm)"}, rows);
}

std::string leadText(const IdentifyReportData& data, const std::vector<mech::Unit>& units) {
  const mech::IdentificationResult& result = data.result;
  double before = 0.0;
  long n = 0;
  for (const auto& p : data.residuals_before) before += p.residual.squaredNorm(), n += p.residual.size();
  before = n > 0 ? std::sqrt(before / n) : 0.0;
  std::string text = data.model_label + ": " + std::to_string(result.free_names.size()) +
                     " parameters identified from " + std::to_string(result.poses.size()) +
                     " poses (values \xC2\xB1 1\xCF\x83 below); joint residual RMS " +
                     format("%.4f", mech::toDisplay(units.front(), result.rms_joint_residual)) + " " +
                     mech::displayUnitName(units.front()) + " after, " +
                     format("%.4f", mech::toDisplay(units.front(), before)) + " before identification";
  if (data.v3_after_m >= 0.0)
    text += "; straightness V3 " + format("%.4f", data.v3_after_m * 1e3) + " mm after, " +
            format("%.4f", data.v3_before_m * 1e3) + " mm before";
  return text + ".";
}

}  // namespace

std::vector<Eigen::VectorXd> jointResidualSigmas(const mechanism::IdentificationResult& result) {
  const auto legs = static_cast<Eigen::Index>(result.model.mechanism->jointCount());
  std::vector<Eigen::VectorXd> out;
  if (!result.weighted) {
    for (std::size_t k = 0; k < result.poses.size(); ++k)
      out.push_back(Eigen::VectorXd::Constant(legs, result.residual_scale));
    return out;
  }
  if (result.whitening.size() != result.poses.size()) return {};
  for (const auto& w : result.whitening) {
    if (w.rows() != legs || w.cols() != legs) return {};
    out.push_back((w.transpose() * w).inverse().diagonal().cwiseSqrt());
  }
  return out;
}

std::vector<NamedFigure> identifyFigures(const IdentifyReportData& data) {
  const mech::IdentificationResult& result = data.result;
  const std::vector<mech::Unit> units = result.model.mechanism->jointUnits();
  const auto& id = result.identifiability;
  std::vector<NamedFigure> figures{
      {"residuals.svg",
       residualFigure(data.residuals_after, jointResidualSigmas(result), units, "after identification", "#1f77b4"),
       "Joint residuals q\xCC\x84 \xE2\x88\x92 f(X) per pose and leg after identification (" + data.model_label +
           "), with the \xC2\xB1"
           "1\xCF\x83 band the pose covariances predict for each pose; \xCF\x87\xC2\xB2/dof " +
           format("%.3g", result.chi2 / std::max(1, result.dof)) + " measures how well the points fill it."},
      {"residuals_before.svg", residualFigure(data.residuals_before, {}, units, "nominal geometry", "#7f7f7f"),
       "The same residuals before identification (nominal geometry), on their own scale."},
      {"singular_values.svg", singularValueFigure(id),
       "Singular values of the column-scaled identification Jacobian (condition number " +
           format("%.4g", id.condition_number) + "); the parameter dominating each direction is in the table below."}};
  if (data.study)
    figures.push_back(
        {"monte_carlo_spread.svg", spreadFigure(*data.study, result, result.poses.size()),
         "Spread (\xCF\x83 over the runs) of every free parameter per subset size, one panel per unit, beside "
         "the analytic \xCF\x83 of the fit on all " +
             std::to_string(result.poses.size()) +
             " poses and, for each subset size, what that spread should be from it: subsets of n drawn from the "
             "same N poses share most of them, so their spread is near the analytic \xCF\x83 \xC3\x97 "
             "\xE2\x88\x9A(N/n \xE2\x88\x92 1) (delete-d jackknife), not \xE2\x88\x9A(N/n)."});
  return figures;
}

void writeIdentifyReportHtml(const std::filesystem::path& path, const IdentifyReportData& data) {
  const mech::IdentificationResult& result = data.result;
  const std::vector<mech::Unit> units = result.model.mechanism->jointUnits();
  rp::HtmlReport page("Mechanism identification report");
  page.lead(leadText(data, units));
  page.section("Identified parameters");
  addParameters(page, data);
  page.section("Fit");
  addFit(page, data);
  const std::vector<NamedFigure> figures = identifyFigures(data);
  page.figure(figures[0].figure, figures[0].caption);
  page.figure(figures[1].figure, figures[1].caption);
  page.section("Identifiability");
  page.figure(figures[2].figure, figures[2].caption);
  addIdentifiability(page, result.identifiability);
  if (!data.gauge_text.empty()) {
    page.subsection("Gauge (model-consistent poses)");
    page.preformatted(data.gauge_text);
  }
  if (data.study) {
    page.section("Monte-Carlo study");
    page.figure(figures[3].figure, figures[3].caption);
    addStudyTable(page, *data.study, data.v3_after_m >= 0.0);
  }
  addProvenance(page, data.provenance);
  writeHtml(path, page);
}

}  // namespace mire::app
