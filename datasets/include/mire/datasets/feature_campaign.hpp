#pragma once
// A synthetic measurement campaign at the FEATURE level (no images): exact projections of a
// target through a camera, plus Gaussian pixel noise per "image". It tests and benchmarks the
// statistics of `mire measure` (averaging, pose, precision) against ground truth, where
// image-level simulations (render.hpp) would be too slow for Monte-Carlo runs of hundreds
// of poses.
#include "mire/calibration/camera_model.hpp"
#include "mire/metrology/detection.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <random>
#include <vector>

namespace mire::datasets {

// The reference system's camera (doc/measurement.md, "The reference system"): 1024×768, 3.8 mm lens,
// fx = fy = 817.2 px, cx = 511.5, cy = 383.5, k1 k2 p1 p2 k3 = −0.30, 0.10, 4e-4, −3e-4, −0.015.
calibration::Camera referenceCamera();

struct CampaignGeometry {
  // Nominal target pose: target centre on the optical axis at `distance_m`, the target plane
  // tilted by `tilt_deg` about the camera's x axis.
  double distance_m = 0.75;
  double tilt_deg = 15.0;
  Eigen::Vector3d target_centre_m = Eigen::Vector3d::Zero();  // offset of the board centre in M
  // Effector motion around the nominal pose (uniform): translations ±half_extent_m along the
  // camera's axes (200×200×150 mm by default, the paper's protocol volume), rotation about the target normal
  // ±rotation_deg, and small tilts ±wobble_deg about the target's x and y axes.
  Eigen::Vector3d half_extent_m = Eigen::Vector3d(0.100, 0.100, 0.075);
  double rotation_deg = 20.0;
  double wobble_deg = 5.0;
};

// Random poses cTm of the campaign (deterministic for `rng`'s state).
Eigen::Isometry3d drawCampaignPose(const CampaignGeometry& geometry, std::mt19937_64& rng);

// Per-feature pixel noise σ: uniform in [sigma_px·(1 − spread), sigma_px·(1 + spread)] (the
// corners of a real board are not equally sharp).
std::vector<double> drawFeatureSigmas(std::size_t count, double sigma_px, double spread, std::mt19937_64& rng);

// Exact projections of `points` (frame M) seen from `cTm`; features behind the camera or
// outside the image are left out. Then `images` noisy copies: each coordinate gets
// N(0, sigma_px[i]²), independently per image.
metrology::Detection exactDetection(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                    const Eigen::Isometry3d& cTm);
std::vector<metrology::Detection> noisyDetections(const metrology::Detection& exact,
                                                  const std::vector<double>& sigma_px, int images, std::mt19937_64& rng);

// A realistic intrinsics covariance: the Cramér–Rao bound of a simulated calibration
// (`views` random views of the target over the field, tilts up to ±35°, distances 0.45–0.9 m,
// single images with `sigma_px` noise, all intrinsics and distortion free), i.e. the inverse
// of the information matrix JᵀJ/σ² with the view poses eliminated (Schur complement).
Eigen::MatrixXd simulatedCalibrationCovariance(const calibration::Camera& camera,
                                               const std::vector<Eigen::Vector3d>& points, int views, double sigma_px,
                                               std::mt19937_64& rng);

// A camera drawn from N(camera.params, camera.covariance) (the "true" camera of a simulated
// world whose calibration is `camera`); the returned camera keeps the same covariance.
calibration::Camera drawCamera(const calibration::Camera& camera, std::mt19937_64& rng);

}  // namespace mire::datasets
