#include "mire/metrology/pose_estimation.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <opencv2/calib3d.hpp>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace mire::metrology {
namespace {

constexpr int kCameraStride = 4;

// Whitened reprojection residual of one feature: L⁻¹ (project(cTm · X) − x̄), with
// L Lᵀ = Σ the covariance of the averaged feature x̄. Parameter blocks: pose = (angle-axis r,
// translation t), camera = calibration::Camera::params. Templated projection (doc/measurement.md, step 4 "Pose").
struct ReprojectionResidual {
  Eigen::Vector3d point;
  Eigen::Vector2d observed;
  Eigen::Matrix2d whitening;
  int distortion_count;
  calibration::LensModel lens;

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    const T* pose = blocks[0];
    const T* camera = blocks[1];
    const T target_point[3] = {T(point.x()), T(point.y()), T(point.z())};
    T camera_point[3];
    ceres::AngleAxisRotatePoint(pose, target_point, camera_point);
    for (int i = 0; i < 3; ++i) camera_point[i] += pose[3 + i];
    T pixel[2];
    if (!calibration::projectPoint(camera, lens, distortion_count, camera_point, pixel)) return false;
    const T ex = pixel[0] - T(observed.x());
    const T ey = pixel[1] - T(observed.y());
    residual[0] = T(whitening(0, 0)) * ex + T(whitening(0, 1)) * ey;
    residual[1] = T(whitening(1, 0)) * ex + T(whitening(1, 1)) * ey;
    return true;
  }
};

using ResidualCost = ceres::DynamicAutoDiffCostFunction<ReprojectionResidual, kCameraStride>;

std::unique_ptr<ResidualCost> makeCost(const calibration::Camera& camera, const Eigen::Vector3d& point,
                                       const Eigen::Vector2d& observed, const Eigen::Matrix2d& whitening) {
  auto cost = std::make_unique<ResidualCost>(
      new ReprojectionResidual{point, observed, whitening, camera.distortionCount(), camera.lens});
  cost->AddParameterBlock(6);
  cost->AddParameterBlock(static_cast<int>(camera.params.size()));
  cost->SetNumResiduals(2);
  return cost;
}

// L⁻¹ for each feature (identity when the features carry no scatter).
std::vector<Eigen::Matrix2d> whiteningMatrices(const AveragedFeatures& features, const PoseOptions& options) {
  std::vector<Eigen::Matrix2d> result;
  result.reserve(features.size());
  const double floor = options.covariance_floor_px * options.covariance_floor_px;
  for (std::size_t i = 0; i < features.size(); ++i) {
    if (!features.hasScatter()) {
      result.emplace_back(Eigen::Matrix2d::Identity());
      continue;
    }
    const Eigen::Matrix2d covariance = features.covariance[i] + floor * Eigen::Matrix2d::Identity();
    const Eigen::Matrix2d lower = covariance.llt().matrixL();
    result.emplace_back(lower.inverse());
  }
  return result;
}

// pose = (angle-axis, translation) ↔ Isometry3d.
Eigen::Isometry3d isometryFromParameters(const double pose[6]) {
  return isometryFromVectors(Eigen::Vector3d(pose[3], pose[4], pose[5]), Eigen::Vector3d(pose[0], pose[1], pose[2]));
}

// Minimises the whitened reprojection error from `pose` (in place); returns ½ Σ r².
double refine(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
              const AveragedFeatures& features, const std::vector<Eigen::Matrix2d>& whitening, double pose[6],
              int max_iterations) {
  std::vector<double> camera_params = camera.params;
  ceres::Problem problem;
  for (std::size_t i = 0; i < features.size(); ++i) {
    const auto& point = points[static_cast<std::size_t>(features.ids[i])];
    problem.AddResidualBlock(makeCost(camera, point, features.pixels[i], whitening[i]).release(), nullptr, pose,
                             camera_params.data());
  }
  problem.SetParameterBlockConstant(camera_params.data());
  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = max_iterations;
  solver_options.function_tolerance = 1e-14;
  solver_options.gradient_tolerance = 1e-14;
  solver_options.parameter_tolerance = 1e-12;
  solver_options.num_threads = 1;  // poses are measured in parallel by the caller
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem, &summary);
  if (summary.termination_type == ceres::FAILURE || !std::isfinite(summary.final_cost))
    return std::numeric_limits<double>::infinity();
  return summary.final_cost;
}

