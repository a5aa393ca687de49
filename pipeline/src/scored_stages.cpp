// The calibrate and measure stages scored against a simulated campaign's truth (scored_stages.hpp).
#include "mire/pipeline/scored_stages.hpp"

#include "mire/calibration/calibrate.hpp"
#include "mire/calibration/camera_io.hpp"
#include "mire/mechanism/translating_target.hpp"
#include "mire/metrology/pose_measurement.hpp"
#include "mire/metrology/poses_csv.hpp"
#include "mire/metrology/shared_term_csv.hpp"
#include "mire/pipeline/pose_scores.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/side_files.hpp"
#include "mire/support/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <stdexcept>

namespace mire::pipeline {
namespace fs = std::filesystem;
namespace mech = mire::mechanism;
using support::kPi;
using support::upperMedian;

// Stage 2: detection on every image (parallel), then the bundle adjustment.
calibration::Camera calibrateStage(const fs::path& calibration_images, const calibration::Camera& true_camera,
                                   const metrology::Target& target, const fs::path& output, CalibrationScore& summary) {
  const CalibrationFolder folder = detectCalibrationFolder(target, calibration_images, 0);
  calibration::CalibrationOptions options;
  options.model = calibration::DistortionModel::OpenCV5;
  const calibration::CalibrationResult result =
      calibration::calibrateCamera(target.points(), folder.views, folder.width, folder.height, options);
  support::writeFileAtomically(output / "camera.yaml", calibration::cameraYamlString(result.camera));

  summary.names = result.camera.parameterNames();
  summary.estimate = result.camera.params;
  summary.sigma = result.camera.sigmas();
  summary.truth = true_camera.params;
  summary.rms_px = result.camera.rms_px;
  summary.views_used = result.used_views;
  summary.views_total = static_cast<int>(folder.images);
  const auto uncertainty = calibration::summarizeProjectionUncertainty(result);
  summary.uncertainty_centre_px = uncertainty.centre_px;
  summary.uncertainty_corner_px = uncertainty.corner_px;
  summary.covariance = result.camera.covariance;
  return result.camera;
}

// Stage 3: one pose per folder (parallel), written as poses.csv + covariance side file.
std::vector<PoseFolderMeasurement> measureStage(const fs::path& pose_images, const TrueCameraTMarker& true_pose,
                                                const calibration::Camera& camera, const metrology::Target& target,
                                                const fs::path& poses_csv, MeasurementScore& summary) {
  // The simulated robot is static by construction: a static-pose test alarm (false-alarm rate
  // 1e-3 per pose, doc/measurement.md, "Imperfect campaigns") keeps the largest consistent group, as
  // `mire measure --split-moving keep-largest` would, instead of dropping the pose.
  metrology::MeasurementOptions options;
  options.integrity.split = metrology::SplitPolicy::KeepLargest;
  std::vector<PoseFolderMeasurement> measurements = measurePoseFolders(camera, target, pose_images, options, 0);
  std::vector<metrology::MeasuredPose> measured;
  std::vector<double> sigma[6];
  Eigen::Matrix<double, 6, 1> squared_error = Eigen::Matrix<double, 6, 1>::Zero();
  std::vector<PoseErrorSample> samples;
  for (const auto& pose : measurements) {
    const auto& m = pose.measurement;
    if (!m.ok) {
      std::cerr << "mire demo: pose " << pose.pose_id << ": " << m.error << "\n";
      continue;
    }
    measured.emplace_back(pose.pose_id, m.features.images_used, pose.images_total, m.estimate);
    // Scoring against the simulator's truth.
    const Eigen::Isometry3d truth = true_pose(pose.pose_id);
    PoseErrorSample sample;
    sample.error << m.estimate.translation - truth.translation(),
        m.estimate.rotation_vector - metrology::rotationVector(truth.linear());
    sample.independent = m.estimate.covariance_noise;
    sample.sensitivity = m.estimate.intrinsics_sensitivity;
    sample.sigma = metrology::PoseEstimate::sigmas(m.estimate.covariance);
    for (int k = 0; k < 6; ++k) {
      sigma[k].push_back(sample.sigma[k]);
      squared_error[k] += sample.error[k] * sample.error[k];
    }
    samples.push_back(std::move(sample));
  }
  if (measured.empty()) throw std::runtime_error("no pose could be measured");
  metrology::writePosesCsv(poses_csv, measured);
  metrology::writePosesCovarianceCsv(support::covarianceSidePath(poses_csv), measured);
  summary.detector_bias = sharedDetectorBias(camera, target, measurements, options);
  metrology::writeSharedTermCsv(support::sharedTermSidePath(poses_csv), camera, measured, summary.detector_bias);

  summary.measured = static_cast<int>(measured.size());
  summary.total = static_cast<int>(measurements.size());
  const double n = static_cast<double>(measured.size());
  for (int k = 0; k < 3; ++k) {
    summary.median_sigma_mm[k] = 1e3 * upperMedian(sigma[k]);
    summary.median_sigma_deg[k] = 180.0 / kPi * upperMedian(sigma[k + 3]);
    summary.rms_error_mm[k] = 1e3 * std::sqrt(squared_error[k] / n);
    summary.rms_error_deg[k] = 180.0 / kPi * std::sqrt(squared_error[k + 3] / n);
  }
  const PoseErrorScores scores = scorePoseErrors(samples, camera.covariance);
  summary.normalized_error_std = scores.rms_per_pose_all;
  summary.normalized_error_rms = scores.rms_per_pose;
  summary.whitened_error_rms = scores.rms_whitened;
  summary.whitened_error_rms_all = scores.rms_whitened_all;
  return measurements;
}

mech::ParameterSet truthInGauge(const datasets::MechanismImageCampaign& campaign, const InitialModel& initial,
                                const std::vector<mech::PoseObservation>& measured) {
  const mech::Mechanism& mechanism = campaign.robot.mechanism();
  std::vector<mech::PoseObservation> exact;
  for (std::size_t i = 0; i < campaign.commanded.size(); ++i) {
    const Eigen::Isometry3d bTe = mechanism.poseToTransform(campaign.commanded[i]);
    mech::PoseObservation pose;
    pose.id = campaign.pose_ids[i];
    pose.joints = mechanism.inverseKinematics(campaign.robot.geometry.values(), bTe).joints;
    pose.cTm = mech::toPoseVector(campaign.camera_on_effector ? campaign.eTc.inverse() * bTe.inverse() * campaign.bTm
                                                              : campaign.bTc.inverse() * bTe * campaign.mTe.inverse());
    const auto same = std::find_if(measured.begin(), measured.end(), [&](const auto& p) { return p.id == pose.id; });
    if (same != measured.end()) pose.covariance = same->covariance;
    exact.push_back(pose);
  }
  mech::IdentificationOptions options;
  options.compute_identifiability = false;
  mech::IdentificationResult truth = mech::identify(initial.model, exact, options);
  mech::alignTranslatingTarget(truth, exact);
  return truth.model.parameters;
}

}  // namespace mire::pipeline
