// The demo's report (doc/simulation.md, doc/demo-mechanisms.md): report.md with the calibration and
// the pose measurement against truth, then the paper's study (demo_report_paper.cpp) or each model's
// identification (parameters against the truth in its gauge) with V3 and the positioning test
// before and after, the closed loop; the figures as SVG files; report.html and report.json.
#include "demo.hpp"
#include "demo_report_html.hpp"
#include "demo_report_parts.hpp"
#include "report_json.hpp"

#include "mire/mechanism/registry.hpp"
#include "mire/support/atomic_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace mire::app {

namespace {

using demo_report::fixed;
using demo_report::format;
using demo_report::percent;

mechanism::MechanismFamily family(const std::string& name) { return mechanism::mechanismFamilyOf(name); }

// The encoder noise the campaign adds follows the joints' unit (mechanism_image_campaign.hpp).
bool revoluteJoints(const std::string& name) {
  return mechanism::makeRegisteredModel(family(name).truth_model).mechanism->jointUnits().front() ==
         mechanism::Unit::Radian;
}

void writeIntroduction(const DemoOptions& options, const DemoResults& r, std::ostream& md) {
  md << "# mire demo --mechanism " << r.mechanism << ": the " << family(r.mechanism).title
     << " from images to an identified robot, in simulation\n\n"
     << "The simulated robot is " << family(r.mechanism).simulated_robot
     << ". It carries the H4 demo's chessboard (12 × 9 corners of 16 mm) and is seen by the H4 demo's reference "
        "camera (1024×768, 3.8 mm lens, strong barrel distortion), rendered by the same renderer; encoder noise "
     << (revoluteJoints(r.mechanism) ? "2·10⁻⁵ rad" : "1 µm") << ". "
     << (r.mounting == "camera-on-effector"
             ? "Mounting: **camera on the effector** (`--mounting camera-on-effector`): the camera rides on the "
               "effector and looks at the board fixed in the workspace, cTm = cTe·eTb(X)·bTm; the mounting "
               "identified is eTc and bTm. "
             : "Mounting: camera fixed, the board on the effector, cTm = cTb·bTe(X)·eTm. ")
     << "mire calibrated the camera from images, measured every pose from images (`poses.csv` with its "
        "covariance and shared-term side files) and identified the robot from `poses.csv` + `joints.csv` exactly "
        "as `mire identify --model NAME` does. The simulator's truth (`campaign/truth/`) is used only to score.\n\n"
     << "Run: " << (options.quick ? "`--quick` (fewer images)" : "full") << ", seed " << options.seed << ".\n\n";
  demo_report::writeRunTimeTable(r.timings, md);
}

void writeMeasurementSection(const DemoResults& r, std::ostream& md) {
  const pipeline::MeasurementScore& m = r.measurement;
  // The paper's study compares with the paper's figure (§5).
  md << "\n## 2. Pose measurement (`poses.csv`)" << (r.paper ? ", paper §5: about 0.2 mm and 0.03° per component" : "")
     << "\n\n"
     << m.measured << " of " << m.total << " poses measured. Predicted σ (median over poses"
     << (r.paper ? ", pixel noise and intrinsics uncertainty combined" : "") << ") against the actual "
     << "error to truth:\n\n";
  demo_report::writePoseMeasurementTable(m, md, r.paper ? "| paper | 0.2 | 0.2 | 0.2 | 0.03 | 0.03 | 0.03 |" : "");
}

std::string joinNames(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& name : names) out += (out.empty() ? "`" : ", `") + name + "`";
  return out.empty() ? "none" : out;
}

void writeModelSummary(const DemoModelScore& s, const std::string& truth_model, std::ostream& md) {
  const bool rad = s.joint_unit == "rad";
  const double scale = rad ? 180.0 / 3.14159265358979323846 : 1e3;
  const std::string unit = rad ? "°" : "mm";
  md << "\n### `" << s.model << "` (`" << s.file << "`)\n\n"
     << s.free_parameters << " free parameters (rank " << s.rank << " before the gauge was fixed); gauge held at its "
     << "data-initialised values: " << joinNames(s.gauge) << ". Joint residual RMS "
     << fixed(scale * s.rms_joint_before, 4) << " " << unit << " (nominal geometry) → "
     << fixed(scale * s.rms_joint_after, 4) << " " << unit << "; χ²/dof " << fixed(s.chi2_per_dof, 2)
     << "; printed σ: " << s.sigma_method << ". Identification " << fixed(s.seconds, 2)
     << " s (with the shared term's refits).\n";
  if (!s.has_truth) {
    md << "\nThe simulator's truth is not written in this model's parameters (its geometry is `" << truth_model
       << "`'s): no parameter truth; judged by V3 and the positioning test below.\n";
    return;
  }
  md << "\nEvery free parameter against the truth in the identification's gauge (error/σ RMS "
     << fixed(s.error_over_sigma_rms, 2) << ", max " << fixed(s.error_over_sigma_max, 2)
     << "; the unmodelled defects bias the estimates beyond their σ where they project on a parameter):\n\n"
     << "| parameter | unit | identified | σ | truth | error / σ |\n| --- | --- | ---: | ---: | ---: | ---: |\n";
  for (const auto& p : s.identified)
    md << "| " << p.name << " | " << p.unit << " | " << format("%.5f", p.estimate) << " | " << format("%.2g", p.sigma)
       << " | " << format("%.5f", p.truth) << " | " << fixed((p.estimate - p.truth) / p.sigma, 2) << " |\n";
}

