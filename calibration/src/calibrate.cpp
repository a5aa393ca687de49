// Camera calibration by bundle adjustment (see calibrate.hpp for the pipeline).
#include "mire/calibration/calibrate.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/statistics.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numeric>
#include <set>
#include <stdexcept>

namespace mire::calibration {

int distortionCoefficientCount(DistortionModel model) {
  switch (model) {
    case DistortionModel::OpenCV4:
      return 4;
    case DistortionModel::OpenCV5:
      return 5;
    case DistortionModel::OpenCV8:
      return 8;
    case DistortionModel::OpenCV12:
      return 12;
    case DistortionModel::Pinhole:
      return 0;
    case DistortionModel::Fisheye:
      return 4;
  }
  return 5;
}

LensModel lensOf(DistortionModel model) {
  return model == DistortionModel::Fisheye ? LensModel::Fisheye : LensModel::OpenCV;
}

std::string distortionModelName(DistortionModel model) {
  switch (model) {
    case DistortionModel::OpenCV4:
      return "opencv4";
    case DistortionModel::OpenCV5:
      return "opencv5";
    case DistortionModel::OpenCV8:
      return "opencv8";
    case DistortionModel::OpenCV12:
      return "opencv12";
    case DistortionModel::Pinhole:
      return "pinhole";
    case DistortionModel::Fisheye:
      return "fisheye";
  }
  return "opencv5";
}

DistortionModel parseDistortionModel(const std::string& name) {
  for (const DistortionModel model : {DistortionModel::Pinhole, DistortionModel::OpenCV4, DistortionModel::OpenCV5,
                                      DistortionModel::OpenCV8, DistortionModel::OpenCV12, DistortionModel::Fisheye})
    if (name == distortionModelName(model)) return model;
  throw std::invalid_argument("unknown camera model '" + name +
                              "' (expected pinhole, opencv4, opencv5, opencv8, opencv12 or fisheye)");
}

namespace {

using Pose = Eigen::Matrix<double, 6, 1>;  // angle-axis, translation (cTm)

// Reprojection residual (px) of one target point in one view, through the shared templated
// projection (camera_model.hpp) so that each lens model is written once.
template <LensModel kLens, int kDistortion>
struct ReprojectionError {
  explicit ReprojectionError(const Eigen::Vector2d& observed) : observed_(observed) {}
  template <typename T>
  bool operator()(const T* intrinsics, const T* pose, const T* point, T* residual) const {
    T camera_point[3];
    ceres::AngleAxisRotatePoint(pose, point, camera_point);
    for (int i = 0; i < 3; ++i) camera_point[i] += pose[3 + i];
    T pixel[2];
    if (!projectPoint(intrinsics, kLens, kDistortion, camera_point, pixel)) return false;
    residual[0] = pixel[0] - observed_.x();
    residual[1] = pixel[1] - observed_.y();
    return true;
  }
  Eigen::Vector2d observed_;
};

template <LensModel kLens, int kDistortion>
ceres::CostFunction* makeCostFor(const Eigen::Vector2d& observed) {
  using Functor = ReprojectionError<kLens, kDistortion>;
  return new ceres::AutoDiffCostFunction<Functor, 2, kIntrinsicCount + kDistortion, 6, 3>(new Functor(observed));
}

// Ceres needs each parameter-block size at compile time: one case per calibrated model.
ceres::CostFunction* makeCost(LensModel lens, int distortion_count, const Eigen::Vector2d& observed) {
  if (lens == LensModel::Fisheye && distortion_count == 4) return makeCostFor<LensModel::Fisheye, 4>(observed);
  if (lens == LensModel::OpenCV) switch (distortion_count) {
      case 0:
        return makeCostFor<LensModel::OpenCV, 0>(observed);
      case 4:
        return makeCostFor<LensModel::OpenCV, 4>(observed);
      case 5:
        return makeCostFor<LensModel::OpenCV, 5>(observed);
      case 8:
        return makeCostFor<LensModel::OpenCV, 8>(observed);
      case 12:
        return makeCostFor<LensModel::OpenCV, 12>(observed);
      default:
        break;
    }
  throw std::invalid_argument("unsupported camera model for calibration (" + std::string(lensName(lens)) + ", " +
                              std::to_string(distortion_count) + " coefficients)");
}

Eigen::Vector2d projectWithPose(const std::vector<double>& params, LensModel lens, const Pose& pose,
                                const Eigen::Vector3d& point, bool* in_front) {
  Eigen::Vector3d camera_point;
  ceres::AngleAxisRotatePoint(pose.data(), point.data(), camera_point.data());
  camera_point += pose.tail<3>();
  Eigen::Vector2d pixel(0.0, 0.0);
  *in_front = projectPoint(params.data(), lens, static_cast<int>(params.size()) - kIntrinsicCount, camera_point.data(),
                           pixel.data());
  return pixel;
}

// The mutable state of the adjustment.
struct State {
  LensModel lens = LensModel::OpenCV;
  std::vector<double> params;
  std::vector<Pose> poses;              // one per view (meaningful when active)
  std::vector<Eigen::Vector3d> points;  // target points (refined or nominal)
  std::vector<bool> view_active;
  std::vector<std::vector<bool>> inlier;  // per view, per observation
};

struct Setup {
  const std::vector<CalibrationView>* views = nullptr;
  std::vector<int> fixed_indices;  // into params
  bool refine_target = false;
  std::array<int, 3> gauge{{-1, -1, -1}};
  std::vector<bool> point_refinable;  // seen in enough views to be an unknown
  int num_threads = 1;
};

// Builds and solves one pass. Returns the final cost.
void solvePass(const Setup& setup, State* state, RobustLoss loss, double loss_scale) {
  ceres::Problem problem;
  const int distortion_count = static_cast<int>(state->params.size()) - kIntrinsicCount;
  double* intrinsics = state->params.data();
  std::set<int> used_points;
  const auto& views = *setup.views;
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (!state->view_active[v]) continue;
    for (std::size_t k = 0; k < views[v].ids.size(); ++k) {
      if (!state->inlier[v][k]) continue;
      const int id = views[v].ids[k];
      ceres::LossFunction* loss_function = nullptr;
      if (loss == RobustLoss::Huber) loss_function = new ceres::HuberLoss(loss_scale);
      if (loss == RobustLoss::Cauchy) loss_function = new ceres::CauchyLoss(loss_scale);
      problem.AddResidualBlock(makeCost(state->lens, distortion_count, views[v].pixels[k]), loss_function, intrinsics,
                               state->poses[v].data(), state->points[id].data());
      used_points.insert(id);
    }
  }
  std::vector<int> fixed = setup.fixed_indices;
  if (!fixed.empty()) {
    if (static_cast<int>(fixed.size()) == static_cast<int>(state->params.size()))
      problem.SetParameterBlockConstant(intrinsics);
    else
      problem.SetManifold(intrinsics, new ceres::SubsetManifold(static_cast<int>(state->params.size()), fixed));
  }
  for (const int id : used_points) {
    double* point = state->points[id].data();
    if (!setup.refine_target || !setup.point_refinable[id] || id == setup.gauge[0] || id == setup.gauge[1]) {
      problem.SetParameterBlockConstant(point);
    } else if (id == setup.gauge[2]) {
      problem.SetManifold(point, new ceres::SubsetManifold(3, {2}));
    }
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  // The robust pass only has to find the outliers: a loose stop (Huber's kink slows the
  // final digits); the least-squares passes converge tightly (the covariance assumes it).
  const bool robust = loss != RobustLoss::None;
  options.max_num_iterations = robust ? 50 : 200;
  options.function_tolerance = robust ? 1e-8 : 1e-12;
  options.gradient_tolerance = robust ? 1e-8 : 1e-12;
  options.parameter_tolerance = robust ? 1e-8 : 1e-12;
  options.num_threads = setup.num_threads;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable()) throw std::runtime_error("calibration bundle adjustment failed: " + summary.message);
  // With the target's points free, an unconverged least-squares pass means a gauge or
  // conditioning problem whose result must not be written (doc/calibration.md).
  if (setup.refine_target && !robust && summary.termination_type == ceres::NO_CONVERGENCE)
    throw std::runtime_error("target refinement did not converge in " + std::to_string(options.max_num_iterations) +
                             " iterations (" + summary.message +
                             "): the views do not fix the target's shape; calibrate without --refine-target");
}

// Residual norms (px) of every active observation; inactive ones get NaN.
std::vector<std::vector<Eigen::Vector2d>> residualsOf(const std::vector<CalibrationView>& views, const State& state) {
  std::vector<std::vector<Eigen::Vector2d>> residuals(views.size());
  for (std::size_t v = 0; v < views.size(); ++v) {
    residuals[v].assign(views[v].ids.size(), Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN()));
    if (!state.view_active[v]) continue;
    for (std::size_t k = 0; k < views[v].ids.size(); ++k) {
      bool in_front = false;
      const Eigen::Vector2d pixel =
          projectWithPose(state.params, state.lens, state.poses[v], state.points[views[v].ids[k]], &in_front);
      if (in_front) residuals[v][k] = pixel - views[v].pixels[k];
    }
  }
  return residuals;
}

