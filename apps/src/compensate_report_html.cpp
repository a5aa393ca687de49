// report.html of `mire compensate --report` (compensate_report.hpp): what was written and its
// uncertainty first, the σ of every command per component (each unit on its own axis) or the
// controller fit's errors with the expected error's 1σ, what was left out, the provenance.
#include "compensate_report.hpp"
#include "report_html.hpp"

#include <cmath>
#include <cstdio>
#include <map>

namespace mire::app {
namespace {

namespace rp = mire::report;
namespace mech = mire::mechanism;

std::string mm(double metres) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4f", metres * 1e3);
  return buffer;
}

// Per row (file order) the σ of each command component, one panel per display unit.
rp::Figure commandSigmaFigure(const CompensateReportData& data) {
  std::map<std::string, std::vector<std::size_t>> by_unit;
  for (std::size_t k = 0; k < data.units.size(); ++k) by_unit[mech::displayUnitName(data.units[k])].push_back(k);
  rp::Figure figure;
  figure.columns = by_unit.size() > 1 ? 2 : 1;
  figure.panel_width = by_unit.size() > 1 ? 390.0 : 760.0;
  figure.panel_height = 290.0;
  for (const auto& [unit, indices] : by_unit) {
    rp::Panel panel;
    panel.x = rp::makeAxis(data.mode == "grid" ? "grid point" : "pose (file order)", "");
    panel.y = rp::makeAxis("\xCF\x83 of the command", unit);
    panel.y.include_zero = true;
    for (const std::size_t k : indices) {
      rp::Series s;
      s.label = data.component_names[k];
      s.mark = rp::Mark::points;
      for (std::size_t r = 0; r < data.sigmas.size(); ++r) {
        s.x.push_back(static_cast<double>(r + 1));
        s.y.push_back(mech::toDisplay(data.units[k], data.sigmas[r][static_cast<Eigen::Index>(k)]));
      }
      panel.series.push_back(s);
    }
    figure.panels.push_back(panel);
  }
  return figure;
}

// The controller fit: what the controller model cannot correct (RMS, max) beside the error to
// expect on the robot with its 1σ, one axis in mm.
rp::Figure controllerFigure(const mech::ControllerFit& fit) {
  rp::Panel panel;
  panel.x = rp::makeAxis("position error of the robot following the controller's commands", "");
  panel.y = rp::makeAxis("error", "mm");
  panel.y.include_zero = true;
  panel.categories = {"RMS, identified robot", "max, identified robot", "expected RMS on the robot"};
  rp::Series bars;
  bars.label =
      "\xC2\xB1"
      "1\xCF\x83 over robots drawn from the covariance";
  bars.mark = rp::Mark::bars;
  bars.x = {0.0, 1.0, 2.0};
  bars.y = {fit.rms_position_error * 1e3, fit.max_position_error * 1e3, fit.expected_rms_position_error * 1e3};
  bars.sigma = {NAN, NAN, fit.sigma_rms_position_error * 1e3};
  panel.series = {bars};
  rp::Figure figure;
  figure.panels = {panel};
  figure.panel_width = 640.0;
  figure.panel_height = 280.0;
  return figure;
}

std::string leadText(const CompensateReportData& data) {
  if (data.controller) {
    const mech::ControllerFit& fit = *data.controller;
    std::string text = "Controller model " + data.controller_model + " fitted to " + data.model + " over " +
                       std::to_string(fit.poses) + " workspace poses: residual error RMS " +
                       mm(fit.rms_position_error) + " mm (max " + mm(fit.max_position_error) + " mm)";
    if (fit.draws > 0)
      text += "; expected on the robot " +
              rp::withSigma(fit.expected_rms_position_error * 1e3, fit.sigma_rms_position_error * 1e3, 4) +
              " mm RMS (\xC2\xB1 1\xCF\x83)";
    return text + ".";
  }
  std::string text = std::to_string(data.sigmas.size()) +
                     (data.mode == "grid" ? " pose corrections" : " joint commands") + " from " + data.model;
  if (!data.has_covariance) return text + "; no parameter covariance: their \xCF\x83 are not known.";
  text += "; largest \xCF\x83 of a command:";
  for (std::size_t k = 0; k < data.component_names.size(); ++k) {
    double largest = 0.0;
    for (const auto& s : data.sigmas) largest = std::max(largest, s[static_cast<Eigen::Index>(k)]);
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, " %s %.4g %s", data.component_names[k].c_str(),
                  mech::toDisplay(data.units[k], largest), mech::displayUnitName(data.units[k]).c_str());
    text += (k == 0 ? "" : ",") + std::string(buffer);
  }
  return text + ".";
}

}  // namespace

void writeCompensateReportHtml(const std::filesystem::path& path, const CompensateReportData& data) {
  rp::HtmlReport page("Compensation report");
  page.lead(leadText(data));
  page.keyValues({{"mode", data.mode}, {"identified model", data.model}, {"written", data.output}});
  if (data.controller) {
    page.figure(controllerFigure(*data.controller),
                "What the controller model cannot correct on the identified robot (RMS and largest position "
                "error over the workspace poses) and the RMS error to expect on the real robot, which adds the "
                "identification's own uncertainty, with its 1\xCF\x83 over robots drawn from the covariance "
                "(doc/accuracy.md, \"Controller model\").");
  } else if (data.has_covariance && !data.sigmas.empty()) {
    page.figure(commandSigmaFigure(data),
                "The standard uncertainty of every command the identification's covariance implies, per "
                "component, each unit on its own axis.");
  }
  if (!data.left_out.empty()) {
    page.section("Left out");
    std::vector<std::vector<std::string>> rows;
    for (const auto& reason : data.left_out) rows.push_back({reason});
    page.table({"reason"}, rows);
  }
  addProvenance(page, data.provenance);
  writeHtml(path, page);
}

}  // namespace mire::app
