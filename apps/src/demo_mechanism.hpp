#pragma once
// `mire demo --mechanism delta|gough-stewart` (doc/demo-mechanisms.md): the H4 demo's pipeline on a
// simulated true Delta or hexapod with unmodelled defects. The pipeline sees only what a user would
// have (images, encoder readings, the model's built-in nominal); the truth only scores.
#include <Eigen/Core>

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "demo.hpp"
#include "demo_legs.hpp"
#include "report_json.hpp"

namespace mire::app {

// One model identified on the measured poses, as `mire identify --model NAME` runs it.
struct MechanismModelScore {
  std::string model;       // delta, delta-legs, gough-stewart
  std::string joint_unit;  // rad or m
  int free_parameters = 0, rank = 0;
  std::vector<std::string> gauge;                        // held at their data-initialised values (pivoted QR)
  double rms_joint_before = 0.0, rms_joint_after = 0.0;  // joint unit, all poses
  double chi2_per_dof = 0.0;
  std::string sigma_method;
  // The true robot has this model's parameters: each free one scored against the truth
  // expressed in the identification's gauge (doc/demo-mechanisms.md, "Scoring").
  bool has_truth = false;
  std::vector<DemoParameterScore> identified;                     // every free parameter; truth NaN without one
  Eigen::MatrixXd covariance;                                     // of `identified` (that order), SI
  double error_over_sigma_rms = 0.0, error_over_sigma_max = 0.0;  // over `identified` (has_truth)
  // V3 (paper eq. 29) from lines.csv, and the positioning test: a square (100 mm, smaller on a
  // robot whose protocol is: datasets::protocolScale) commanded through the model's IKM, reached
  // by the true robot, 3-D side-length errors.
  double square_side_mm = 100.0;
  double v3_before_m = 0.0, v3_after_m = 0.0;
  std::array<double, 4> square_before_mm{}, square_after_mm{};
  double square_rms_before_mm = 0.0, square_rms_after_mm = 0.0;
  double seconds = 0.0;  // identification with the shared term's refits
  std::string file;      // identified_<model>.yaml
};

struct MechanismDemoResults {
  std::string mechanism;                  // delta, gough-stewart
  std::string mounting = "camera-fixed";  // or camera-on-effector (DemoOptions::mounting)
  std::string truth_model;
  std::vector<StageTiming> timings;
  pipeline::CalibrationScore calibration;
  pipeline::MeasurementScore measurement;
  double true_v3_m = 0.0;  // the true robot's own straightness along the recorded lines
  std::vector<MechanismModelScore> models;
  // The ISO 9283 test of the true robot before / after compensation with the truth's model
  // (closed_loop.hpp); not run with the camera on the effector (its reading is the fixed camera's).
  std::optional<pipeline::ClosedLoopTest> closed_loop;
  std::vector<std::string> files;       // written, relative to the output folder
  std::optional<LegsDemoSection> legs;  // with DemoOptions::legs (legs.md)
};

// Runs the demo of options.mechanism into options.output.
MechanismDemoResults runMechanismDemo(const DemoOptions& options);

// report.md, report.json and the figures; returns the files written (relative names).
std::vector<std::string> writeMechanismDemoReport(const DemoOptions& options, const MechanismDemoResults& results);

// report.json (demo_mechanism_report_json.cpp): the results without the run times.
void writeMechanismDemoReportJson(const std::filesystem::path& path, const ReportProvenance& provenance,
                                  const DemoOptions& options, const MechanismDemoResults& results);

}  // namespace mire::app
