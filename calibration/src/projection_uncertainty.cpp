// Projection uncertainty à la mrcal (calibrate.hpp): how far the pixel of a fixed world point
// moves when the calibration is redone with other noise, propagated to first order from the
// covariance of the intrinsics and the poses.
#include "mire/calibration/calibrate.hpp"

#include <ceres/rotation.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>

namespace mire::calibration {

namespace {
using Pose = Eigen::Matrix<double, 6, 1>;

Eigen::Vector3d applyPose(const Pose& pose, const Eigen::Vector3d& point) {
  Eigen::Vector3d out;
  ceres::AngleAxisRotatePoint(pose.data(), point.data(), out.data());
  return out + pose.tail<3>();
}

Eigen::Vector3d applyInversePose(const Pose& pose, const Eigen::Vector3d& point) {
  const Eigen::Vector3d minus_rotation = -pose.head<3>();
  Eigen::Vector3d out;
  const Eigen::Vector3d shifted = point - pose.tail<3>();
  ceres::AngleAxisRotatePoint(minus_rotation.data(), shifted.data(), out.data());
  return out;
}

std::vector<Pose> posesOf(const CalibrationResult& result) {
  std::vector<Pose> poses;
  for (const int v : result.state_view_index) {
    Pose pose;
    pose << result.views[v].rotation, result.views[v].translation;
    poses.push_back(pose);
  }
  return poses;
}
}  // namespace

Eigen::Vector2d reprojectThroughEstimate(const std::vector<double>& estimate_params,
                                         const std::vector<Pose>& estimate_poses,
                                         const std::vector<double>& truth_params, const std::vector<Pose>& truth_poses,
                                         const Eigen::Vector2d& pixel, double distance_m, LensModel lens) {
  Eigen::Vector2d nan = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  Camera truth;
  truth.lens = lens;
  truth.params = truth_params;
  Eigen::Vector2d normalized;
  if (!truth.unproject(pixel, &normalized)) return nan;
  const Eigen::Vector3d point_camera = distance_m * Eigen::Vector3d(normalized.x(), normalized.y(), 1.0);
  // mrcal's reference frame is the mean of the target frames: the point is expressed in every
  // view's target frame (true poses), brought back by the estimated poses, and averaged.
  Eigen::Vector3d moved = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < truth_poses.size(); ++i)
    moved += applyPose(estimate_poses[i], applyInversePose(truth_poses[i], point_camera));
  moved /= static_cast<double>(truth_poses.size());
  Eigen::Vector2d out;
  if (!projectPoint(estimate_params.data(), lens, static_cast<int>(estimate_params.size()) - kIntrinsicCount,
                    moved.data(), out.data()))
    return nan;
  return out;
}

double projectionUncertaintyPx(const CalibrationResult& result, const Eigen::Vector2d& pixel, double distance_m) {
  const Eigen::Matrix2d covariance = projectionCovariancePx(result, pixel, distance_m);
  if (!covariance.allFinite()) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(covariance);
  return std::sqrt(std::max(0.0, eigen.eigenvalues().maxCoeff()));
}

Eigen::Matrix2d projectionCovariancePx(const CalibrationResult& result, const Eigen::Vector2d& pixel, double distance_m) {
  Eigen::Matrix2d nan = Eigen::Matrix2d::Constant(std::numeric_limits<double>::quiet_NaN());
  const std::vector<double>& params = result.camera.params;
  const std::vector<Pose> poses = posesOf(result);
  const int parameter_count = static_cast<int>(params.size());
  const int state_size = static_cast<int>(result.state_covariance.rows());
  if (state_size != parameter_count + 6 * static_cast<int>(poses.size())) return nan;
  // Central differences over the state (intrinsics, then 6 per pose); fixed entries have
  // zero variance and are skipped.
  Eigen::MatrixXd jacobian = Eigen::MatrixXd::Zero(2, state_size);
  for (int j = 0; j < state_size; ++j) {
    if (!(result.state_covariance(j, j) > 0.0)) continue;
    const double step = 1e-3 * std::sqrt(result.state_covariance(j, j));
    std::vector<double> plus_params = params, minus_params = params;
    std::vector<Pose> plus_poses = poses, minus_poses = poses;
    if (j < parameter_count) {
      plus_params[j] += step;
      minus_params[j] -= step;
    } else {
      const int view = (j - parameter_count) / 6, component = (j - parameter_count) % 6;
      plus_poses[view](component) += step;
      minus_poses[view](component) -= step;
    }
    const Eigen::Vector2d plus =
        reprojectThroughEstimate(plus_params, plus_poses, params, poses, pixel, distance_m, result.camera.lens);
    const Eigen::Vector2d minus =
        reprojectThroughEstimate(minus_params, minus_poses, params, poses, pixel, distance_m, result.camera.lens);
    if (!plus.allFinite() || !minus.allFinite()) return nan;
    jacobian.col(j) = (plus - minus) / (2.0 * step);
  }
  return jacobian * result.state_covariance * jacobian.transpose();
}

ProjectionUncertaintySummary summarizeProjectionUncertainty(const CalibrationResult& result) {
  const double w = result.camera.width, h = result.camera.height, d = result.uncertainty_distance_m;
  ProjectionUncertaintySummary summary;
  summary.centre_px = projectionUncertaintyPx(result, {0.5 * (w - 1), 0.5 * (h - 1)}, d);
  summary.edge_px = projectionUncertaintyPx(result, {w - 1, 0.5 * (h - 1)}, d);
  summary.corner_px = projectionUncertaintyPx(result, {0.0, 0.0}, d);
  return summary;
}

}  // namespace mire::calibration