void writeCriteriaSection(const DemoResults& r, std::ostream& md) {
  md << "\n## 4. V3 and the positioning test, before and after identification\n\n"
     << "V3 (paper eq. 29): straightness of two recorded straight-line motions rebuilt with the model's FKM (the "
        "true robot's own: "
     << fixed(1e3 * r.true_v3_m, 4) << " mm). Positioning test: a "
     << fixed(r.models.empty() ? 100.0 : r.models.front().square_side_mm, 0)
     << " mm square at the workspace centre commanded through the model's IKM and "
        "reached by the true robot, RMS of the 3-D side-length errors. Paper (H4): V3 −68 %.\n\n"
     << "| model | V3 nominal (mm) | V3 identified (mm) | change | square RMS nominal (mm) | square RMS identified "
        "(mm) | change |\n| --- | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  for (const auto& s : r.models)
    md << "| " << s.model << " | " << fixed(1e3 * s.v3_before_m, 4) << " | " << fixed(1e3 * s.v3_after_m, 4) << " | "
       << percent(s.v3_after_m, s.v3_before_m) << " | " << fixed(s.square_rms_before_mm, 4) << " | "
       << fixed(s.square_rms_after_mm, 4) << " | " << percent(s.square_rms_after_mm, s.square_rms_before_mm) << " |\n";
  md << "\nSide-length errors (mm):\n\n| model | parameters | side 1 | side 2 | side 3 | side 4 |\n"
        "| --- | --- | ---: | ---: | ---: | ---: |\n";
  for (const auto& s : r.models) {
    md << "| " << s.model << " | nominal |";
    for (const double e : s.square_before_mm) md << " " << fixed(e, 4) << " |";
    md << "\n| " << s.model << " | identified |";
    for (const double e : s.square_after_mm) md << " " << fixed(e, 4) << " |";
    md << "\n";
  }
}

void writeModelSections(const DemoResults& r, std::ostream& md) {
  md << "\n## 3. Identification (`mire identify --model NAME` on `poses.csv` + `joints.csv`)\n";
  for (const auto& s : r.models) {
    writeModelSummary(s, r.truth_model, md);
    if (s.has_truth) md << "\n![parameter errors](parameter_errors_" << s.model << ".svg)\n";
  }
  writeCriteriaSection(r, md);
}

// The paper's study nests it in its identification section (the paper's last step).
void writeClosedLoop(const DemoResults& r, std::ostream& md) {
  if (r.closed_loop)
    demo_report::writeClosedLoopSection(*r.closed_loop,
                                        r.paper ? "### Closing the loop: ISO 9283 before and after compensation"
                                                : "## 5. Closing the loop: ISO 9283 before and after compensation",
                                        demo_report::nominalController(r), md);
  else
    md << "\n## 5. Closing the loop\n\nNot run with the camera on the effector: the ISO 9283 test reads the "
          "attained poses through a fixed camera and the identified camera-fixed mounting (doc/accuracy.md, "
          "\"Closing the loop\").\n";
}

// The in-process run's equivalent command (report.json's provenance).
std::vector<std::string> equivalentCommand(const DemoOptions& options) {
  std::vector<std::string> command{"mire", "demo"};
  if (options.mechanism != DemoOptions{}.mechanism) command.insert(command.end(), {"--mechanism", options.mechanism});
  command.insert(command.end(), {"--output", options.output.string()});
  if (options.mounting != "camera-fixed") command.insert(command.end(), {"--mounting", options.mounting});
  if (options.quick) command.emplace_back("--quick");
  command.insert(command.end(), {"--seed", std::to_string(options.seed)});
  return command;
}

}  // namespace

std::vector<std::string> writeDemoReport(const DemoOptions& options, const DemoResults& r) {
  std::ostringstream md;
  if (r.paper)
    demo_report::writePaperIntroduction(options, r, md);
  else
    writeIntroduction(options, r, md);
  demo_report::writeCalibrationSection(r.calibration, md);
  writeMeasurementSection(r, md);
  if (r.paper)
    demo_report::writePaperStudy(r, md);  // its files close its square test
  else
    writeModelSections(r, md);
  writeClosedLoop(r, md);
  if (!r.paper) {
    md << "\nFiles: `camera.yaml`, `poses.csv` (+ `poses_covariance.csv`, `poses_shared.csv`)";
    for (const auto& s : r.models) md << ", `" << s.file << "`";
    md << "; the simulated campaign under `campaign/` (its truth under `campaign/truth/`).\n";
  }
  const std::vector<std::string> figures = writeSvgFiles(options.output, demoFigures(r));
  support::writeFileAtomically(options.output / "report.md", md.str());

  std::vector<std::string> files{"report.md", "report.html", "report.json"};
  files.insert(files.end(), figures.begin(), figures.end());
  files.insert(files.end(), {"camera.yaml", "poses.csv", "poses_covariance.csv"});
  if (r.paper) files.push_back(r.paper->file);
  for (const auto& s : r.models) files.push_back(s.file);
  DemoResults with_files = r;
  with_files.files = files;
  ReportProvenance provenance{options.command_line, {}, {{options.output, "--output"}}};
  if (provenance.command_line.empty()) provenance.command_line = equivalentCommand(options);
  writeDemoReportJson(options.output / "report.json", provenance, options, with_files);
  writeDemoReportHtml(options.output / "report.html", provenance, options, with_files);
  return files;
}

}  // namespace mire::app
