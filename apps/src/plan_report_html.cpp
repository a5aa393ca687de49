// report.html of `mire plan --report` (report_html.hpp): the predicted positioning σ first, then
// the predicted σ of every free parameter from the planned poses beside random sets of the same
// size and all candidates (one panel per unit: never mm and degrees on one axis), the plan's text
// and the provenance.
#include "number_text.hpp"
#include "report_html.hpp"

#include <cstdio>
#include <map>

namespace mire::app {
namespace {

namespace rp = mire::report;
namespace mech = mire::mechanism;

rp::Figure sigmaFigure(const mech::DesignReport& r) {
  std::map<std::string, std::vector<std::size_t>> by_unit;  // geometric parameters only
  for (std::size_t i = 0; i < r.names.size() && static_cast<int>(i) < r.geometric_free; ++i)
    by_unit[mech::displayUnitName(r.units[i])].push_back(i);
  rp::Figure figure;
  figure.panel_width = 780.0;
  figure.panel_height = 280.0;
  const std::vector<std::pair<const Eigen::VectorXd*, std::string>> designs{
      {&r.sigma_plan, "planned poses"},
      {&r.sigma_random, "random poses (median of " + std::to_string(r.random_designs_used) + " sets)"},
      {&r.sigma_all, "all candidates"}};
  for (const auto& [unit, indices] : by_unit) {
    rp::Panel panel;
    panel.title = "geometric parameters in " + (unit.empty() ? std::string("no unit") : unit);
    panel.x = rp::makeAxis("parameter", "");
    panel.y = rp::makeAxis("predicted \xCF\x83", unit, rp::Scale::log10);
    for (const std::size_t i : indices) panel.categories.push_back(r.names[i]);
    for (std::size_t d = 0; d < designs.size(); ++d) {
      rp::Series bars;
      bars.label = designs[d].second;
      bars.mark = rp::Mark::bars;
      bars.colour = rp::paletteColour(d);
      for (std::size_t c = 0; c < indices.size(); ++c) {
        const auto k = static_cast<Eigen::Index>(indices[c]);
        bars.x.push_back(static_cast<double>(c));
        bars.y.push_back(k < designs[d].first->size() ? mech::toDisplay(r.units[indices[c]], (*designs[d].first)[k])
                                                      : NAN);
      }
      panel.series.push_back(bars);
    }
    figure.panels.push_back(panel);
  }
  return figure;
}

}  // namespace

void writePlanReportHtml(const std::filesystem::path& path, const PlanReportSettings& settings,
                         const mech::DesignReport& r, const std::string& text) {
  rp::HtmlReport page("Experiment plan report");
  page.lead(std::to_string(r.design.size()) + " poses planned for " + settings.model + " (" +
            mech::designCriterionName(r.criterion) + "-optimal): predicted positioning \xCF\x83 after identification " +
            format("%.4f", r.position_sigma_plan_rms * 1e3) + " mm RMS over the workspace (max " +
            format("%.4f", r.position_sigma_plan_max * 1e3) + " mm), against " +
            format("%.4f", r.position_sigma_random_rms * 1e3) + " mm from random poses; median geometric \xCF\x83 " +
            format("%.2f", r.median_ratio_plan_random) + " \xC3\x97 that of random poses.");
  page.section("Predicted parameter \xCF\x83");
  page.figure(sigmaFigure(r),
              "The standard uncertainty each geometric parameter would have after identifying it from the planned "
              "poses, from random poses of the same number drawn from the " +
                  std::to_string(settings.candidates) +
                  " candidates, and from all candidates (the floor), one panel per unit; the mounting parameters "
                  "(nuisance) are in the table.");
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    const auto show = [&](const Eigen::VectorXd& v) {
      return k < v.size() ? format("%.4g", mech::toDisplay(r.units[i], v[k])) : std::string("n/a");
    };
    rows.push_back({r.names[i], mech::displayUnitName(r.units[i]), show(r.sigma_plan), show(r.sigma_random),
                    show(r.sigma_all), static_cast<int>(i) < r.geometric_free ? "geometric" : "mounting (nuisance)"});
  }
  page.table({"parameter", "unit", "\xCF\x83 plan", "\xCF\x83 random", "\xCF\x83 all candidates", "kind"}, rows);
  page.section("The plan as mire plan printed it");
  page.preformatted(text);
  addProvenance(page, settings.provenance);
  writeHtml(path, page);
}

}  // namespace mire::app
