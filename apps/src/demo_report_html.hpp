#pragma once
// report.html of `mire demo` (doc/plots.md, demo_report_html.cpp), with its parts: the paper's
// study (demo_report_html_paper.cpp) and the sections every demo has (demo_report_html_parts.cpp):
// the calibration and the pose measurement against the simulator's truth, identified parameters'
// error/σ, the closed loop, the run times.
#include <filesystem>
#include <string>
#include <vector>

#include "demo.hpp"
#include "mire/pipeline/closed_loop.hpp"
#include "mire/report/html.hpp"
#include "report_html.hpp"
#include "report_json.hpp"

namespace mire::app::demo_html {

// Camera calibration: the intrinsics ± σ beside the truth and error/σ, with its figure.
void addCalibration(report::HtmlReport& page, const pipeline::CalibrationScore& c);
// Pose measurement: predicted σ and the RMS error to truth per component, error/σ rows.
void addMeasurement(report::HtmlReport& page, const pipeline::MeasurementScore& m);
// Identified parameters ± σ against the truth (display units), and `figure` (the error/σ figure).
void addParameterScores(report::HtmlReport& page, const std::vector<DemoParameterScore>& scores,
                        const NamedFigure& figure);
// error/σ of every parameter with the ±1σ and ±2σ bands an honest σ predicts.
NamedFigure parameterScoreFigure(const std::vector<DemoParameterScore>& scores, const std::string& title,
                                 const std::string& file);
// The ISO 9283 test before / after compensation: figure and tables.
void addClosedLoop(report::HtmlReport& page, const pipeline::ClosedLoopTest& test, const std::string& controller);
void addRunTimes(report::HtmlReport& page, const std::vector<StageTiming>& timings);

// The paper's study (results.paper): the page's title, lead and introduction, its identification
// sections (Tables 1 and 3 with Fig. 11, the pose-count study, plan and select, the identified
// parameters, the square test), and its figures (fig11_v3_per_variant.svg, pose_count_study.svg).
std::string paperTitle();
std::string paperLead(const DemoResults& results);
std::string paperIntroduction(const DemoOptions& options);
void addPaperStudy(report::HtmlReport& page, const DemoResults& results);
std::vector<NamedFigure> paperFigures(const DemoResults& results);

}  // namespace mire::app::demo_html

namespace mire::app {

// The figures report.md links as SVG files (and report.html shows): the paper's study's, and
// parameter_errors_<model>.svg for each model with a truth.
std::vector<NamedFigure> demoFigures(const DemoResults& results);

void writeDemoReportHtml(const std::filesystem::path& path, const ReportProvenance& provenance,
                         const DemoOptions& options, const DemoResults& results);

}  // namespace mire::app