// Whitened Jacobians with the given whitening; J_p columns in (angle-axis, t) order.
void jacobians(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
               const AveragedFeatures& features, const std::vector<Eigen::Matrix2d>& whitening, const double pose[6],
               Eigen::MatrixXd* jacobian_pose, Eigen::MatrixXd* jacobian_intrinsics) {
  const Eigen::Index n = static_cast<Eigen::Index>(features.size());
  const int k = static_cast<int>(camera.params.size());
  jacobian_pose->setZero(2 * n, 6);
  jacobian_intrinsics->setZero(2 * n, k);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMajor jp(2, 6), jk(2, k);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto cost = makeCost(camera, points[static_cast<std::size_t>(features.ids[static_cast<std::size_t>(i)])],
                               features.pixels[static_cast<std::size_t>(i)], whitening[static_cast<std::size_t>(i)]);
    const double* parameters[2] = {pose, camera.params.data()};
    double residual[2];
    double* blocks[2] = {jp.data(), jk.data()};
    if (!cost->Evaluate(parameters, residual, blocks)) continue;  // behind the camera: no information
    jacobian_pose->middleRows(2 * i, 2) = jp;
    jacobian_intrinsics->middleRows(2 * i, 2) = jk;
  }
}

// Reorders (angle-axis, t) columns to the public (t, r) order.
Eigen::MatrixXd toTranslationFirst(const Eigen::MatrixXd& jacobian_pose) {
  Eigen::MatrixXd result(jacobian_pose.rows(), 6);
  result.leftCols(3) = jacobian_pose.rightCols(3);
  result.rightCols(3) = jacobian_pose.leftCols(3);
  return result;
}

double rotationDistance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle();
}

// One refined IPPE solution: angle-axis, translation (cTm) and its final cost.
struct Candidate {
  double pose[6];
  double cost;
};

// IPPE on exactly undistorted rays (normalised coordinates, K = I, no distortion): the
// candidate rotation and translation vectors, or the reason there are none.
std::string ippeSolutions(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                          const AveragedFeatures& features, std::vector<cv::Mat>* rvecs, std::vector<cv::Mat>* tvecs) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> rays;
  for (std::size_t i = 0; i < features.size(); ++i) {
    const auto& point = points[static_cast<std::size_t>(features.ids[i])];
    Eigen::Vector2d normalized;
    if (!camera.unproject(features.pixels[i], &normalized)) continue;
    object.emplace_back(point.x(), point.y(), point.z());
    rays.emplace_back(normalized.x(), normalized.y());
  }
  if (object.size() < 4) return "fewer than 4 features could be undistorted";
  try {
    cv::solvePnPGeneric(object, rays, cv::Mat::eye(3, 3, CV_64F), cv::noArray(), *rvecs, *tvecs, false,
                        cv::SOLVEPNP_IPPE);
  } catch (const cv::Exception& e) {
    return std::string("IPPE initialisation failed: ") + e.what();
  }
  if (rvecs->empty()) return "IPPE initialisation found no pose (degenerate feature layout?)";
  return {};
}

// Ceres refinement of each IPPE solution in front of the camera through the full distortion
// model; the finite ones, cheapest first.
std::vector<Candidate> refinedCandidates(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                         const AveragedFeatures& features, const std::vector<Eigen::Matrix2d>& whitening,
                                         const std::vector<cv::Mat>& rvecs, const std::vector<cv::Mat>& tvecs,
                                         const PoseOptions& options) {
  std::vector<Candidate> candidates;
  for (std::size_t s = 0; s < rvecs.size(); ++s) {
    Candidate candidate{};
    for (int i = 0; i < 3; ++i) {
      candidate.pose[i] = rvecs[s].at<double>(i);
      candidate.pose[3 + i] = tvecs[s].at<double>(i);
    }
    if (!(candidate.pose[5] > 0.0)) continue;  // target behind the camera
    candidate.cost = refine(camera, points, features, whitening, candidate.pose, options.max_iterations);
    if (std::isfinite(candidate.cost)) candidates.push_back(candidate);
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) { return a.cost < b.cost; });
  return candidates;
}

