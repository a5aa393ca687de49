#pragma once
// The calibrate and measure stages on a simulated campaign's images, run exactly as a user's
// files would be, then scored against the simulator's truth: what the demos report and the
// end-to-end studies (benchmarks/) collect. The truth never reaches the estimates.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "mire/calibration/camera_model.hpp"
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/metrology/detector_bias.hpp"
#include "mire/metrology/target.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/pipeline/image_folders.hpp"

namespace mire::pipeline {

// The calibration against the true camera (parameters in camera.yaml order).
struct CalibrationScore {
  std::vector<std::string> names;
  std::vector<double> estimate, sigma, truth;
  double rms_px = 0.0;
  int views_used = 0, views_total = 0;
  double uncertainty_centre_px = 0.0, uncertainty_corner_px = 0.0;
  Eigen::MatrixXd covariance;  // of `estimate` (camera.yaml's), for report.json
};

// The measured poses against their true cTm.
struct MeasurementScore {
  int measured = 0, total = 0;
  Eigen::Vector3d median_sigma_mm = Eigen::Vector3d::Zero();   // predicted, translation
  Eigen::Vector3d median_sigma_deg = Eigen::Vector3d::Zero();  // predicted, rotation
  Eigen::Vector3d rms_error_mm = Eigen::Vector3d::Zero();      // against truth
  Eigen::Vector3d rms_error_deg = Eigen::Vector3d::Zero();
  double normalized_error_std = 0.0;  // RMS of error/σ over all components (≈1 when honest)
  // Per component: RMS of error/σ pose by pose, and whitened with the cross-pose covariance
  // (the calibration's error is shared by every pose; mire/pipeline/pose_scores.hpp).
  Eigen::Matrix<double, 6, 1> normalized_error_rms = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Matrix<double, 6, 1> whitened_error_rms = Eigen::Matrix<double, 6, 1>::Zero();
  double whitened_error_rms_all = 0.0;
  metrology::DetectorBiasTerm detector_bias;  // the shared-term file's detector part
};

// Calibration from the images of `calibration_images` (camera.yaml into `output`), scored
// against `true_camera`.
calibration::Camera calibrateStage(const std::filesystem::path& calibration_images,
                                   const calibration::Camera& true_camera, const metrology::Target& target,
                                   const std::filesystem::path& output, CalibrationScore& summary);
// One pose per subfolder of `pose_images` into poses_csv (+ covariance and shared-term side
// files), scored against the simulator's true cTm of each pose id; returns the measurements
// (their features, for diagnostics against the truth).
using TrueCameraTMarker = std::function<Eigen::Isometry3d(const std::string& pose_id)>;
std::vector<PoseFolderMeasurement> measureStage(const std::filesystem::path& pose_images,
                                                const TrueCameraTMarker& true_pose, const calibration::Camera& camera,
                                                const metrology::Target& target, const std::filesystem::path& poses_csv,
                                                MeasurementScore& summary);

// The truth in the identification's gauge: the true geometry's exact-model observations at the
// commanded poses (no defect, no noise), identified from the same initial model with the same
// parameters held; the fit is exact, and lands where the gauge puts it.
mechanism::ParameterSet truthInGauge(const datasets::MechanismImageCampaign& campaign, const InitialModel& initial,
                                     const std::vector<mechanism::PoseObservation>& measured);

}  // namespace mire::pipeline