// σ of one residual component from the median residual norm (Rayleigh median = 1.1774 σ):
// insensitive to the outliers that the robust pass is about to down-weight.
double robustSigma(const std::vector<CalibrationView>& views, const State& state) {
  const auto residuals = residualsOf(views, state);
  std::vector<double> norms;
  for (std::size_t v = 0; v < views.size(); ++v)
    for (std::size_t k = 0; k < views[v].ids.size(); ++k)
      if (state.view_active[v] && state.inlier[v][k] && residuals[v][k].allFinite())
        norms.push_back(residuals[v][k].norm());
  return support::upperMedian(std::move(norms)) / std::sqrt(2.0 * std::log(2.0));
}

// Dense Jacobian of the final (plain least-squares) problem in tangent coordinates, with the
// column layout [free intrinsics | 6 per active view | free target coordinates].
struct Linearisation {
  Eigen::MatrixXd jacobian;
  std::vector<int> free_intrinsics;  // ambient index of each tangent intrinsic column
  int pose_columns_begin = 0;
  std::vector<int> active_views;
  Eigen::VectorXd residuals;  // px, rows of `jacobian`
  std::vector<int> row_view;  // position in active_views of each row's view
};

Linearisation linearise(const Setup& setup, State* state) {
  ceres::Problem::Options problem_options;
  ceres::Problem problem(problem_options);
  const int distortion_count = static_cast<int>(state->params.size()) - kIntrinsicCount;
  const auto& views = *setup.views;
  Linearisation result;
  std::set<int> used_points;
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (!state->view_active[v]) continue;
    result.active_views.push_back(static_cast<int>(v));
    for (std::size_t k = 0; k < views[v].ids.size(); ++k) {
      if (!state->inlier[v][k]) continue;
      problem.AddResidualBlock(makeCost(state->lens, distortion_count, views[v].pixels[k]), nullptr,
                               state->params.data(), state->poses[v].data(), state->points[views[v].ids[k]].data());
      used_points.insert(views[v].ids[k]);
      const int position = static_cast<int>(result.active_views.size()) - 1;
      result.row_view.insert(result.row_view.end(), {position, position});
    }
  }
  const int parameter_count = static_cast<int>(state->params.size());
  std::vector<int> fixed = setup.fixed_indices;
  for (int i = 0; i < parameter_count; ++i)
    if (std::find(fixed.begin(), fixed.end(), i) == fixed.end()) result.free_intrinsics.push_back(i);
  ceres::Problem::EvaluateOptions evaluate;
  if (!result.free_intrinsics.empty()) {
    if (!fixed.empty()) problem.SetManifold(state->params.data(), new ceres::SubsetManifold(parameter_count, fixed));
    evaluate.parameter_blocks.push_back(state->params.data());
  }
  result.pose_columns_begin = static_cast<int>(result.free_intrinsics.size());
  for (const int v : result.active_views) evaluate.parameter_blocks.push_back(state->poses[v].data());
  if (setup.refine_target) {
    for (const int id : used_points) {
      if (!setup.point_refinable[id] || id == setup.gauge[0] || id == setup.gauge[1]) continue;
      if (id == setup.gauge[2]) problem.SetManifold(state->points[id].data(), new ceres::SubsetManifold(3, {2}));
      evaluate.parameter_blocks.push_back(state->points[id].data());
    }
  }
  ceres::CRSMatrix crs;
  std::vector<double> residuals;
  problem.Evaluate(evaluate, nullptr, &residuals, nullptr, &crs);
  result.residuals = Eigen::Map<const Eigen::VectorXd>(residuals.data(), static_cast<Eigen::Index>(residuals.size()));
  result.jacobian = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int entry = crs.rows[row]; entry < crs.rows[row + 1]; ++entry)
      result.jacobian(row, crs.cols[entry]) = crs.values[entry];
  return result;
}

