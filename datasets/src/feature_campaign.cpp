#include "mire/datasets/feature_campaign.hpp"

#include "mire/metrology/feature_averaging.hpp"
#include "mire/metrology/pose_estimation.hpp"
#include "mire/metrology/pose_types.hpp"
#include "mire/support/constants.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <cmath>
#include <stdexcept>

namespace mire::datasets {
namespace {

double radians(double degrees) { return degrees * support::kPi / 180.0; }

double uniform(std::mt19937_64& rng, double low, double high) {
  return std::uniform_real_distribution<double>(low, high)(rng);
}

}  // namespace

calibration::Camera referenceCamera() {
  return calibration::cameraFromOpenCV(1024, 768, 817.2, 817.2, 511.5, 383.5, {-0.30, 0.10, 4e-4, -3e-4, -0.015});
}

Eigen::Isometry3d drawCampaignPose(const CampaignGeometry& geometry, std::mt19937_64& rng) {
  // Nominal: board centre on the optical axis, target z pointing away from the camera.
  Eigen::Isometry3d nominal = Eigen::Isometry3d::Identity();
  nominal.linear() = Eigen::AngleAxisd(radians(geometry.tilt_deg), Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Vector3d motion(uniform(rng, -1, 1) * geometry.half_extent_m.x(),
                               uniform(rng, -1, 1) * geometry.half_extent_m.y(),
                               uniform(rng, -1, 1) * geometry.half_extent_m.z());
  const Eigen::Matrix3d effector_rotation =
      (Eigen::AngleAxisd(radians(uniform(rng, -1, 1) * geometry.rotation_deg), Eigen::Vector3d::UnitZ()) *
       Eigen::AngleAxisd(radians(uniform(rng, -1, 1) * geometry.wobble_deg), Eigen::Vector3d::UnitX()) *
       Eigen::AngleAxisd(radians(uniform(rng, -1, 1) * geometry.wobble_deg), Eigen::Vector3d::UnitY()))
          .toRotationMatrix();
  // Rotate about the board centre, then move: cTm maps M to C.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = nominal.linear() * effector_rotation;
  pose.translation() = Eigen::Vector3d(0, 0, geometry.distance_m) + motion - pose.linear() * geometry.target_centre_m;
  return pose;
}

std::vector<double> drawFeatureSigmas(std::size_t count, double sigma_px, double spread, std::mt19937_64& rng) {
  std::vector<double> sigmas(count);
  for (double& s : sigmas) s = sigma_px * uniform(rng, 1.0 - spread, 1.0 + spread);
  return sigmas;
}

metrology::Detection exactDetection(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                    const Eigen::Isometry3d& cTm) {
  metrology::Detection detection;
  for (std::size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector2d pixel;
    if (!camera.project(cTm * points[i], &pixel)) continue;
    if (pixel.x() < 0.0 || pixel.y() < 0.0 || pixel.x() > camera.width - 1.0 || pixel.y() > camera.height - 1.0)
      continue;
    detection.ids.push_back(static_cast<int>(i));
    detection.pixels.push_back(pixel);
  }
  detection.found = detection.size() >= 4;
  if (!detection.found) detection.reason = "fewer than 4 features in the image";
  return detection;
}

std::vector<metrology::Detection> noisyDetections(const metrology::Detection& exact, const std::vector<double>& sigma_px,
                                                  int images, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<metrology::Detection> result(static_cast<std::size_t>(images), exact);
  for (auto& detection : result)
    for (std::size_t i = 0; i < detection.size(); ++i) {
      const double sigma = sigma_px.at(static_cast<std::size_t>(detection.ids[i]));
      detection.pixels[i] += sigma * Eigen::Vector2d(normal(rng), normal(rng));
    }
  return result;
}

Eigen::MatrixXd simulatedCalibrationCovariance(const calibration::Camera& camera,
                                               const std::vector<Eigen::Vector3d>& points, int views, double sigma_px,
                                               std::mt19937_64& rng) {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : points) centre += p;
  centre /= static_cast<double>(points.size());
  const Eigen::Index k = static_cast<Eigen::Index>(camera.params.size());
  Eigen::MatrixXd information = Eigen::MatrixXd::Zero(k, k);
  int used = 0;
  for (int attempt = 0; used < views && attempt < 50 * views; ++attempt) {
    const double distance = uniform(rng, 0.45, 0.9);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = (Eigen::AngleAxisd(radians(uniform(rng, -35, 35)), Eigen::Vector3d::UnitX()) *
                     Eigen::AngleAxisd(radians(uniform(rng, -35, 35)), Eigen::Vector3d::UnitY()) *
                     Eigen::AngleAxisd(radians(uniform(rng, -30, 30)), Eigen::Vector3d::UnitZ()))
                        .toRotationMatrix();
    const Eigen::Vector3d lateral(uniform(rng, -0.3, 0.3) * distance, uniform(rng, -0.22, 0.22) * distance, distance);
    pose.translation() = lateral - pose.linear() * centre;
    const metrology::Detection detection = exactDetection(camera, points, pose);
    if (detection.size() < points.size() * 3 / 4) continue;  // a calibration view shows most of the board
    metrology::AveragedFeatures features;
    features.ids = detection.ids;
    features.pixels = detection.pixels;
    features.covariance.assign(detection.size(), sigma_px * sigma_px * Eigen::Matrix2d::Identity());
    features.observations.assign(detection.size(), 1);
    features.pooled_dof = 1;  // the covariance above is known
    Eigen::MatrixXd jp, jk;
    metrology::reprojectionJacobians(camera, points, features, pose, &jp, &jk);
    // Eliminate this view's pose (Schur complement): what the view tells about the camera.
    const Eigen::MatrixXd pose_information = jp.transpose() * jp;
    const Eigen::MatrixXd cross = jp.transpose() * jk;
    information += jk.transpose() * jk - cross.transpose() * pose_information.ldlt().solve(cross);
    ++used;
  }
  if (used < views) throw std::runtime_error("simulatedCalibrationCovariance: could not place the views");
  const Eigen::MatrixXd covariance = information.inverse();
  return 0.5 * (covariance + covariance.transpose());
}

calibration::Camera drawCamera(const calibration::Camera& camera, std::mt19937_64& rng) {
  calibration::Camera drawn = camera;
  if (camera.covariance.size() == 0) return drawn;
  const Eigen::LLT<Eigen::MatrixXd> llt(camera.covariance);
  if (llt.info() != Eigen::Success) throw std::invalid_argument("drawCamera: covariance is not positive definite");
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd z(camera.covariance.rows());
  for (Eigen::Index i = 0; i < z.size(); ++i) z[i] = normal(rng);
  const Eigen::VectorXd delta = llt.matrixL() * z;
  for (Eigen::Index i = 0; i < delta.size(); ++i) drawn.params[static_cast<std::size_t>(i)] += delta[i];
  return drawn;
}

}  // namespace mire::datasets
