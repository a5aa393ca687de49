#pragma once
// `mire demo`: the paper's experiment end to end in simulation (doc/simulation.md). The pipeline sees
// only what a user would have (images, encoder readings, the nominal geometry); the
// simulator's truth is used only to score the results.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "mire/calibration/camera_model.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/metrology/detector_bias.hpp"
#include "mire/metrology/target.hpp"

#include "mire/pipeline/closed_loop.hpp"
#include "mire/pipeline/scored_stages.hpp"

namespace mire::app {

struct DemoOptions {
  std::filesystem::path output = "demo-output";
  bool quick = false;  // fewer images and repeats (the end-to-end test uses it)
  std::uint64_t seed = 2004;
  std::string mechanism = "h4";  // h4, delta or gough-stewart (demo_mechanism.hpp)
  // camera-fixed, or camera-on-effector (doc/demo-mechanisms.md; the mechanism demos only: the H4 demo's
  // variants assume the camera fixed, paper §4).
  std::string mounting = "camera-fixed";
  bool legs = false;                      // the legs drawn and identified from (demo_legs.hpp; gough-stewart, delta)
  std::vector<std::string> command_line;  // as parsed (report.json); empty when run in-process
};

struct StageTiming {
  std::string name;
  double seconds = 0.0;
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

// One identified parameter of variant D (all poses) scored against the simulator's truth (the
// true robot's model-12 part; z_BC in the model's z_ME gauge, paper eq. 24).
struct DemoParameterScore {
  std::string name, unit;                     // display unit (mm, deg)
  double estimate = 0, sigma = 0, truth = 0;  // display units
  std::string si_unit;                        // the same in SI (m, rad), as identified_D.yaml
  double si_estimate = 0, si_sigma = 0, si_truth = 0;
};

// `mire plan` and `mire select` on the demo (doc/plan-and-select.md).
struct DemoExperimentDesign {
  int plan_candidates = 0;
  double plan_sigma_ratio = 0.0;         // median geometric σ, 15 planned / 15 random poses
  double plan_position_sigma_m = 0.0;    // predicted positioning σ after identification, plan
  double random_position_sigma_m = 0.0;  // the same, median over random sets
  int folds = 0;
  std::string selection_table;  // as `mire select` prints it
  std::string recommended;
};

struct DemoResults {
  std::vector<StageTiming> timings;
  pipeline::CalibrationScore calibration;
  pipeline::MeasurementScore measurement;
  double nominal_v1_rad = 0, nominal_v2_rad = 0, nominal_v3_m = 0;  // before identification
  double true_v3_m = 0;  // the true robot's own straightness along the commanded lines
  std::vector<DemoVariant> variants;
  int variant_sets = 0;  // 71-pose sets averaged for Fig. 11
  std::vector<DemoPoseCount> pose_counts;
  int pose_count_repeats = 0;
  std::array<double, 4> square_before_mm{}, square_after_mm{};
  DemoExperimentDesign design;
  std::vector<DemoParameterScore> identified;  // variant D on all poses
  Eigen::MatrixXd identified_covariance;       // of `identified` (that order), SI
  std::string sigma_method;                    // which σ identify printed (and why)
  double chi2_per_dof = 0.0;
  std::size_t outlier_count = 0;
  // The ISO 9283 test of the true robot before / after compensation with variant D (closed_loop.hpp).
  std::optional<pipeline::ClosedLoopTest> closed_loop;
  std::vector<std::string> files;  // written, relative to the output folder
};

// Wall time since construction.
class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// Runs one named stage of a demo, records its wall time and says so on the terminal.
template <class Work>
void timedStage(std::vector<StageTiming>& timings, const std::string& name, const Work& work) {
  const Stopwatch watch;
  work();
  timings.push_back({name, watch.seconds()});
  std::cerr << "mire demo: " << name << " done in " << timings.back().seconds << " s\n";
}

// Runs the whole demo into options.output; returns the results (also written as report.md).
DemoResults runDemo(const DemoOptions& options);

// Plan (15 of the protocol volume's candidates) and select (variants A–H on `poses`).
DemoExperimentDesign experimentDesignStage(const DemoOptions& options, const mechanism::H4Nominal& nominal,
                                           const std::vector<mechanism::PoseObservation>& poses);

// Writes report.md, report.json and the figures; returns the files written (relative names).
std::vector<std::string> writeDemoReport(const DemoOptions& options, const DemoResults& results);

}  // namespace mire::app
