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
#include <string>
#include <vector>

#include "mire/calibration/camera_model.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/metrology/detector_bias.hpp"
#include "mire/metrology/target.hpp"

#include "image_folders.hpp"

namespace mire::app {

struct DemoOptions {
  std::filesystem::path output = "demo-output";
  bool quick = false;  // fewer images and repeats (the end-to-end test uses it)
  std::uint64_t seed = 2004;
  std::string mechanism = "h4";           // h4, delta or gough-stewart (demo_mechanism.hpp)
  std::vector<std::string> command_line;  // as parsed (report.json); empty when run in-process
};

struct StageTiming {
  std::string name;
  double seconds = 0.0;
};

struct DemoCalibration {
  std::vector<std::string> names;
  std::vector<double> estimate, sigma, truth;
  double rms_px = 0.0;
  int views_used = 0, views_total = 0;
  double uncertainty_centre_px = 0.0, uncertainty_corner_px = 0.0;
  Eigen::MatrixXd covariance;  // of `estimate` (camera.yaml's), for report.json
};

struct DemoMeasurement {
  int measured = 0, total = 0;
  Eigen::Vector3d median_sigma_mm = Eigen::Vector3d::Zero();   // predicted, translation
  Eigen::Vector3d median_sigma_deg = Eigen::Vector3d::Zero();  // predicted, rotation
  Eigen::Vector3d rms_error_mm = Eigen::Vector3d::Zero();      // against truth
  Eigen::Vector3d rms_error_deg = Eigen::Vector3d::Zero();
  double normalized_error_std = 0.0;  // RMS of error/σ over all components (≈1 when honest)
  // Per component: RMS of error/σ pose by pose, and whitened with the cross-pose covariance
  // (the calibration's error is shared by every pose; demo_pose_scores.hpp).
  Eigen::Matrix<double, 6, 1> normalized_error_rms = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> whitened_error_rms = Eigen::Matrix<double, 6, 1>::Zero();
  double whitened_error_rms_all = 0.0;
  metrology::DetectorBiasTerm detector_bias;  // the shared-term file's detector part
};

struct DemoVariant {
  char letter = 'D';
  int free_parameters = 0;
  double cond = 0.0, v1_rad = 0.0, v2_rad = 0.0, v3_m = 0.0;
  double v3_mean_m = 0.0;  // over the repeated 71-pose sets (Fig. 11)
  std::string error;       // when the identification failed
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
  DemoCalibration calibration;
  DemoMeasurement measurement;
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

// The stages every demo shares (demo_pipeline.cpp; doc/demo-mechanisms.md reuses them).
// Calibration from the images of `calibration_images` (camera.yaml into `output`), scored
// against `true_camera`.
calibration::Camera calibrateStage(const std::filesystem::path& calibration_images,
                                   const calibration::Camera& true_camera, const metrology::Target& target,
                                   const std::filesystem::path& output, DemoCalibration& summary);
// One pose per subfolder of `pose_images` into poses_csv (+ covariance and shared-term side
// files), scored against the simulator's true cTm of each pose id; returns the measurements
// (their features, for diagnostics against the truth).
using TrueCameraTMarker = std::function<Eigen::Isometry3d(const std::string& pose_id)>;
std::vector<PoseFolderMeasurement> measureStage(const std::filesystem::path& pose_images,
                                                const TrueCameraTMarker& true_pose, const calibration::Camera& camera,
                                                const metrology::Target& target, const std::filesystem::path& poses_csv,
                                                DemoMeasurement& summary);

}  // namespace mire::app