// The cheapest candidate is the pose; a distinct second one is the planar-pose ambiguity's
// alternative, flagged when its cost is within options.ambiguity_ratio.
void chooseCandidate(const std::vector<Candidate>& candidates, const PoseOptions& options, PoseEstimate* estimate) {
  const Candidate& best = candidates.front();
  estimate->cTm = isometryFromParameters(best.pose);
  estimate->rotation_vector = Eigen::Vector3d(best.pose[0], best.pose[1], best.pose[2]);
  estimate->translation = Eigen::Vector3d(best.pose[3], best.pose[4], best.pose[5]);
  estimate->ambiguity_cost_ratio = std::numeric_limits<double>::infinity();
  if (candidates.size() < 2) return;
  const Candidate& second = candidates[1];
  const Eigen::Isometry3d other = isometryFromParameters(second.pose);
  // Both IPPE solutions may refine to the same minimum: then there is no ambiguity.
  const bool distinct =
      rotationDistance(other, estimate->cTm) > 1e-6 || (other.translation() - estimate->translation).norm() > 1e-9;
  if (distinct) {
    estimate->alternative_cTm = other;
    estimate->ambiguity_cost_ratio = best.cost > 0.0 ? second.cost / best.cost : std::numeric_limits<double>::infinity();
    estimate->ambiguous = estimate->ambiguity_cost_ratio < options.ambiguity_ratio;
  }
}

// RMS reprojection residual in pixels of the chosen pose.
double rmsResidualPx(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                     const AveragedFeatures& features, const Eigen::Isometry3d& cTm) {
  double squared_px = 0.0;
  for (std::size_t i = 0; i < features.size(); ++i) {
    Eigen::Vector2d pixel;
    if (camera.project(cTm * points[static_cast<std::size_t>(features.ids[i])], &pixel))
      squared_px += (pixel - features.pixels[i]).squaredNorm();
  }
  return std::sqrt(squared_px / static_cast<int>(features.size()));
}

// Below this many residual degrees of freedom a one-image σ is pooled with the calibration's
// noise (the same threshold as measurePose's warning).
constexpr int kPriorDof = 10;

// Precision. Fisher information of the whitened residuals; the intrinsics part through the
// implicit function theorem at the optimum: A = −(J_pᵀ J_p)⁻¹ J_pᵀ J_k. False (with the
// reason set) when the information matrix is singular.
bool estimatePrecision(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                       const AveragedFeatures& features, const std::vector<Eigen::Matrix2d>& whitening,
                       const Candidate& best, const PoseOptions& options, PoseEstimate* estimate) {
  const int dof = 2 * static_cast<int>(features.size()) - 6;
  Eigen::MatrixXd jp, jk;
  jacobians(camera, points, features, whitening, best.pose, &jp, &jk);
  jp = toTranslationFirst(jp);
  const PosePrecision precision = posePrecision(camera, jp, jk);
  if (!precision.observable) {
    estimate->reason = "the pose is not observable from these features (singular information matrix)";
    return false;
  }
  Matrix6d noise = precision.information_inverse;
  if (!features.hasScatter()) {
    // No multi-image scatter: the residuals estimate an isotropic pixel noise (unit weights),
    // σ² = Σ r² / (2N − 6), floored. reduced_chi2 is then computed with that covariance, the
    // one actually used, as for many images: 1 by construction unless floored.
    estimate->scatter_from_residuals = true;
    const double floor = options.covariance_floor_px * options.covariance_floor_px;
    double variance = dof > 0 ? std::max(2.0 * best.cost / dof, floor) : floor;
    // Fewer than kPriorDof residual degrees of freedom (one image of one or two tags): that
    // estimate is itself uncertain by 1/√(2·dof), so it is pooled with the calibration's
    // per-coordinate noise rms_px²/2 weighted as kPriorDof degrees of freedom (doc/measurement.md,
    // "Warnings with numbers").
    const double prior = 0.5 * camera.rms_px * camera.rms_px;
    if (dof < kPriorDof && prior > 0.0)
      variance = std::max((2.0 * best.cost + kPriorDof * prior) / (std::max(dof, 0) + kPriorDof), floor);
    noise *= variance;
    estimate->reduced_chi2 = dof > 0 ? 2.0 * best.cost / (dof * variance) : 0.0;
  }
  estimate->covariance_pixel_noise = 0.5 * (noise + noise.transpose());
  const bool inflate = options.inflate_by_residuals && !estimate->scatter_from_residuals;
  estimate->covariance_noise = estimate->covariance_pixel_noise * (inflate ? std::max(1.0, estimate->reduced_chi2) : 1.0);
  estimate->covariance_intrinsics = precision.covariance_intrinsics;
  estimate->intrinsics_sensitivity = precision.intrinsics_sensitivity;
  estimate->covariance = estimate->covariance_noise + estimate->covariance_intrinsics;
  return true;
}

}  // namespace

