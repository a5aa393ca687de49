// report.html of `mire demo` (demo_report_html.hpp): the result first (the paper's straightness,
// or each model's joint residual, V3 and positioning before and after; the closed loop with its
// σ), then the calibration and the pose measurement against truth, the paper's study
// (demo_report_html_paper.cpp) or each model's parameters against the truth in its gauge (error/σ
// with the band an honest σ predicts) and the criteria tables in the mechanism's own joint unit,
// and the closed loop.
#include "demo_report_html.hpp"
#include "demo_report_parts.hpp"
#include "report_html.hpp"

#include "mire/mechanism/registry.hpp"

#include <cmath>

namespace mire::app {
namespace {

namespace rp = mire::report;
using demo_report::fixed;
using demo_report::percent;

// The joint unit's display scale and name: degrees for a revolute joint, mm for a prismatic one.
std::pair<double, std::string> jointDisplay(const DemoModelScore& s) {
  if (s.joint_unit == "rad") return {180.0 / 3.14159265358979323846, "deg"};
  return {1e3, "mm"};
}

std::string modelsLead(const DemoResults& r) {
  std::string text;
  for (const auto& s : r.models) {
    const auto [scale, unit] = jointDisplay(s);
    text += (text.empty() ? "" : " ") + s.model + ": joint residual RMS " + fixed(scale * s.rms_joint_before, 4) +
            " \xE2\x86\x92 " + fixed(scale * s.rms_joint_after, 4) + " " + unit + ", V3 " +
            fixed(1e3 * s.v3_before_m, 3) + " \xE2\x86\x92 " + fixed(1e3 * s.v3_after_m, 3) + " mm, square RMS " +
            fixed(s.square_rms_before_mm, 3) + " \xE2\x86\x92 " + fixed(s.square_rms_after_mm, 3) + " mm (" +
            percent(s.square_rms_after_mm, s.square_rms_before_mm) + ").";
  }
  return text;
}

// The closed loop's mean AP_p before and after (with its σ), after the lead's first sentence.
std::string closedLoopLead(const pipeline::ClosedLoopTest& t) {
  double before = 0.0, after = 0.0, variance = 0.0;
  for (const auto& p : t.before.positions) before += p.ap_p;
  for (const auto& p : t.after.positions) after += p.ap_p, variance += p.sigma_ap_p * p.sigma_ap_p;
  const double nb = std::max<double>(1.0, static_cast<double>(t.before.positions.size())),
               na = std::max<double>(1.0, static_cast<double>(t.after.positions.size()));
  return " Closed loop (ISO 9283): mean AP_p " + fixed(1e3 * before / nb, 3) + " mm before, " +
         rp::withSigma(1e3 * after / na, 1e3 * std::sqrt(variance) / na, 3) + " mm after compensation.";
}

void addModel(rp::HtmlReport& page, const DemoModelScore& s, const std::string& truth_model) {
  const auto [scale, unit] = jointDisplay(s);
  page.subsection(s.model + " (" + s.file + ")");
  std::string gauge;
  for (const auto& name : s.gauge) gauge += (gauge.empty() ? "" : ", ") + name;
  page.keyValues({{"free parameters", std::to_string(s.free_parameters) + " (rank " + std::to_string(s.rank) +
                                          " before the gauge was fixed)"},
                  {"gauge (held at data-initialised values)", gauge.empty() ? "none" : gauge},
                  {"joint residual RMS (" + unit + ")", fixed(scale * s.rms_joint_before, 4) + " nominal \xE2\x86\x92 " +
                                                            fixed(scale * s.rms_joint_after, 4) + " identified"},
                  {"\xCF\x87\xC2\xB2/dof", fixed(s.chi2_per_dof, 2)},
                  {"\xCF\x83 method", s.sigma_method}});
  if (!s.has_truth) {
    page.paragraph("The simulator's truth is not written in this model's parameters (its geometry is " + truth_model +
                   "'s): judged by V3 and the positioning test below.");
    return;
  }
  page.paragraph("Every free parameter against the truth in the identification's gauge: error/\xCF\x83 RMS " +
                 fixed(s.error_over_sigma_rms, 2) + ", max " + fixed(s.error_over_sigma_max, 2) + ".");
  demo_html::addParameterScores(page, s.identified,
                                demo_html::parameterScoreFigure(s.identified, s.model, "parameter_errors.svg"));
}

void addCriteria(rp::HtmlReport& page, const DemoResults& r) {
  const double side = r.models.empty() ? 100.0 : r.models.front().square_side_mm;
  page.section("4. V3 and the positioning test, before and after identification");
  page.paragraph(
      "V3 (paper eq. 29): straightness of two recorded straight-line motions rebuilt with the model's FKM "
      "(the true robot's own: " +
      fixed(1e3 * r.true_v3_m, 4) + " mm). Positioning test: a " + fixed(side, 0) +
      " mm square commanded through the model's IKM and reached by the true robot, without measurement "
      "(no \xCF\x83; the measured test with its \xCF\x83 is the closed loop below).");
  std::vector<std::vector<std::string>> rows;
  for (const auto& s : r.models)
    rows.push_back({s.model, fixed(1e3 * s.v3_before_m, 4), fixed(1e3 * s.v3_after_m, 4),
                    percent(s.v3_after_m, s.v3_before_m), fixed(s.square_rms_before_mm, 4),
                    fixed(s.square_rms_after_mm, 4), percent(s.square_rms_after_mm, s.square_rms_before_mm)});
  page.table({"model", "V3 nominal (mm)", "V3 identified (mm)", "change", "square RMS nominal (mm)",
              "square RMS identified (mm)", "change"},
             rows);
  std::vector<std::vector<std::string>> sides;
  for (const auto& s : r.models) {
    std::vector<std::string> nominal{s.model + ", nominal"}, identified{s.model + ", identified"};
    for (const double e : s.square_before_mm) nominal.push_back(fixed(e, 4));
    for (const double e : s.square_after_mm) identified.push_back(fixed(e, 4));
    sides.push_back(nominal), sides.push_back(identified);
  }
  page.table({"signed side-length error (mm)", "side 1", "side 2", "side 3", "side 4"}, sides);
}

void addModels(rp::HtmlReport& page, const DemoResults& r) {
  page.section("3. Identification (mire identify --model NAME)");
  for (const auto& s : r.models) addModel(page, s, r.truth_model);
  addCriteria(page, r);
}

std::string modelsTitle(const DemoResults& r) {
  return "mire demo --mechanism " + r.mechanism + ": the " + mechanism::mechanismFamilyOf(r.mechanism).title +
         " in simulation";
}

std::string modelsIntroduction(const DemoOptions& options, const DemoResults& r) {
  return "The simulated robot is " + mechanism::mechanismFamilyOf(r.mechanism).simulated_robot +
         ". The H4 demo's camera and chessboard; mire calibrated the camera and measured every pose from "
         "images, then identified the robot from poses.csv + joints.csv as mire identify --model NAME does. "
         "The simulator's truth (campaign/truth/) only scores. Run: " +
         (options.quick ? std::string("--quick") : std::string("full")) + ", seed " + std::to_string(options.seed) + ".";
}

}  // namespace

std::vector<NamedFigure> demoFigures(const DemoResults& r) {
  std::vector<NamedFigure> figures = r.paper ? demo_html::paperFigures(r) : std::vector<NamedFigure>{};
  for (const auto& s : r.models)
    if (s.has_truth)
      figures.push_back(demo_html::parameterScoreFigure(s.identified, s.model, "parameter_errors_" + s.model + ".svg"));
  return figures;
}

void writeDemoReportHtml(const std::filesystem::path& path, const ReportProvenance& provenance,
                         const DemoOptions& options, const DemoResults& r) {
  rp::HtmlReport page(r.paper ? demo_html::paperTitle() : modelsTitle(r));
  page.lead((r.paper ? demo_html::paperLead(r) : modelsLead(r)) + (r.closed_loop ? closedLoopLead(*r.closed_loop) : ""));
  page.paragraph(r.paper ? demo_html::paperIntroduction(options) : modelsIntroduction(options, r));
  demo_html::addCalibration(page, r.calibration);
  demo_html::addMeasurement(page, r.measurement);
  if (r.paper)
    demo_html::addPaperStudy(page, r);
  else
    addModels(page, r);
  if (r.closed_loop) {
    // The paper's study has no section for V3 and the positioning test (its square test is in 3).
    page.section(std::string(r.paper ? "4" : "5") + ". Closing the loop: ISO 9283 before and after compensation");
    demo_html::addClosedLoop(page, *r.closed_loop, demo_report::nominalController(r));
  }
  page.section("Run time");
  demo_html::addRunTimes(page, r.timings);
  addProvenance(page, provenance);
  writeHtml(path, page);
}

}  // namespace mire::app
