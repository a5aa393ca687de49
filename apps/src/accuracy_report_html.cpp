// report.html of `mire accuracy --report` (accuracy_report.hpp): the ISO 9283 figures (doc/accuracy.md)
// with their σ first, one figure of AP_p and RP_l per position beside what the camera's noise alone
// would show, the distance and straightness tables, and the provenance.
#include "accuracy_report.hpp"
#include "report_html.hpp"

#include <cmath>
#include <cstdio>

namespace mire::app {
namespace {

namespace rp = mire::report;

std::string mm(double metres) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3f", metres * 1e3);
  return buffer;
}

std::string deg(double radians) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4f", radians * 180.0 / 3.14159265358979323846);
  return buffer;
}

// The mean of AP_p over positions and its σ (positions measured independently: σ/√n of the RMS σ).
std::pair<double, double> meanAp(const pipeline::AccuracyResult& result) {
  double sum = 0.0, variance = 0.0;
  for (const auto& p : result.positions) sum += p.ap_p, variance += p.sigma_ap_p * p.sigma_ap_p;
  const double n = static_cast<double>(result.positions.size());
  if (n == 0.0) return {NAN, NAN};
  return {sum / n, std::sqrt(variance) / n};
}

rp::Panel positionPanel(const std::vector<LabelledAccuracy>& results, const std::string& title, bool repeatability) {
  rp::Panel panel;
  panel.title = title;
  panel.x = rp::makeAxis("position", "");
  panel.y = rp::makeAxis(repeatability ? "RP_l" : "AP_p", "mm");
  panel.y.include_zero = true;
  const auto& first = *results.front().result;
  for (const auto& p : first.positions) panel.categories.push_back(p.position);
  for (std::size_t r = 0; r < results.size(); ++r) {
    rp::Series bars;
    bars.label = results[r].label;
    bars.mark = rp::Mark::bars;
    rp::Series noise;
    noise.label = results.size() == 1 ? "noise-only p95" : "noise-only p95, " + results[r].label;
    noise.mark = rp::Mark::points;
    noise.colour = r == 0 ? "#555555" : "#111111";
    const auto& positions = results[r].result->positions;
    for (std::size_t k = 0; k < positions.size() && k < first.positions.size(); ++k) {
      const auto& p = positions[k];
      bars.x.push_back(static_cast<double>(k));
      bars.y.push_back((repeatability ? p.rp_l : p.ap_p) * 1e3);
      if (!repeatability) bars.sigma.push_back(p.sigma_ap_p * 1e3);
      noise.x.push_back(static_cast<double>(k));
      noise.y.push_back((repeatability ? p.noise_rp_l.p95 : p.noise_ap_p.p95) * 1e3);
    }
    panel.series.push_back(bars);
    if (r + 1 == results.size()) panel.series.push_back(noise);  // the camera's floor, once
  }
  return panel;
}

}  // namespace

rp::Figure accuracyFigure(const std::vector<LabelledAccuracy>& results) {
  rp::Figure figure;
  figure.columns = 2;
  figure.panel_width = 390.0;
  figure.panel_height = 300.0;
  figure.panels = {positionPanel(results,
                                 "pose accuracy (\xC2\xB1"
                                 "1\xCF\x83)",
                                 false),
                   positionPanel(results, "pose repeatability", true)};
  return figure;
}

void addAccuracyTables(rp::HtmlReport& page, const pipeline::AccuracyResult& result) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& p : result.positions)
    rows.push_back({p.position, std::to_string(p.cycles), rp::withSigma(p.ap_p * 1e3, p.sigma_ap_p * 1e3, 3),
                    mm(p.noise_ap_p.p95), mm(p.rp_l), mm(p.noise_rp_l.p95), deg(p.ap_abc.norm()),
                    deg(p.rp_abc.maxCoeff())});
  page.table({"position", "cycles", "AP_p \xC2\xB1 1\xCF\x83 (mm)", "noise-only AP_p p95 (mm)", "RP_l (mm)",
              "noise-only RP_l p95 (mm)", "|AP_a,b,c| (deg)", "max RP_a,b,c (deg)"},
             rows);
  if (!result.distances.empty()) {
    std::vector<std::vector<std::string>> d_rows;
    for (const auto& d : result.distances)
      d_rows.push_back({d.from + "\xE2\x80\x93" + d.to, std::to_string(d.cycles), mm(d.d_commanded),
                        rp::withSigma(d.ad_p * 1e3, d.sigma_ad_p * 1e3, 3), mm(d.noise_ad_p.p95), mm(d.rd),
                        mm(d.noise_rd.p95)});
    page.table({"distance", "cycles", "commanded (mm)", "AD_p \xC2\xB1 1\xCF\x83 (mm)", "noise-only AD_p p95 (mm)",
                "RD (mm)", "noise-only RD p95 (mm)"},
               d_rows);
  }
  if (!result.lines.empty()) {
    std::vector<std::vector<std::string>> l_rows;
    for (const auto& l : result.lines)
      l_rows.push_back(
          {l.line, std::to_string(l.points), mm(l.rms), mm(l.noise_rms.mean), mm(l.rms_beyond_noise), mm(l.max)});
    page.table({"line", "points", "straightness RMS (mm)", "noise-only RMS (mm)", "beyond the noise (mm)", "max (mm)"},
               l_rows);
  }
  // The standard's warnings as one compact table (a page of paragraphs otherwise).
  std::vector<std::vector<std::string>> warnings;
  for (const auto& p : result.positions)
    for (const auto& w : p.warnings) warnings.push_back({"position " + p.position, w});
  for (const auto& d : result.distances)
    for (const auto& w : d.warnings) warnings.push_back({"distance " + d.from + "-" + d.to, w});
  for (const auto& l : result.lines)
    for (const auto& w : l.warnings) warnings.push_back({"line " + l.line, w});
  if (!warnings.empty()) page.table({"warning", "what the measurement resolves"}, warnings);
}

void writeAccuracyReportHtml(const std::filesystem::path& path, const ReportProvenance& provenance,
                             const std::string& model_name, const pipeline::AccuracyResult& result) {
  rp::HtmlReport page("ISO 9283 accuracy report");
  const auto [mean, sigma] = meanAp(result);
  double worst_rp = 0.0;
  for (const auto& p : result.positions) worst_rp = std::max(worst_rp, p.rp_l);
  page.lead("Pose accuracy AP_p " + rp::withSigma(mean * 1e3, sigma * 1e3, 3) + " mm (mean over " +
            std::to_string(result.positions.size()) + " positions, \xC2\xB1 1\xCF\x83), largest repeatability RP_l " +
            mm(worst_rp) + " mm, from " + std::to_string(result.cycles_used) + " measured cycles (model " + model_name +
            ").");
  page.section("Pose accuracy and repeatability per position");
  page.figure(accuracyFigure({{"measured", &result}}),
              "AP_p (distance of the attained barycentre to the commanded position, ISO 9283 \xC2\xA7"
              "7.2.1) with its "
              "\xC2\xB1"
              "1\xCF\x83 error bar, and RP_l (\xC2\xA7"
              "7.2.2), per position; the dots are what a perfect "
              "robot would show through the measurement noise alone (95th percentile): a bar at or below its dot "
              "is the camera's, not the robot's.");
  addAccuracyTables(page, result);
  if (!result.unmeasured.empty()) {
    std::string ids;
    for (const auto& id : result.unmeasured) ids += (ids.empty() ? "" : ", ") + id;
    page.paragraph("Commanded poses without a measurement (left out): " + ids + ".");
  }
  addProvenance(page, provenance);
  writeHtml(path, page);
}

}  // namespace mire::app