Eigen::Matrix<double, 6, 1> PoseEstimate::sigmas(const Matrix6d& covariance) {
  return covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
}

PosePrecision posePrecision(const calibration::Camera& camera, const Eigen::MatrixXd& jacobian_pose,
                            const Eigen::MatrixXd& jacobian_intrinsics) {
  PosePrecision precision;
  const Matrix6d information = jacobian_pose.transpose() * jacobian_pose;
  const Eigen::FullPivLU<Matrix6d> lu(information);
  if (!lu.isInvertible()) return precision;
  precision.observable = true;
  precision.information_inverse = lu.inverse();
  if (camera.covariance.rows() == static_cast<Eigen::Index>(camera.params.size()) && camera.covariance.size() > 0) {
    precision.intrinsics_sensitivity = -lu.solve(Eigen::MatrixXd(jacobian_pose.transpose() * jacobian_intrinsics));
    const Matrix6d intrinsics =
        precision.intrinsics_sensitivity * camera.covariance * precision.intrinsics_sensitivity.transpose();
    precision.covariance_intrinsics = 0.5 * (intrinsics + intrinsics.transpose());
  }
  return precision;
}

void reprojectionJacobians(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                           const AveragedFeatures& features, const Eigen::Isometry3d& cTm, Eigen::MatrixXd* jacobian_pose,
                           Eigen::MatrixXd* jacobian_intrinsics, const PoseOptions& options) {
  const auto whitening = whiteningMatrices(features, options);
  const Eigen::Vector3d r = rotationVector(cTm.linear());
  const double pose[6] = {r.x(), r.y(), r.z(), cTm.translation().x(), cTm.translation().y(), cTm.translation().z()};
  Eigen::MatrixXd jp;
  jacobians(camera, points, features, whitening, pose, &jp, jacobian_intrinsics);
  *jacobian_pose = toTranslationFirst(jp);
}

Eigen::MatrixXd featureSensitivity(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                                   const AveragedFeatures& features, const Eigen::Isometry3d& cTm,
                                   const PoseOptions& options) {
  Eigen::MatrixXd jp, jk;
  reprojectionJacobians(camera, points, features, cTm, &jp, &jk, options);
  const auto whitening = whiteningMatrices(features, options);
  const Eigen::FullPivLU<Matrix6d> lu(Matrix6d(jp.transpose() * jp));
  if (!lu.isInvertible()) return {};
  // ∂r_w/∂x = −L⁻¹ per feature, so δpose = (J_pᵀ J_p)⁻¹ J_pᵀ L⁻¹ δx.
  Eigen::MatrixXd weighted = jp.transpose();
  for (std::size_t i = 0; i < features.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(2 * i);
    weighted.middleCols(c, 2) = Eigen::MatrixXd(weighted.middleCols(c, 2) * whitening[i]);
  }
  return lu.solve(weighted);
}

// Stages: IPPE initialisation, Ceres refinement of each solution, the choice between them,
// residual statistics, then the precision.
PoseEstimate estimatePose(const calibration::Camera& camera, const std::vector<Eigen::Vector3d>& points,
                          const AveragedFeatures& features, const PoseOptions& options) {
  PoseEstimate estimate;
  const int n = static_cast<int>(features.size());
  estimate.feature_count = n;
  if (n < 4) {
    estimate.reason = "only " + std::to_string(n) + " features (a pose needs at least 4)";
    return estimate;
  }
  std::vector<cv::Mat> rvecs, tvecs;
  estimate.reason = ippeSolutions(camera, points, features, &rvecs, &tvecs);
  if (!estimate.reason.empty()) return estimate;
  const auto whitening = whiteningMatrices(features, options);
  const std::vector<Candidate> candidates = refinedCandidates(camera, points, features, whitening, rvecs, tvecs, options);
  if (candidates.empty()) {
    estimate.reason = "the pose refinement failed from every IPPE solution";
    return estimate;
  }
  chooseCandidate(candidates, options, &estimate);
  const Candidate& best = candidates.front();
  estimate.rms_px = rmsResidualPx(camera, points, features, estimate.cTm);
  const int dof = 2 * n - 6;
  estimate.reduced_chi2 = dof > 0 ? 2.0 * best.cost / dof : 0.0;
  estimate.valid = estimatePrecision(camera, points, features, whitening, best, options, &estimate);
  return estimate;
}

}  // namespace mire::metrology
