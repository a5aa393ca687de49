#pragma once
// accuracy.json of `mire accuracy` (doc/accuracy.md, doc/file-formats.md): the ISO 9283 figures
// per position, per pair of positions and per straight line, SI units (m, rad) in the key names,
// each with its σ and its noise-only part; written as report.json is (report_json.hpp).
#include <filesystem>
#include <string>

#include "mire/pipeline/accuracy.hpp"
#include "mire/report/html.hpp"
#include "report_json.hpp"

namespace mire::app {

// {"pose_components", "cycles_used", "unmeasured", "positions", "distances", "lines"}: the figures
// as accuracy.json holds them (the demos' closed-loop section reuses them).
Json accuracyFiguresJson(const pipeline::AccuracyResult& result);

void writeAccuracyJson(const std::filesystem::path& path, const ReportProvenance& provenance,
                       const std::string& model_name, const pipeline::AccuracyResult& result);

// report.html's ISO 9283 section (accuracy_report_html.cpp), shared with the demos' closed loop:
// AP_p per position with its ±1σ error bar beside the noise-only p95, RP_l per position beside the
// noise-only p95, both in mm; one bar series per labelled result (e.g. before / after), the
// positions of the first result's order.
struct LabelledAccuracy {
  std::string label;
  const pipeline::AccuracyResult* result = nullptr;
};
report::Figure accuracyFigure(const std::vector<LabelledAccuracy>& results);
// The per-position table (AP_p ± σ, RP_l, their noise-only p95) of one result, then its distances
// and lines.
void addAccuracyTables(report::HtmlReport& page, const pipeline::AccuracyResult& result);

// `mire accuracy --report DIR`: DIR/report.html.
void writeAccuracyReportHtml(const std::filesystem::path& path, const ReportProvenance& provenance,
                             const std::string& model_name, const pipeline::AccuracyResult& result);

}  // namespace mire::app