// (JᵀJ)⁻¹ with column equilibration (the columns mix px/rad and px/px); a rank-deficient
// problem is reported and inverted in the least-squares (pseudo-inverse) sense.
Eigen::MatrixXd inverseNormalMatrix(const Eigen::MatrixXd& jacobian, std::vector<std::string>* warnings) {
  const Eigen::Index n = jacobian.cols();
  Eigen::VectorXd scale(n);
  for (Eigen::Index c = 0; c < n; ++c) {
    const double norm = jacobian.col(c).norm();
    scale(c) = norm > 0.0 ? 1.0 / norm : 0.0;
  }
  const Eigen::MatrixXd scaled = jacobian * scale.asDiagonal();
  const Eigen::MatrixXd normal = scaled.transpose() * scaled;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(normal);
  const Eigen::VectorXd& values = eigen.eigenvalues();
  const double largest = values.maxCoeff();
  Eigen::VectorXd inverse_values(n);
  int deficient = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (values(i) > 1e-12 * largest) {
      inverse_values(i) = 1.0 / values(i);
    } else {
      inverse_values(i) = 0.0;
      ++deficient;
    }
  }
  if (deficient > 0)
    warnings->push_back("the views leave " + std::to_string(deficient) +
                        " parameter combination(s) unconstrained (rank-deficient Jacobian): σ unreliable");
  else if (values.minCoeff() < 1e-9 * largest)
    warnings->push_back("nearly singular problem (column-scaled condition number " +
                        std::to_string(std::sqrt(largest / values.minCoeff())) + "): σ unreliable");
  const Eigen::MatrixXd inverse = eigen.eigenvectors() * inverse_values.asDiagonal() * eigen.eigenvectors().transpose();
  return scale.asDiagonal() * inverse * scale.asDiagonal();
}

Pose poseFromOpenCV(const cv::Vec3d& rvec, const cv::Vec3d& tvec) {
  Pose pose;
  pose << rvec[0], rvec[1], rvec[2], tvec[0], tvec[1], tvec[2];
  return pose;
}

std::vector<double> initialIntrinsics(const std::vector<Eigen::Vector3d>& target_points,
                                      const std::vector<CalibrationView>& views, const std::vector<bool>& usable,
                                      int width, int height, int distortion_count, const CalibrationOptions& options) {
  std::vector<double> params(static_cast<std::size_t>(kIntrinsicCount + distortion_count), 0.0);
  if (options.initial_params) {
    if (options.initial_params->size() != params.size())
      throw std::invalid_argument("initial_params has " + std::to_string(options.initial_params->size()) +
                                  " values, the model needs " + std::to_string(params.size()));
    return *options.initial_params;
  }
  std::vector<std::vector<cv::Point3f>> object_points;
  std::vector<std::vector<cv::Point2f>> image_points;
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (!usable[v]) continue;
    std::vector<cv::Point3f> object;
    std::vector<cv::Point2f> image;
    for (std::size_t k = 0; k < views[v].ids.size(); ++k) {
      const Eigen::Vector3d& p = target_points[views[v].ids[k]];
      object.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.0f);
      image.emplace_back(static_cast<float>(views[v].pixels[k].x()), static_cast<float>(views[v].pixels[k].y()));
    }
    object_points.push_back(std::move(object));
    image_points.push_back(std::move(image));
  }
  // Aspect ratio 0: fx and fy estimated separately (OpenCV's closed form from homographies).
  const cv::Mat matrix = cv::initCameraMatrix2D(object_points, image_points, cv::Size(width, height), 0.0);
  params[0] = matrix.at<double>(0, 0);
  params[1] = matrix.at<double>(1, 1);
  params[2] = matrix.at<double>(0, 2);
  params[3] = matrix.at<double>(1, 2);
  if (!(params[0] > 0.0) || !(params[1] > 0.0) || !std::isfinite(params[0]) || !std::isfinite(params[1])) {
    params[0] = params[1] = std::max(width, height);
  }
  // A square-pixel start is closer to every real camera than two independent guesses.
  const double mean_focal = 0.5 * (params[0] + params[1]);
  params[0] = params[1] = mean_focal;
  return params;
}

