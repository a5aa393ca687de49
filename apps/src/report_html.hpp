#pragma once
// report.html beside report.json and the Markdown (doc/plots.md): the same results for a
// reader, one self-contained page (mire/report/html.hpp) with vector figures, the command line
// and the inputs' SHA-256. One writer per command, each in <command>_report_html.cpp.
#include <filesystem>
#include <string>
#include <vector>

#include "mire/calibration/calibrate.hpp"
#include "mire/calibration/model_check.hpp"
#include "mire/report/html.hpp"
#include "report_json.hpp"

namespace mire::app {

// The command line as one shell-quoted string ("mire identify --poses 'a b.csv' ...").
std::string commandLineText(const std::vector<std::string>& command_line);
// The provenance section: the command, mire's version, each input file's or folder's SHA-256.
void addProvenance(report::HtmlReport& report, const ReportProvenance& provenance);
// Writes the page atomically.
void writeHtml(const std::filesystem::path& path, const report::HtmlReport& report);

void writeCalibrateReportHtml(const std::filesystem::path& path, const ReportProvenance& provenance,
                              const calibration::CalibrationResult& result,
                              const calibration::ProjectionUncertaintySummary& uncertainty,
                              const calibration::ModelCheck& check);

}  // namespace mire::app
