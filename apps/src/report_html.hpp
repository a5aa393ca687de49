#pragma once
// report.html beside report.json and the Markdown (doc/plots.md): the same results for a
// reader, one self-contained page (mire/report/html.hpp) with vector figures, the command line
// and the inputs' SHA-256. One writer per command, each in <command>_report_html.cpp.
#include <filesystem>
#include <string>
#include <vector>

#include "mire/calibration/calibrate.hpp"
#include "mire/calibration/model_check.hpp"
#include "mire/mechanism/experiment_design.hpp"
#include "mire/mechanism/model_selection.hpp"
#include "mire/report/html.hpp"
#include "report_json.hpp"

namespace mire::app {

// The command line as one shell-quoted string ("mire identify --poses 'a b.csv' ...").
std::string commandLineText(const std::vector<std::string>& command_line);
// The provenance section: the command, mire's version, each input file's or folder's SHA-256.
void addProvenance(report::HtmlReport& report, const ReportProvenance& provenance);
// Writes the page atomically.
void writeHtml(const std::filesystem::path& path, const report::HtmlReport& report);

// A report's figure with the file name the Markdown report links (`<file>`, an SVG) and its caption.
struct NamedFigure {
  std::string file;
  report::Figure figure;
  std::string caption;
};
// Each figure as a standalone SVG file in `dir` (atomically); returns the names written.
std::vector<std::string> writeSvgFiles(const std::filesystem::path& dir, const std::vector<NamedFigure>& figures);

// calibrate's figures (calibrate_report_html.cpp): residuals.svg, projection_uncertainty.svg,
// residuals_per_view.svg, model_check.svg.
std::vector<NamedFigure> calibrateFigures(const calibration::CalibrationResult& result,
                                          const calibration::ModelCheck& check);

void writeCalibrateReportHtml(const std::filesystem::path& path, const ReportProvenance& provenance,
                              const calibration::CalibrationResult& result,
                              const calibration::ProjectionUncertaintySummary& uncertainty,
                              const calibration::ModelCheck& check);

// `mire plan --report`: the predicted σ of every free parameter from the planned, random and all
// candidate poses (plan_report_html.cpp).
void writePlanReportHtml(const std::filesystem::path& path, const PlanReportSettings& settings,
                         const mechanism::DesignReport& report, const std::string& text);

// `mire select --report`: the cross-validated score of every candidate with its standard error and
// the one-SE threshold (select_report_html.cpp). The figure is select_cv.svg's too.
report::Figure selectFigure(const mechanism::SelectionResult& result, mechanism::Unit joint_unit);
void writeSelectReportHtml(const std::filesystem::path& path, const ReportProvenance& provenance,
                           const mechanism::SelectionResult& result, mechanism::Unit joint_unit, int folds,
                           const std::string& table);

}  // namespace mire::app
