#include "mire/metrology/pose_prediction.hpp"

#include "mire/metrology/feature_averaging.hpp"
#include "mire/metrology/pose_estimation.hpp"
#include "mire/support/constants.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace mire::metrology {
namespace {

using support::kPi;

std::string threeDigits(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

// Distance of a pixel to the nearest image border (negative outside), in OpenCV's pixel
// convention (the image spans [-0.5, size - 0.5]).
double insideMargin(const calibration::Camera& camera, const Eigen::Vector2d& pixel) {
  const double left = pixel.x() + 0.5, right = camera.width - 0.5 - pixel.x();
  const double top = pixel.y() + 0.5, bottom = camera.height - 0.5 - pixel.y();
  return std::min(std::min(left, right), std::min(top, bottom));
}

// Projects a target-frame point; false when it is behind the camera or beyond the lens's valid
// field (the distortion polynomial folds back there: the pixel's ray is not the point's).
bool projectInField(const calibration::Camera& camera, const Eigen::Isometry3d& cTm, const Eigen::Vector3d& point,
                    Eigen::Vector2d* pixel) {
  const Eigen::Vector3d p = cTm * point;
  if (!(p.z() > 0.0) || !camera.project(p, pixel)) return false;
  Eigen::Vector2d ray;
  if (!camera.unproject(*pixel, &ray)) return false;
  return (ray - p.head<2>() / p.z()).norm() < 1e-6;
}

// The board's outline in frame M: the features' bounding box grown by the outer squares of
// a chessboard or a ChArUco board (their features are inner corners), sampled along its sides.
std::vector<Eigen::Vector3d> outlinePoints(const Target& target) {
  Eigen::Vector3d low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d high = -low;
  for (const auto& p : target.points()) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  const TargetType type = target.spec().type;
  const double border =
      (type == TargetType::Chessboard || type == TargetType::Charuco) ? target.spec().square_size_m : 0.0;
  low.head<2>().array() -= border;
  high.head<2>().array() += border;
  std::vector<Eigen::Vector3d> outline;
  constexpr int kPerSide = 8;
  for (int k = 0; k <= kPerSide; ++k) {
    const double s = static_cast<double>(k) / kPerSide;
    const double x = low.x() + s * (high.x() - low.x()), y = low.y() + s * (high.y() - low.y());
    outline.emplace_back(x, low.y(), 0.0);
    outline.emplace_back(x, high.y(), 0.0);
    outline.emplace_back(low.x(), y, 0.0);
    outline.emplace_back(high.x(), y, 0.0);
  }
  return outline;
}

// Angle between the target's normal (z_M) and the line of sight to the features' centroid.
double tiltDegrees(const Target& target, const Eigen::Isometry3d& cTm) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : target.points()) centroid += p;
  centroid /= static_cast<double>(target.points().size());
  const Eigen::Vector3d sight = (cTm * centroid).normalized();
  const Eigen::Vector3d normal = cTm.linear().col(2);
  return std::acos(std::min(1.0, std::abs(normal.dot(sight)))) * 180.0 / kPi;
}

}  // namespace

Visibility targetVisibility(const calibration::Camera& camera, const Target& target, const Eigen::Isometry3d& cTm,
                            const VisibilityOptions& options) {
  Visibility result;
  result.min_margin_px = std::numeric_limits<double>::infinity();
  const auto& points = target.points();
  for (std::size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector2d pixel;
    if (!projectInField(camera, cTm, points[i], &pixel)) {
      result.reason = "feature " + std::to_string(i) + " is behind the camera or outside the lens's field";
      return result;
    }
    result.min_margin_px = std::min(result.min_margin_px, insideMargin(camera, pixel));
  }
  if (result.min_margin_px < options.margin_px) {
    result.reason = "a feature is " + threeDigits(result.min_margin_px) + " px from the image border (margin " +
                    threeDigits(options.margin_px) + " px)";
    return result;
  }
  for (const auto& p : outlinePoints(target)) {
    Eigen::Vector2d pixel;
    const bool ok = projectInField(camera, cTm, p, &pixel);
    const double margin = ok ? insideMargin(camera, pixel) : -std::numeric_limits<double>::infinity();
    result.min_margin_px = std::min(result.min_margin_px, margin);
    if (margin < 0.0) {
      result.reason = "the board's outline leaves the image";
      return result;
    }
  }
  result.tilt_deg = tiltDegrees(target, cTm);
  if (result.tilt_deg > options.max_tilt_deg) {
    result.reason = "the target is tilted " + threeDigits(result.tilt_deg) + " deg from the line of sight (limit " +
                    threeDigits(options.max_tilt_deg) + " deg)";
    return result;
  }
  result.visible = true;
  return result;
}