// cTm of one view by cv::solvePnP on the normalised rays of `camera` (unproject), identity K.
std::optional<Pose> initialPose(const Camera& camera, const std::vector<Eigen::Vector3d>& target_points,
                                const CalibrationView& view, bool non_planar) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> rays;
  for (std::size_t k = 0; k < view.ids.size(); ++k) {
    Eigen::Vector2d ray;
    if (!camera.unproject(view.pixels[k], &ray)) continue;
    const Eigen::Vector3d& p = target_points[view.ids[k]];
    object.emplace_back(p.x(), p.y(), p.z());
    rays.emplace_back(ray.x(), ray.y());
  }
  if (object.size() < 4) return std::nullopt;
  cv::Vec3d rvec, tvec;
  bool solved = false;
  try {
    solved = cv::solvePnP(object, rays, cv::Matx33d::eye(), cv::noArray(), rvec, tvec, false,
                          non_planar ? cv::SOLVEPNP_ITERATIVE : cv::SOLVEPNP_IPPE);
  } catch (const cv::Exception&) {
    solved = false;
  }
  if (!solved || !std::isfinite(tvec[2]) || tvec[2] <= 0.0) return std::nullopt;
  return poseFromOpenCV(rvec, tvec);
}

// Non-finite values are never returned (so never written): they mean a gauge or convergence
// problem of the adjustment, reported as such.
void requireFinite(const CalibrationResult& result) {
  bool finite =
      result.camera.covariance.allFinite() && result.state_covariance.allFinite() && std::isfinite(result.sigma_px);
  for (const double value : result.camera.params) finite = finite && std::isfinite(value);
  for (const auto& point : result.target_points) finite = finite && point.allFinite();
  if (!finite)
    throw std::runtime_error(
        std::string("the calibration produced non-finite values (") +
        (result.target_refined ? "target refinement: a gauge or convergence problem" : "a convergence problem") +
        "); nothing written");
}

// Systematic error shows as residuals correlated within a view (a detector bias that depends
// on the view's geometry, an imperfect board): then σ² (JᵀJ)⁻¹ is too small. The view-cluster
// sandwich (Liang & Zeger's cluster-robust covariance, views as clusters, G/(G−1) small-sample
// factor) A⁻¹ (Σ_v J_vᵀ r_v r_vᵀ J_v) A⁻¹, A = JᵀJ, estimates the spread whatever the
// correlation inside a view. Returns, per tangent column, the factor by which the classical σ
// is inflated: σ_sandwich / σ_classic when the evidence is significant, 1 otherwise (never
// deflated). Test: with white residuals the variance ratio behaves as χ²(G−1)/(G−1) (G views);
// it must exceed that law's 99th percentile (Wilson–Hilferty), so a correct model is inflated
// in ≈ 1 % of the parameters only.
Eigen::VectorXd viewClusterInflation(const Linearisation& linear, const Eigen::MatrixXd& normal_inverse, double sigma2) {
  const Eigen::Index n = linear.jacobian.cols();
  const int groups = static_cast<int>(linear.active_views.size());
  Eigen::MatrixXd scores = Eigen::MatrixXd::Zero(n, groups);
  for (Eigen::Index row = 0; row < linear.jacobian.rows(); ++row)
    scores.col(linear.row_view[static_cast<std::size_t>(row)]) +=
        linear.jacobian.row(row).transpose() * linear.residuals(row);
  const Eigen::MatrixXd spread = normal_inverse * scores;  // A⁻¹ g_v per view
  const double small_sample = groups > 1 ? static_cast<double>(groups) / (groups - 1) : 1.0;
  const int dof = std::max(1, groups - 1);
  const double threshold = support::chi2Quantile(dof, 0.01) / dof;  // χ²₀.₉₉(dof) / dof
  Eigen::VectorXd inflation = Eigen::VectorXd::Ones(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double classic = sigma2 * normal_inverse(j, j);
    const double sandwich = small_sample * spread.row(j).squaredNorm();
    if (classic > 0.0 && std::isfinite(sandwich) && sandwich > threshold * classic)
      inflation(j) = std::sqrt(sandwich / classic);
  }
  return inflation;
}

