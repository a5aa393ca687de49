#pragma once
// The demo's report parts (demo.hpp): number formatting for Markdown, the run-time table, the
// calibration and pose-measurement sections and their report.json objects, the closed loop, and
// the paper's study's sections (demo_report_paper.cpp).
#include "demo.hpp"
#include "mire/pipeline/closed_loop.hpp"
#include "number_text.hpp"
#include "report_json.hpp"

#include <ostream>
#include <string>
#include <vector>

namespace mire::app::demo_report {

using app::fixed;
using app::format;
std::string percent(double after, double before);  // signed change, "n/a" when undefined
std::string sci(double value);                     // "%.2e", "n/a" when not finite

// The paper's published values (Renaud et al. 2004): Table 3 per variant A–H (cond, V1 and V2 in
// rad, V3 in m), the variants' parameter counts (Table 2), Table 4's square side errors (mm).
struct PaperVariant {
  double cond, v1, v2, v3;
};
inline constexpr PaperVariant kPaperTable3[8] = {{115, 1.6e-4, 1.4e-3, 6.1e-4}, {160, 5.1e-5, 1.3e-3, 5.4e-4},
                                                 {116, 1.3e-4, 1.2e-3, 6.2e-4}, {161, -2.5e-5, 1.2e-3, 5.5e-4},
                                                 {187, 2.5e-4, 9.8e-4, 7.9e-4}, {192, 2.3e-4, 8.5e-4, 8.8e-4},
                                                 {194, 1.9e-4, 7.1e-4, 8.8e-4}, {220, -3.0e-5, 6.1e-4, 7.7e-4}};
inline constexpr int kPaperParameters[8] = {17, 18, 18, 19, 28, 31, 32, 36};
inline constexpr double kPaperSquareBefore[4] = {6.8, 3.6, 3.8, 6.9};
inline constexpr double kPaperSquareAfter[4] = {0.6, -0.2, 0.4, -0.4};

void writeRunTimeTable(const std::vector<StageTiming>& timings, std::ostream& md);
// "## 1. Camera calibration": views, RMS, projection uncertainty, estimate / σ / truth / error/σ.
void writeCalibrationSection(const pipeline::CalibrationScore& c, std::ostream& md);
// The pose-measurement table (predicted σ, RMS error, `extra_row` if not empty, error/σ pose by pose and
// whitened across poses) and the paragraph that reads it (doc/uncertainty.md).
void writePoseMeasurementTable(const pipeline::MeasurementScore& m, std::ostream& md, const std::string& extra_row = "");

Json calibrationJson(const pipeline::CalibrationScore& c);
Json measurementJson(const pipeline::MeasurementScore& m);
// out["parameters"] (name, unit, value, sigma and the truth under `truth_key`, SI) and
// out["covariance"] of identified parameters.
void setParameterScores(Json& out, const std::vector<DemoParameterScore>& scores, const Eigen::MatrixXd& covariance,
                        const std::string& truth_key, const std::string& no_truth_reason);

// "Closing the loop": the ISO 9283 test before and after compensation, per position (AP_p and its σ,
// RP_l and the camera's noise-only RP_l), under `heading`; `controller` names the nominal controller.
void writeClosedLoopSection(const pipeline::ClosedLoopTest& test, const std::string& heading,
                            const std::string& controller, std::ostream& md);
// {"positions", "cycles", "cube_side_m", "before": figures, "after": figures} (accuracy.json's figures).
Json closedLoopJson(const pipeline::ClosedLoopTest& test);
// What the uncompensated controller runs, in the closed loop's text.
std::string nominalController(const DemoResults& r);

// The paper's study (r.paper): its introduction (title, the simulated H4, run times), and its
// identification sections (Tables 1, 3, 4, the pose-count study, plan and select, the identified
// parameters against the truth).
void writePaperIntroduction(const DemoOptions& options, const DemoResults& r, std::ostream& md);
void writePaperStudy(const DemoResults& r, std::ostream& md);

}  // namespace mire::app::demo_report