double PredictionOptions::systematicSigma(double square_px, double edge_angle_rad) const {
  if (systematic_model == SystematicModel::Constant || !(square_px > 0.0)) return systematic_px;
  const double at_reference = systematic_mean_px + systematic_grid_px * std::cos(4.0 * edge_angle_rad);
  return std::max(0.0, at_reference) * reference_square_px / square_px;
}

double PredictionOptions::featureSigma() const { return featureSigma(systematic_px); }

double PredictionOptions::featureSigma(double systematic) const {
  return std::sqrt(pixel_sigma * pixel_sigma / std::max(1, images) + systematic * systematic);
}

BoardImageGeometry boardImageGeometry(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                      const Eigen::Isometry3d& cTm) {
  BoardImageGeometry geometry;
  if (points.size() < 2) return geometry;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero(), edge = Eigen::Vector3d::Zero();
  double spacing = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < points.size(); ++i) {
    centroid += points[i];
    const double d = (points[i] - points[0]).norm();
    if (i > 0 && d > 0.0 && d < spacing) {
      spacing = d;
      edge = points[i] - points[0];
    }
  }
  if (!std::isfinite(spacing)) return geometry;
  centroid /= static_cast<double>(points.size());
  // The second side of the square: the edge turned by 90° in the board's plane (z_M = 0).
  const Eigen::Vector3d other(-edge.y(), edge.x(), 0.0);
  Eigen::Vector2d centre, along, across;
  if (!camera.project(cTm * centroid, &centre) || !camera.project(cTm * (centroid + edge), &along) ||
      !camera.project(cTm * (centroid + other), &across))
    return geometry;
  const Eigen::Vector2d u = along - centre, v = across - centre;
  geometry.square_px = std::sqrt(std::abs(u.x() * v.y() - u.y() * v.x()));
  geometry.edge_angle_rad = std::atan2(u.y(), u.x());
  geometry.valid = geometry.square_px > 0.0;
  return geometry;
}

// estimatePose's precision (pose_estimation.hpp, step 3) at noise-free features: the whitened
// Jacobians of reprojectionJacobians, then (a) and (b).
PosePrediction predictPoseCovariance(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                     const Eigen::Isometry3d& cTm, const PredictionOptions& options) {
  PosePrediction prediction;
  const BoardImageGeometry board = boardImageGeometry(camera, points, cTm);
  prediction.systematic_px =
      board.valid ? options.systematicSigma(board.square_px, board.edge_angle_rad) : options.systematic_px;
  const double variance = std::pow(options.featureSigma(prediction.systematic_px), 2);
  AveragedFeatures features;
  for (std::size_t i = 0; i < points.size(); ++i) {
    Eigen::Vector2d pixel;
    if (!camera.project(cTm * points[i], &pixel)) continue;
    features.ids.push_back(static_cast<int>(i));
    features.pixels.push_back(pixel);
    features.covariance.emplace_back(variance * Eigen::Matrix2d::Identity());
    features.observations.push_back(options.images);
  }
  features.images_used = features.images_total = options.images;
  features.pooled_covariance = variance * options.images * Eigen::Matrix2d::Identity();
  features.pooled_dof = 1;  // the covariance is given: whiten by it (hasScatter)
  if (features.size() < 4 || !(variance > 0.0)) {
    prediction.reason = features.size() < 4 ? "fewer than 4 features project into the camera" : "zero feature noise";
    return prediction;
  }
  Eigen::MatrixXd jp, jk;
  reprojectionJacobians(camera, points, features, cTm, &jp, &jk);
  const PosePrecision precision = posePrecision(camera, jp, jk);
  if (!precision.observable) {
    prediction.reason = "the pose is not observable from these features (singular information matrix)";
    return prediction;
  }
  const Matrix6d& noise = precision.information_inverse;
  prediction.covariance_noise = 0.5 * (noise + noise.transpose());
  prediction.covariance_intrinsics = precision.covariance_intrinsics;
  prediction.intrinsics_sensitivity = precision.intrinsics_sensitivity;
  prediction.covariance = prediction.covariance_noise + prediction.covariance_intrinsics;
  prediction.valid = true;
  return prediction;
}

}  // namespace mire::metrology