// Coverage and geometry checks: what the views do not constrain.
void addGeometryWarnings(const std::vector<CalibrationView>& views, const State& state, int width, int height,
                         CalibrationResult* result) {
  // Image corners: a 4×4 grid, the four corner cells must hold points, or the distortion
  // there is an extrapolation.
  bool corner_seen[4] = {false, false, false, false};
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (!state.view_active[v]) continue;
    for (std::size_t k = 0; k < views[v].ids.size(); ++k) {
      if (!state.inlier[v][k]) continue;
      const Eigen::Vector2d& p = views[v].pixels[k];
      const bool left = p.x()<width / 4.0, right = p.x()> 3.0 * width / 4.0;
      const bool top = p.y()<height / 4.0, bottom = p.y()> 3.0 * height / 4.0;
      if (left && top) corner_seen[0] = true;
      if (right && top) corner_seen[1] = true;
      if (left && bottom) corner_seen[2] = true;
      if (right && bottom) corner_seen[3] = true;
    }
  }
  const char* const corner_names[4] = {"top-left", "top-right", "bottom-left", "bottom-right"};
  std::string missing;
  for (int i = 0; i < 4; ++i)
    if (!corner_seen[i]) missing += std::string(missing.empty() ? "" : ", ") + corner_names[i];
  if (!missing.empty())
    result->warnings.push_back("no target points in the image corner(s) " + missing +
                               " (outer quarter): distortion there is extrapolated");
  double max_tilt = 0.0;
  for (const auto& view : result->views)
    if (view.used) max_tilt = std::max(max_tilt, view.tilt_deg);
  if (max_tilt < 15.0)
    result->warnings.push_back("every view is nearly fronto-parallel (largest tilt " + std::to_string(max_tilt) +
                               "°): focal length and principal point are poorly separated from distance; "
                               "tilt the target by 30–45° in some views");
}

// Input checks that need no view: the image size, the point count and, without a guess, a
// planar target (the initialisation's homographies need z = 0).
void checkCalibrationInputs(const std::vector<Eigen::Vector3d>& target_points, int width, int height,
                            const CalibrationOptions& options) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("image size must be positive");
  if (target_points.size() < 4) throw std::invalid_argument("the target needs at least 4 points");
  double extent = 0.0;
  for (const auto& p : target_points) extent = std::max(extent, (p - target_points.front()).norm());
  if (!options.initial_params)
    for (const auto& p : target_points)
      if (std::abs(p.z()) > 1e-9 * std::max(extent, 1e-12))
        throw std::invalid_argument("the initialisation needs a planar target (z = 0); give initial_params otherwise");
}

// Indices into the model's parameters of options.fixed_parameters, sorted, without repeats.
std::vector<int> fixedParameterIndices(const CalibrationOptions& options, int parameter_count) {
  Camera names_camera;
  names_camera.lens = lensOf(options.model);
  names_camera.params.assign(static_cast<std::size_t>(parameter_count), 0.0);
  const std::vector<std::string> names = names_camera.parameterNames();
  std::vector<int> indices;
  for (const auto& name : options.fixed_parameters) {
    const auto found = std::find(names.begin(), names.end(), name);
    if (found == names.end())
      throw std::invalid_argument("cannot fix '" + name + "': model " + distortionModelName(options.model) +
                                  " has no such parameter");
    indices.push_back(static_cast<int>(found - names.begin()));
  }
  std::sort(indices.begin(), indices.end());
  indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
  // Nothing left to estimate: the "calibration" would be the initial guess (as identify refuses).
  if (static_cast<int>(indices.size()) >= parameter_count)
    throw std::invalid_argument("every parameter of model " + distortionModelName(options.model) +
                                " is fixed (--fix): no free parameter to calibrate");
  return indices;
}

int activeViewCount(const State& state) {
  return static_cast<int>(std::count(state.view_active.begin(), state.view_active.end(), true));
}

// Validates every view (ids in range, one pixel per id), copies it into its result, and
// activates the views with enough points; the others get their rejection reason.
State screenViews(const std::vector<Eigen::Vector3d>& target_points, const std::vector<CalibrationView>& views,
                  const CalibrationOptions& options, CalibrationResult* result) {
  State state;
  state.lens = lensOf(options.model);
  state.points = target_points;
  state.view_active.assign(views.size(), false);
  state.inlier.resize(views.size());
  state.poses.assign(views.size(), Pose::Zero());
  for (std::size_t v = 0; v < views.size(); ++v) {
    const auto& view = views[v];
    auto& out = result->views[v];
    out.name = view.name;
    out.ids = view.ids;
    out.pixels = view.pixels;
    out.inlier.assign(view.ids.size(), false);
    out.residuals.assign(view.ids.size(), Eigen::Vector2d::Zero());
    if (view.ids.size() != view.pixels.size())
      throw std::invalid_argument("view '" + view.name + "': ids and pixels differ in count");
    for (const int id : view.ids)
      if (id < 0 || id >= static_cast<int>(target_points.size()))
        throw std::invalid_argument("view '" + view.name + "': target point id " + std::to_string(id) + " out of range");
    state.inlier[v].assign(view.ids.size(), true);
    if (static_cast<int>(view.ids.size()) < std::max(options.min_points_per_view, 4)) {
      out.rejection_reason = "only " + std::to_string(view.ids.size()) + " points";
      continue;
    }
    state.view_active[v] = true;
  }
  return state;
}

