#pragma once
// report.html of the demos (doc/plots.md): `mire demo` (the H4, demo_report_html.cpp) and
// `mire demo --mechanism` (demo_mechanism_report_html.cpp), with the sections both share
// (demo_report_html_parts.cpp): the calibration and the pose measurement against the simulator's
// truth, identified parameters' error/σ, the closed loop, the run times.
#include <filesystem>
#include <string>
#include <vector>

#include "demo.hpp"
#include "demo_mechanism.hpp"
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

}  // namespace mire::app::demo_html

namespace mire::app {

// The figures the demos' report.md links as SVG files (and report.html shows): the H4 demo's
// fig11_v3_per_variant.svg and pose_count_study.svg; the mechanism demo's parameter_errors.svg
// (one per model with a truth: parameter_errors_<model>.svg).
std::vector<NamedFigure> demoFigures(const DemoResults& results);
std::vector<NamedFigure> mechanismDemoFigures(const MechanismDemoResults& results);

void writeDemoReportHtml(const std::filesystem::path& path, const ReportProvenance& provenance,
                         const DemoOptions& options, const DemoResults& results);
void writeMechanismDemoReportHtml(const std::filesystem::path& path, const ReportProvenance& provenance,
                                  const DemoOptions& options, const MechanismDemoResults& results);

}  // namespace mire::app
