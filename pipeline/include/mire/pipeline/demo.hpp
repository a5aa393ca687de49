#pragma once
// `mire demo`'s stages (doc/simulation.md, doc/demo-mechanisms.md): simulate the campaign of a
// robot of the table of mechanisms, then run the real pipeline on its files exactly as a user
// would (calibrate from images, measure poses from images, identify from poses.csv + joints.csv),
// close the loop, and score against the simulator's truth only at the end. A robot whose model
// takes the paper's variants (Table 2) gets the paper's study (Tables 1, 3, 4, §6.2, Fig. 11);
// any other robot gets each model of its family's selection identified as `mire identify` does.
#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mire/mechanism/registry.hpp"
#include "mire/pipeline/closed_loop.hpp"
#include "mire/pipeline/demo_legs.hpp"
#include "mire/pipeline/scored_stages.hpp"

namespace mire::pipeline {

struct DemoOptions {
  std::filesystem::path output = "demo-output";
  bool quick = false;  // fewer images and repeats (the end-to-end test uses it)
  std::uint64_t seed = 2004;
  // A family of the table (registry.hpp), the paper's robot by default, or a description file.
  std::string mechanism = mechanism::mechanismFamilies().front().name;
  // camera-fixed, or camera-on-effector (doc/demo-mechanisms.md; not with the paper's variants,
  // which assume the camera fixed, paper §4).
  std::string mounting = "camera-fixed";
  bool legs = false;  // the legs drawn as rods, measured and identified from (demo_legs.hpp; hexapod, Delta)
  std::vector<std::string> command_line;  // as parsed (report.json); empty when run in-process
};

struct StageTiming {
  std::string name;
  double seconds = 0.0;
};

// One identified parameter scored against the simulator's truth (display units and SI).
struct DemoParameterScore {
  std::string name, unit;                     // display unit (mm, deg)
  double estimate = 0, sigma = 0, truth = 0;  // display units
  std::string si_unit;                        // the same in SI (m, rad), as the identified file
  double si_estimate = 0, si_sigma = 0, si_truth = 0;
};

struct DemoVariant {
  char letter = 'D';
  int free_parameters = 0;
  double cond = 0.0, v1_rad = 0.0, v2_rad = 0.0, v3_m = 0.0;
  double v3_mean_m = 0.0;   // over the repeated 71-pose sets (Fig. 11)
  double v3_sigma_m = 0.0;  // their spread (sample σ over the sets; report.html's error bars)
  std::string error;        // when the identification failed
};

struct DemoPoseCount {
  int size = 0, runs_ok = 0;
  double v1_mean = 0, v2_mean = 0, v2_sigma = 0, v3_mean = 0, v3_sigma = 0;
  double median_parameter_sigma_ratio = 0.0;  // median over parameters of σ(size)/σ(6)
};

// `mire plan` and `mire select` on the campaign (doc/plan-and-select.md).
struct DemoExperimentDesign {
  int plan_candidates = 0;
  double plan_sigma_ratio = 0.0;         // median geometric σ, 15 planned / 15 random poses
  double plan_position_sigma_m = 0.0;    // predicted positioning σ after identification, plan
  double random_position_sigma_m = 0.0;  // the same, median over random sets
  int folds = 0;
  std::string selection_table;  // as `mire select` prints it
  std::string recommended;
};

// The paper's study (Renaud et al. 2004, Tables 1, 3, 4, §6.2, Fig. 11), run on a robot whose
// truth model takes the paper's variants.
struct PaperStudy {
  double nominal_v1_rad = 0, nominal_v2_rad = 0, nominal_v3_m = 0;  // before identification
  std::vector<DemoVariant> variants;
  int variant_sets = 0;  // 71-pose sets averaged for Fig. 11
  std::vector<DemoPoseCount> pose_counts;
  int pose_count_repeats = 0;
  std::array<double, 4> square_before_mm{}, square_after_mm{};
  DemoExperimentDesign design;
  // The truth model's default variant on all poses (the paper's D), against the truth model's part
  // of the true robot (z_BC in the model's z_ME gauge, paper eq. 24).
  char variant = 'D';
  std::string file;                            // identified_<variant>.yaml
  std::vector<DemoParameterScore> identified;  // in the model's parameter order
  Eigen::MatrixXd identified_covariance;       // of `identified` (that order), SI
  std::string sigma_method;                    // which σ identify printed (and why)
  double chi2_per_dof = 0.0;
  std::size_t outlier_count = 0;
};

// One model identified on the measured poses, as `mire identify --model NAME` runs it.
struct DemoModelScore {
  std::string model;       // delta, delta-legs, gough-stewart, a description's stem
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

struct DemoResults {
  std::string mechanism;                  // the family's name or the description file
  std::string mounting = "camera-fixed";  // or camera-on-effector (DemoOptions::mounting)
  std::string truth_model;
  std::vector<StageTiming> timings;
  CalibrationScore calibration;
  MeasurementScore measurement;
  double true_v3_m = 0.0;              // the true robot's own straightness along the recorded lines
  std::optional<PaperStudy> paper;     // the paper's study, or
  std::vector<DemoModelScore> models;  // each model of the family's selection
  // The ISO 9283 test of the true robot before / after compensation (closed_loop.hpp); not run
  // with the camera on the effector (its reading is the fixed camera's).
  std::optional<ClosedLoopTest> closed_loop;
  std::optional<LegsDemoSection> legs;  // with DemoOptions::legs (legs.md)
  std::vector<std::string> files;       // written, relative to the output folder (by the report)
};

// The paper's study runs on a family whose truth model takes the paper's variants (registry.hpp).
bool takesPaperVariants(const mechanism::MechanismFamily& family);

// Runs the demo's stages into options.output (campaign/, camera.yaml, poses.csv, identified_*.yaml);
// the report is the caller's.
DemoResults runDemoStages(const DemoOptions& options);

}  // namespace mire::pipeline