// Initial intrinsics from the usable views; without a guess, a fixed principal point sits at
// the image centre (OpenCV's convention).
void initialiseIntrinsics(const std::vector<Eigen::Vector3d>& target_points, const std::vector<CalibrationView>& views,
                          int width, int height, const CalibrationOptions& options,
                          const std::vector<int>& fixed_indices, State* state) {
  const std::vector<bool> usable = state->view_active;
  if (std::count(usable.begin(), usable.end(), true) < 3)
    throw std::runtime_error("only " + std::to_string(std::count(usable.begin(), usable.end(), true)) +
                             " usable views: calibration needs at least 3");
  state->params =
      initialIntrinsics(target_points, views, usable, width, height, distortionCoefficientCount(options.model), options);
  if (!options.initial_params)
    for (const int index : fixed_indices) {
      if (index == 2) state->params[2] = 0.5 * (width - 1);
      if (index == 3) state->params[3] = 0.5 * (height - 1);
    }
}

// Initial poses: OpenCV's PnP (IPPE for planar targets) on the rays of the initial camera,
// so every lens model starts the same way. A view without a pose is deactivated.
void initialisePoses(const std::vector<Eigen::Vector3d>& target_points, const std::vector<CalibrationView>& views,
                     int width, int height, const CalibrationOptions& options, State* state, CalibrationResult* result) {
  Camera initial_camera;
  initial_camera.width = width;
  initial_camera.height = height;
  initial_camera.lens = state->lens;
  initial_camera.params = state->params;
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (!state->view_active[v]) continue;
    const std::optional<Pose> pose =
        initialPose(initial_camera, target_points, views[v], options.initial_params.has_value());
    if (!pose) {
      state->view_active[v] = false;
      result->views[v].rejection_reason = "initial pose (PnP) failed";
      continue;
    }
    state->poses[v] = *pose;
  }
  if (activeViewCount(*state) < 3)
    throw std::runtime_error("only " + std::to_string(activeViewCount(*state)) +
                             " views have an initial pose: need at least 3");
}

// Target refinement gauge (see calibrate.hpp): first point seen in 3 views; the farthest
// from it; the farthest from that line. Also marks the points seen often enough to refine.
void chooseTargetGauge(const std::vector<Eigen::Vector3d>& target_points, const std::vector<CalibrationView>& views,
                       const State& state, Setup* setup) {
  std::vector<int> observation_count(target_points.size(), 0);
  for (std::size_t v = 0; v < views.size(); ++v)
    if (state.view_active[v])
      for (const int id : views[v].ids) ++observation_count[id];
  setup->point_refinable.assign(target_points.size(), false);
  for (std::size_t i = 0; i < target_points.size(); ++i) setup->point_refinable[i] = observation_count[i] >= 3;
  if (!setup->refine_target) return;
  int first = -1;
  for (std::size_t i = 0; i < target_points.size() && first < 0; ++i)
    if (observation_count[i] >= 3) first = static_cast<int>(i);
  if (first < 0) throw std::runtime_error("target refinement: no point is seen in 3 views");
  int far = first;
  for (std::size_t i = 0; i < target_points.size(); ++i)
    if (observation_count[i] >= 3 &&
        (target_points[i] - target_points[first]).norm() > (target_points[far] - target_points[first]).norm())
      far = static_cast<int>(i);
  const Eigen::Vector3d axis = (target_points[far] - target_points[first]).normalized();
  int side = first;
  double best = 0.0;
  for (std::size_t i = 0; i < target_points.size(); ++i) {
    if (observation_count[i] < 3) continue;
    const Eigen::Vector3d d = target_points[i] - target_points[first];
    const double distance = (d - d.dot(axis) * axis).norm();
    if (distance > best) {
      best = distance;
      side = static_cast<int>(i);
    }
  }
  if (far == first || side == first) throw std::runtime_error("target refinement: the seen points are collinear");
  setup->gauge = {{first, far, side}};
}

// Pass 2 (robust loss) and rejection: observations beyond the threshold are outliers, views
// left with too few inliers are dropped; then the final ordinary least-squares pass on the
// inliers (always run, so the estimate is the least-squares one whose covariance follows).
void robustPassAndRejection(const Setup& setup, const CalibrationOptions& options, State* state,
                            CalibrationResult* result) {
  const auto& views = *setup.views;
  const double sigma = std::max(robustSigma(views, *state), options.min_sigma_px);
  result->robust_scale_px = options.robust_scale_sigmas * sigma;
  solvePass(setup, state, options.robust_loss, result->robust_scale_px);
  const double sigma_after = std::max(robustSigma(views, *state), options.min_sigma_px);
  const double threshold = options.outlier_threshold_sigmas * sigma_after;
  const auto residuals = residualsOf(views, *state);
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (!state->view_active[v]) continue;
    int kept = 0;
    for (std::size_t k = 0; k < views[v].ids.size(); ++k) {
      const bool inlier = residuals[v][k].allFinite() && residuals[v][k].norm() <= threshold;
      state->inlier[v][k] = inlier;
      kept += inlier ? 1 : 0;
    }
    const int total = static_cast<int>(views[v].ids.size());
    if (kept < options.min_points_per_view || kept < options.min_inlier_fraction * total) {
      state->view_active[v] = false;
      result->views[v].rejection_reason = "only " + std::to_string(kept) + " of " + std::to_string(total) +
                                          " points within " + std::to_string(threshold) + " px";
    }
  }
  if (activeViewCount(*state) < 3)
    throw std::runtime_error("only " + std::to_string(activeViewCount(*state)) +
                             " views survive outlier rejection: need at least 3");
  solvePass(setup, state, RobustLoss::None, 0.0);
}

// Sums over the inliers of the used views, for σ and the reports.
struct ResidualSummary {
  double ssr = 0.0;
  int inlier_count = 0;
  std::vector<double> distances;  // camera to target centre, per used view
};

