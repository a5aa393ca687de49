// The sections `mire demo` and `mire demo --mechanism` share in report.html (demo_report_html.hpp).
#include "accuracy_report.hpp"
#include "demo_report_html.hpp"
#include "demo_report_parts.hpp"

#include <cmath>

namespace mire::app::demo_html {
namespace {

namespace rp = mire::report;
using demo_report::fixed;
using demo_report::format;

// error/σ per named quantity on one dimensionless axis, with the ±1σ and ±2σ bands within which
// about 68 % and 95 % of the points fall when the σ are honest.
rp::Figure errorOverSigmaFigure(const std::vector<std::string>& names, const std::vector<double>& z,
                                const std::string& title) {
  rp::Panel panel;
  panel.title = title;
  panel.x = rp::makeAxis("parameter", "");
  panel.y = rp::makeAxis("(estimate \xE2\x88\x92 truth) / \xCF\x83", "");
  panel.y.symmetric = true;
  panel.categories = names;
  rp::Series points;
  points.label = "error / \xCF\x83";
  points.mark = rp::Mark::points;
  points.colour = "#1f77b4";
  double largest = 2.5;
  for (std::size_t k = 0; k < z.size(); ++k) {
    points.x.push_back(static_cast<double>(k));
    points.y.push_back(z[k]);
    if (std::isfinite(z[k])) largest = std::max(largest, 1.05 * std::abs(z[k]));
  }
  const double left = -0.5, right = static_cast<double>(names.size()) - 0.5;
  panel.bands = {{"\xC2\xB1"
                  "2\xCF\x83",
                  {left, right},
                  {-2.0, -2.0},
                  {2.0, 2.0},
                  "#9ecae1"},
                 {"\xC2\xB1"
                  "1\xCF\x83",
                  {left, right},
                  {-1.0, -1.0},
                  {1.0, 1.0},
                  "#3182bd"}};
  panel.series = {points};
  panel.references = {{0.0, "", "#555", false}};
  panel.y.min = -largest, panel.y.max = largest;
  rp::Figure figure;
  figure.panels = {panel};
  figure.panel_width = std::max(560.0, std::min(900.0, 34.0 * static_cast<double>(names.size()) + 160.0));
  figure.panel_height = 280.0;
  return figure;
}

// Predicted σ (median over poses) beside the RMS error to truth, per component: translation in mm,
// rotation in degrees, one panel each.
rp::Figure measurementFigure(const pipeline::MeasurementScore& m) {
  rp::Figure figure;
  figure.columns = 2;
  figure.panel_width = 390.0;
  figure.panel_height = 280.0;
  const std::vector<std::string> translation{"tx", "ty", "tz"}, rotation{"rx", "ry", "rz"};
  for (int part = 0; part < 2; ++part) {
    rp::Panel panel;
    panel.title = part == 0 ? "translation of cTm" : "rotation of cTm";
    panel.x = rp::makeAxis("component", "");
    panel.y = rp::makeAxis("\xCF\x83 or RMS error", part == 0 ? "mm" : "deg");
    panel.y.include_zero = true;
    panel.categories = part == 0 ? translation : rotation;
    rp::Series predicted, actual;
    predicted.label = "predicted \xCF\x83 (median)", actual.label = "RMS error to truth";
    predicted.mark = actual.mark = rp::Mark::bars;
    predicted.colour = "#9ecae1", actual.colour = "#e6550d";
    for (int k = 0; k < 3; ++k) {
      predicted.x.push_back(k), actual.x.push_back(k);
      predicted.y.push_back(part == 0 ? m.median_sigma_mm[k] : m.median_sigma_deg[k]);
      actual.y.push_back(part == 0 ? m.rms_error_mm[k] : m.rms_error_deg[k]);
    }
    panel.series = {predicted, actual};
    figure.panels.push_back(panel);
  }
  return figure;
}

}  // namespace

void addCalibration(rp::HtmlReport& page, const pipeline::CalibrationScore& c) {
  page.section("1. Camera calibration (camera.yaml)");
  page.paragraph(std::to_string(c.views_used) + " of " + std::to_string(c.views_total) + " views used, RMS " +
                 fixed(c.rms_px, 3) + " px; projection uncertainty " + fixed(c.uncertainty_centre_px, 3) +
                 " px at the centre, " + fixed(c.uncertainty_corner_px, 3) + " px at the corner.");
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> names;
  std::vector<double> z;
  for (std::size_t i = 0; i < c.names.size() && i < c.truth.size() && i < c.estimate.size(); ++i) {
    const double sigma = i < c.sigma.size() ? c.sigma[i] : NAN;
    const std::string unit = i < 4 ? "px" : "";
    rows.push_back({c.names[i], unit, rp::withSigma(c.estimate[i], sigma, 6), format("%.6g", c.truth[i]),
                    fixed((c.estimate[i] - c.truth[i]) / sigma, 2)});
    names.push_back(c.names[i]);
    z.push_back((c.estimate[i] - c.truth[i]) / sigma);
  }
  page.table({"parameter", "unit", "estimate \xC2\xB1 1\xCF\x83", "truth", "error / \xCF\x83"}, rows);
  page.figure(errorOverSigmaFigure(names, z, "camera parameters"),
              "Each intrinsic's error to the simulator's truth in units of its own \xCF\x83 (pixel units and "
              "dimensionless distortion coefficients on one axis only as this ratio); with honest \xCF\x83 about "
              "two in three points fall in the \xC2\xB1"
              "1\xCF\x83 band.");
}

void addMeasurement(rp::HtmlReport& page, const pipeline::MeasurementScore& m) {
  page.section("2. Pose measurement (poses.csv)");
  page.paragraph(std::to_string(m.measured) + " of " + std::to_string(m.total) +
                 " poses measured. Predicted \xCF\x83 (median over poses, pixel noise and intrinsics combined) "
                 "against the actual error to truth.");
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> predicted{"predicted \xCF\x83 (mm, deg)"}, error{"RMS error to truth (mm, deg)"},
      pose{"RMS error/\xCF\x83, pose by pose"}, whitened{"RMS error/\xCF\x83, whitened across poses"};
  for (int k = 0; k < 3; ++k)
    predicted.push_back(fixed(m.median_sigma_mm[k], 3)), error.push_back(fixed(m.rms_error_mm[k], 3));
  for (int k = 0; k < 3; ++k)
    predicted.push_back(fixed(m.median_sigma_deg[k], 4)), error.push_back(fixed(m.rms_error_deg[k], 4));
  for (int k = 0; k < 6; ++k)
    pose.push_back(fixed(m.normalized_error_rms[k], 2)), whitened.push_back(fixed(m.whitened_error_rms[k], 2));
  page.table({"component", "tx", "ty", "tz", "rx", "ry", "rz"}, {predicted, error, pose, whitened});
  page.figure(measurementFigure(m),
              "The precision each pose was given (median \xCF\x83 over poses) beside the error it actually has "
              "(RMS to the simulator's truth), translation in mm and rotation in degrees. Whitened by the whole "
              "covariance (the calibration error every pose shares) the RMS error/\xCF\x83 is " +
                  fixed(m.whitened_error_rms_all, 2) + " (1 when the \xCF\x83 are honest; doc/uncertainty.md).");
}

NamedFigure parameterScoreFigure(const std::vector<DemoParameterScore>& scores, const std::string& title,
                                 const std::string& file) {
  std::vector<std::string> names;
  std::vector<double> z;
  for (const auto& p : scores) names.push_back(p.name), z.push_back((p.estimate - p.truth) / p.sigma);
  return {file, errorOverSigmaFigure(names, z, title),
          "Every identified parameter's error to the truth in units of its \xCF\x83 (lengths and angles on one "
          "axis only as this ratio). Unmodelled defects bias the estimates beyond their \xCF\x83 where they "
          "project on a parameter."};
}

void addParameterScores(rp::HtmlReport& page, const std::vector<DemoParameterScore>& scores, const NamedFigure& figure) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& p : scores)
    rows.push_back({p.name, p.unit, rp::withSigma(p.estimate, p.sigma, 5), format("%.5f", p.truth),
                    fixed((p.estimate - p.truth) / p.sigma, 2)});
  page.table({"parameter", "unit", "identified \xC2\xB1 1\xCF\x83", "truth", "error / \xCF\x83"}, rows);
  page.figure(figure.figure, figure.caption);
}