// Fills each view's result (pose, tilt, residuals, inlier flags, rms) and counts the rejections.
ResidualSummary collectViewResults(const std::vector<Eigen::Vector3d>& target_points,
                                   const std::vector<CalibrationView>& views, const State& state,
                                   CalibrationResult* result) {
  const auto residuals = residualsOf(views, state);
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (const auto& p : target_points) centre += p;
  centre /= static_cast<double>(target_points.size());
  ResidualSummary summary;
  for (std::size_t v = 0; v < views.size(); ++v) {
    auto& out = result->views[v];
    out.used = state.view_active[v];
    if (!out.used) {
      ++result->rejected_views;
      continue;
    }
    out.rotation = state.poses[v].head<3>();
    out.translation = state.poses[v].tail<3>();
    Eigen::Vector3d normal;
    const Eigen::Vector3d z_axis(0.0, 0.0, 1.0);
    ceres::AngleAxisRotatePoint(out.rotation.data(), z_axis.data(), normal.data());
    out.tilt_deg = std::acos(std::min(1.0, std::abs(normal.z()))) * 180.0 / support::kPi;
    double view_ssr = 0.0;
    int view_count = 0;
    for (std::size_t k = 0; k < views[v].ids.size(); ++k) {
      out.residuals[k] = residuals[v][k];
      out.inlier[k] = state.inlier[v][k];
      if (!out.inlier[k]) {
        ++result->rejected_points;
        continue;
      }
      view_ssr += residuals[v][k].squaredNorm();
      ++view_count;
    }
    out.rms_px = std::sqrt(view_ssr / std::max(1, view_count));
    summary.ssr += view_ssr;
    summary.inlier_count += view_count;
    Eigen::Vector3d camera_centre;
    ceres::AngleAxisRotatePoint(out.rotation.data(), centre.data(), camera_centre.data());
    summary.distances.push_back((camera_centre + out.translation).norm());
  }
  return summary;
}

// Tangent → ambient: column c of the tangent intrinsics is ambient index free_intrinsics[c],
// then 6 per active view; fixed parameters get zero rows/columns.
Eigen::MatrixXd ambientStateCovariance(const Linearisation& linear, const Eigen::MatrixXd& tangent_covariance,
                                       int parameter_count) {
  const int view_count = static_cast<int>(linear.active_views.size());
  const int state_size = parameter_count + 6 * view_count;
  std::vector<int> ambient_of_tangent;
  for (const int index : linear.free_intrinsics) ambient_of_tangent.push_back(index);
  for (int i = 0; i < 6 * view_count; ++i) ambient_of_tangent.push_back(parameter_count + i);
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(state_size, state_size);
  const int tangent_state = static_cast<int>(ambient_of_tangent.size());
  for (int r = 0; r < tangent_state; ++r)
    for (int c = 0; c < tangent_state; ++c)
      covariance(ambient_of_tangent[r], ambient_of_tangent[c]) = tangent_covariance(r, c);
  return covariance;
}

// Covariance (see calibrate.hpp): Σ = σ² (JᵀJ)⁻¹, σ² = SSR / (2N − n_free), each σ inflated
// by the view-cluster factor when asked.
void estimateCovariance(const Setup& setup, const ResidualSummary& summary, int parameter_count,
                        const CalibrationOptions& options, State* state, CalibrationResult* result) {
  const Linearisation linear = linearise(setup, state);
  result->free_parameter_count = static_cast<int>(linear.jacobian.cols());
  const int dof = 2 * summary.inlier_count - result->free_parameter_count;
  if (dof <= 0)
    throw std::runtime_error("more unknowns (" + std::to_string(result->free_parameter_count) +
                             ") than measurements (" + std::to_string(2 * summary.inlier_count) + ")");
  result->sigma_px = std::sqrt(summary.ssr / dof);
  const Eigen::MatrixXd normal_inverse = inverseNormalMatrix(linear.jacobian, &result->warnings);
  const double sigma2 = result->sigma_px * result->sigma_px;
  Eigen::MatrixXd tangent_covariance = sigma2 * normal_inverse;
  result->covariance_pixel_noise = Eigen::MatrixXd::Zero(parameter_count, parameter_count);
  for (std::size_t r = 0; r < linear.free_intrinsics.size(); ++r)
    for (std::size_t c = 0; c < linear.free_intrinsics.size(); ++c)
      result->covariance_pixel_noise(linear.free_intrinsics[r], linear.free_intrinsics[c]) =
          tangent_covariance(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c));
  result->sigma_inflation.assign(static_cast<std::size_t>(parameter_count), 1.0);
  if (options.view_cluster_covariance && linear.active_views.size() >= 2) {
    const Eigen::VectorXd inflation = viewClusterInflation(linear, normal_inverse, sigma2);
    tangent_covariance = inflation.asDiagonal() * tangent_covariance * inflation.asDiagonal();
    for (std::size_t c = 0; c < linear.free_intrinsics.size(); ++c)
      result->sigma_inflation[static_cast<std::size_t>(linear.free_intrinsics[c])] =
          inflation(static_cast<Eigen::Index>(c));
  }
  result->state_covariance = ambientStateCovariance(linear, tangent_covariance, parameter_count);
  result->state_view_index = linear.active_views;
}