void addClosedLoop(rp::HtmlReport& page, const pipeline::ClosedLoopTest& t, const std::string& controller) {
  page.paragraph(
      "The paper's last step, \"modify the control law accordingly\", checked the ISO 9283 way "
      "(doc/accuracy.md): 5 positions on a diagonal plane of a " +
      fixed(t.spec.side * 1e3, 0) + " mm cube, " + std::to_string(t.spec.cycles) +
      " cycles, measured by the camera. Before: the controller runs " + controller +
      ". After: it sends the identified model's joint commands (mire compensate --poses).");
  page.figure(accuracyFigure({{"before compensation", &t.before}, {"after compensation", &t.after}}),
              "AP_p with its \xC2\xB1"
              "1\xCF\x83 error bar and RP_l per position, before and after compensation; "
              "the dots are the noise-only p95 after compensation (what the camera alone would show).");
  page.subsection("After compensation");
  addAccuracyTables(page, t.after);
}

void addRunTimes(rp::HtmlReport& page, const std::vector<StageTiming>& timings) {
  std::vector<std::vector<std::string>> rows;
  double total = 0.0;
  for (const auto& t : timings) rows.push_back({t.name, fixed(t.seconds, 1)}), total += t.seconds;
  rows.push_back({"total", fixed(total, 1)});
  page.table({"stage", "seconds"}, rows);
}

}  // namespace mire::app::demo_html