// Shape of the refined target: its points' spread about their best-fit plane and their
// displacement from the nominal points.
void describeRefinedTarget(const std::vector<Eigen::Vector3d>& target_points, const State& state, const Setup& setup,
                           CalibrationResult* result) {
  std::vector<Eigen::Vector3d> refined;
  double displacement = 0.0;
  for (std::size_t i = 0; i < state.points.size(); ++i) {
    if (!setup.point_refinable[i]) continue;
    refined.push_back(state.points[i]);
    displacement += (state.points[i] - target_points[i]).squaredNorm();
  }
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const auto& p : refined) centroid += p;
  centroid /= static_cast<double>(refined.size());
  Eigen::MatrixXd centred(3, refined.size());
  for (std::size_t i = 0; i < refined.size(); ++i) centred.col(static_cast<Eigen::Index>(i)) = refined[i] - centroid;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred, Eigen::ComputeThinU);
  const Eigen::Vector3d normal = svd.matrixU().col(2);
  double sum = 0.0, worst = 0.0;
  for (const auto& p : refined) {
    const double off = normal.dot(p - centroid);
    sum += off * off;
    worst = std::max(worst, std::abs(off));
  }
  result->target_out_of_plane_rms_m = std::sqrt(sum / refined.size());
  result->target_out_of_plane_max_m = worst;
  result->target_displacement_rms_m = std::sqrt(displacement / refined.size());
}

}  // namespace

// The solve in stages: check and screen the input, initialise (closed-form intrinsics, PnP
// poses, target gauge), adjust (least squares, then robust pass and rejection), then the
// per-view results, the covariance and the refined target's shape.
CalibrationResult calibrateCamera(const std::vector<Eigen::Vector3d>& target_points,
                                  const std::vector<CalibrationView>& views, int width, int height,
                                  const CalibrationOptions& options) {
  checkCalibrationInputs(target_points, width, height, options);
  const int parameter_count = kIntrinsicCount + distortionCoefficientCount(options.model);
  Setup setup;
  setup.views = &views;
  setup.refine_target = options.refine_target;
  setup.num_threads = std::max(1, options.num_threads);
  setup.fixed_indices = fixedParameterIndices(options, parameter_count);

  CalibrationResult result;
  result.model = options.model;
  result.fixed_parameters = options.fixed_parameters;
  result.views.resize(views.size());
  State state = screenViews(target_points, views, options, &result);
  initialiseIntrinsics(target_points, views, width, height, options, setup.fixed_indices, &state);
  initialisePoses(target_points, views, width, height, options, &state, &result);
  chooseTargetGauge(target_points, views, state, &setup);

  solvePass(setup, &state, RobustLoss::None, 0.0);  // pass 1: plain least squares
  if (options.robust_loss != RobustLoss::None) robustPassAndRejection(setup, options, &state, &result);

  const ResidualSummary summary = collectViewResults(target_points, views, state, &result);
  result.used_views = activeViewCount(state);
  result.used_points = summary.inlier_count;
  estimateCovariance(setup, summary, parameter_count, options, &state, &result);

  result.camera.width = width;
  result.camera.height = height;
  result.camera.lens = state.lens;
  result.camera.params = state.params;
  result.camera.rms_px = std::sqrt(summary.ssr / std::max(1, summary.inlier_count));
  result.camera.covariance = result.state_covariance.topLeftCorner(parameter_count, parameter_count);

  result.target_points = state.points;
  result.target_refined = options.refine_target;
  result.gauge_points = setup.gauge;
  if (options.refine_target) describeRefinedTarget(target_points, state, setup, &result);

  result.uncertainty_distance_m =
      options.uncertainty_distance_m > 0.0 ? options.uncertainty_distance_m : support::upperMedian(summary.distances);
  requireFinite(result);
  addGeometryWarnings(views, state, width, height, &result);
  if (options.refine_target) {
    // The same views with the nominal target rigid: the yardstick of the refinement's warnings.
    CalibrationOptions rigid_options = options;
    rigid_options.refine_target = false;
    rigid_options.uncertainty_distance_m = result.uncertainty_distance_m;
    const CalibrationResult rigid = calibrateCamera(target_points, views, width, height, rigid_options);
    result.target_refinement = checkTargetRefinement(rigid, &result);
  }
  return result;
}

CalibrationResult calibrateCamera(const std::vector<std::vector<Eigen::Vector3d>>& object_points,
                                  const std::vector<std::vector<Eigen::Vector2d>>& image_points, int width, int height,
                                  const CalibrationOptions& options) {
  if (object_points.size() != image_points.size())
    throw std::invalid_argument("object_points and image_points differ in view count");
  // Identical object points are one target point: lexicographic map on exact coordinates.
  auto less = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  };
  std::map<Eigen::Vector3d, int, decltype(less)> index(less);
  std::vector<Eigen::Vector3d> target_points;
  std::vector<CalibrationView> views(object_points.size());
  for (std::size_t v = 0; v < object_points.size(); ++v) {
    if (object_points[v].size() != image_points[v].size())
      throw std::invalid_argument("view " + std::to_string(v) + ": object and image point counts differ");
    views[v].name = "view " + std::to_string(v);
    for (std::size_t k = 0; k < object_points[v].size(); ++k) {
      const auto inserted = index.emplace(object_points[v][k], static_cast<int>(target_points.size()));
      if (inserted.second) target_points.push_back(object_points[v][k]);
      views[v].ids.push_back(inserted.first->second);
      views[v].pixels.push_back(image_points[v][k]);
    }
  }
  return calibrateCamera(target_points, views, width, height, options);
}

}  // namespace mire::calibration
