// The model check after a calibration (model_check.hpp, doc/calibration.md "Model check").
#include "mire/calibration/model_check.hpp"

#include "mire/support/constants.hpp"

#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>

namespace mire::calibration {
namespace {

using Pose = Eigen::Matrix<double, 6, 1>;  // angle-axis, translation (cTm)

// Upper tail of the standard normal.
double normalUpperTail(double z) { return 0.5 * std::erfc(z / std::sqrt(2.0)); }

// Upper tail of χ²(k) by the Wilson–Hilferty cube-root normal approximation (support's
// chi2Quantile is its inverse).
double chi2UpperTail(int k, double x) {
  if (!(x > 0.0)) return 1.0;
  const double a = 2.0 / (9.0 * std::max(1, k));
  return normalUpperTail((std::cbrt(x / k) - (1.0 - a)) / std::sqrt(a));
}

// Upper tail of F(2, d): exact, (1 + 2f/d)^(−d/2).
double f2UpperTail(int d, double f) {
  if (!(f > 0.0)) return 1.0;
  return std::pow(1.0 + 2.0 * f / d, -0.5 * d);
}

// Upper tail of Student's t(d), by the normal approximation z = t (1 − 1/(4d)) / √(1 + t²/(2d)).
double tUpperTail(int d, double t) {
  const double dd = std::max(1, d);
  return normalUpperTail(t * (1.0 - 1.0 / (4.0 * dd)) / std::sqrt(1.0 + t * t / (2.0 * dd)));
}

std::string number(double value, int digits) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", digits, value);
  return buffer;
}

std::string pText(double p) {
  if (p < 1e-12) return "p < 1e-12";
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "p = %.2g", p);
  return buffer;
}

std::string joined(const std::vector<std::string>& items, const std::string& separator) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) out += (i ? separator : "") + items[i];
  return out;
}

// The used views' inlier observations: what the refits calibrate.
std::vector<CalibrationView> inlierViews(const CalibrationResult& result, const std::vector<int>& view_indices) {
  std::vector<CalibrationView> out;
  for (const int v : view_indices) {
    const CalibrationViewResult& view = result.views[static_cast<std::size_t>(v)];
    CalibrationView kept{view.name, {}, {}};
    for (std::size_t k = 0; k < view.ids.size(); ++k)
      if (view.inlier[k]) {
        kept.ids.push_back(view.ids[k]);
        kept.pixels.push_back(view.pixels[k]);
      }
    out.push_back(std::move(kept));
  }
  return out;
}

std::vector<int> usedViews(const CalibrationResult& result) {
  std::vector<int> used;
  for (std::size_t v = 0; v < result.views.size(); ++v)
    if (result.views[v].used) used.push_back(static_cast<int>(v));
  return used;
}

// The calibration again, from its solution, on its inliers (no robust pass, the target points
// as solved), with `model` and `extra_fixed` held at 0.
CalibrationResult refit(const CalibrationResult& result, const CalibrationOptions& options, DistortionModel model,
                        const std::vector<std::string>& extra_fixed, const std::vector<int>& view_indices) {
  CalibrationOptions refit_options = options;
  refit_options.model = model;
  refit_options.fixed_parameters.insert(refit_options.fixed_parameters.end(), extra_fixed.begin(), extra_fixed.end());
  std::vector<double> start = result.camera.params;
  start.resize(static_cast<std::size_t>(kIntrinsicCount + distortionCoefficientCount(model)), 0.0);
  refit_options.initial_params = start;
  refit_options.robust_loss = RobustLoss::None;
  refit_options.refine_target = false;
  return calibrateCamera(result.target_points, inlierViews(result, view_indices), result.camera.width,
                         result.camera.height, refit_options);
}

// The richer models that nest `model`: (model, terms held at 0, terms tested, what to try).
struct Candidate {
  DistortionModel model;
  std::vector<std::string> fixed;
  std::vector<std::string> terms;
  std::string suggestion;
};

std::vector<Candidate> candidatesFor(DistortionModel model) {
  const std::vector<std::string> prism{"s1", "s2", "s3", "s4"};
  switch (model) {
    case DistortionModel::Pinhole:
      return {{DistortionModel::OpenCV4, {}, {"k1", "k2", "p1", "p2"}, "--model opencv5"}};
    case DistortionModel::OpenCV4:
      return {{DistortionModel::OpenCV5, {}, {"k3"}, "--model opencv5"},
              {DistortionModel::OpenCV12, {"k3", "k4", "k5", "k6"}, prism, "--model opencv12 --fix k3,k4,k5,k6"}};
    case DistortionModel::OpenCV5:
      return {{DistortionModel::OpenCV8, {}, {"k4", "k5", "k6"}, "--model opencv8"},
              {DistortionModel::OpenCV12, {"k4", "k5", "k6"}, prism, "--model opencv12 --fix k4,k5,k6"}};
    case DistortionModel::OpenCV8:
      return {{DistortionModel::OpenCV12, {}, prism, "--model opencv12"}};
    case DistortionModel::OpenCV12:
    case DistortionModel::Fisheye:
      break;
  }
  return {};
}

int indexOf(const std::vector<std::string>& names, const std::string& name) {
  const auto found = std::find(names.begin(), names.end(), name);
  return found == names.end() ? -1 : static_cast<int>(found - names.begin());
}

NestedModelTest testCandidate(const CalibrationResult& result, const CalibrationOptions& options,
                              const Candidate& candidate, const std::vector<int>& used) {
  NestedModelTest test;
  test.model = distortionModelName(candidate.model);
  test.fixed = candidate.fixed;
  test.suggestion = candidate.suggestion;
  const CalibrationResult richer = refit(result, options, candidate.model, candidate.fixed, used);
  const std::vector<std::string> names = richer.camera.parameterNames();
  const std::vector<double> sigma = richer.camera.sigmas();
  std::vector<int> indices;
  for (const auto& term : candidate.terms) {
    const int index = indexOf(names, term);
    if (index < 0 || indexOf(options.fixed_parameters, term) >= 0) continue;
    indices.push_back(index);
    test.terms.push_back(term);
    test.values.push_back(richer.camera.params[static_cast<std::size_t>(index)]);
    test.sigmas.push_back(sigma[static_cast<std::size_t>(index)]);
  }
  test.dof = static_cast<int>(indices.size());
  for (const int index : indices)
    test.design_effect =
        std::max(test.design_effect, std::pow(richer.sigma_inflation[static_cast<std::size_t>(index)], 2));
  // Both fits on the same inliers: SSR = rms² N.
  const double ssr = result.camera.rms_px * result.camera.rms_px * result.used_points;
  const double ssr_richer = richer.camera.rms_px * richer.camera.rms_px * richer.used_points;
  test.statistic = std::max(0.0, ssr - ssr_richer) / (richer.sigma_px * richer.sigma_px * test.design_effect);
  test.p_value = test.dof > 0 ? chi2UpperTail(test.dof, test.statistic) : 1.0;
  test.rms_px = richer.camera.rms_px;
  for (int i = 0; i < kIntrinsicCount; ++i) {
    test.intrinsics.push_back(richer.camera.params[static_cast<std::size_t>(i)]);
    const double shift =
        richer.camera.params[static_cast<std::size_t>(i)] - result.camera.params[static_cast<std::size_t>(i)];
    test.intrinsic_shift_sigma.push_back(
        sigma[static_cast<std::size_t>(i)] > 0.0 ? shift / sigma[static_cast<std::size_t>(i)] : 0.0);
  }
  return test;
}

// Pose-only reprojection residual of one point, intrinsics held.
struct PoseResidual {
  PoseResidual(const Camera& camera, const Eigen::Vector3d& point, const Eigen::Vector2d& observed)
      : camera_(&camera), point_(point), observed_(observed) {}
  template <typename T>
  bool operator()(const T* pose, T* residual) const {
    const T point[3] = {T(point_.x()), T(point_.y()), T(point_.z())};
    T camera_point[3];
    ceres::AngleAxisRotatePoint(pose, point, camera_point);
    for (int i = 0; i < 3; ++i) camera_point[i] += pose[3 + i];
    T params[kIntrinsicCount + 12];
    for (std::size_t i = 0; i < camera_->params.size(); ++i) params[i] = T(camera_->params[i]);
    T pixel[2];
    if (!projectPoint(params, camera_->lens, camera_->distortionCount(), camera_point, pixel)) return false;
    residual[0] = pixel[0] - observed_.x();
    residual[1] = pixel[1] - observed_.y();
    return true;
  }
  const Camera* camera_;
  Eigen::Vector3d point_;
  Eigen::Vector2d observed_;
};

Eigen::Vector2d projectAt(const std::vector<double>& params, const Camera& camera, const Pose& pose,
                          const Eigen::Vector3d& point) {
  Eigen::Vector3d camera_point;
  ceres::AngleAxisRotatePoint(pose.data(), point.data(), camera_point.data());
  camera_point += pose.tail<3>();
  Eigen::Vector2d pixel(std::numeric_limits<double>::quiet_NaN(), 0.0);
  projectPoint(params.data(), camera.lens, camera.distortionCount(), camera_point.data(), pixel.data());
  return pixel;
}

// One held-out view: its pose fitted with `camera` held, its SSR, and the SSR expected from
// pixel noise σ² and the camera's covariance.
struct HeldOutView {
  double ssr = 0.0;
  double expected_noise = 0.0;
  double expected_calibration = 0.0;
  int points = 0;
};

HeldOutView evaluateHeldOut(const Camera& camera, double sigma_px, const std::vector<Eigen::Vector3d>& target_points,
                            const CalibrationView& view, Pose pose) {
  ceres::Problem problem;
  for (std::size_t k = 0; k < view.ids.size(); ++k)
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PoseResidual, 2, 6>(new PoseResidual(
                                 camera, target_points[static_cast<std::size_t>(view.ids[k])], view.pixels[k])),
                             nullptr, pose.data());
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.max_num_iterations = 100;
  solver.function_tolerance = solver.gradient_tolerance = solver.parameter_tolerance = 1e-12;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  const int n = static_cast<int>(view.ids.size());
  const int p = static_cast<int>(camera.params.size());
  Eigen::MatrixXd j_camera(2 * n, p), j_pose(2 * n, 6);
  HeldOutView out;
  out.points = n;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d& point = target_points[static_cast<std::size_t>(view.ids[static_cast<std::size_t>(k)])];
    const Eigen::Vector2d pixel = projectAt(camera.params, camera, pose, point);
    out.ssr += (pixel - view.pixels[static_cast<std::size_t>(k)]).squaredNorm();
    for (int i = 0; i < p; ++i) {
      std::vector<double> plus = camera.params, minus = camera.params;
      const double h = 1e-6 * std::max(1.0, std::abs(camera.params[static_cast<std::size_t>(i)]));
      plus[static_cast<std::size_t>(i)] += h;
      minus[static_cast<std::size_t>(i)] -= h;
      j_camera.block(2 * k, i, 2, 1) =
          (projectAt(plus, camera, pose, point) - projectAt(minus, camera, pose, point)) / (2.0 * h);
    }
    for (int i = 0; i < 6; ++i) {
      Pose plus = pose, minus = pose;
      plus(i) += 1e-7;
      minus(i) -= 1e-7;
      j_pose.block(2 * k, i, 2, 1) =
          (projectAt(camera.params, camera, plus, point) - projectAt(camera.params, camera, minus, point)) / 2e-7;
    }
  }
  // Q J_θ: what of an intrinsics error the view's own pose cannot absorb.
  const Eigen::MatrixXd absorbed = j_pose * (j_pose.transpose() * j_pose).ldlt().solve(j_pose.transpose() * j_camera);
  const Eigen::MatrixXd residual_map = j_camera - absorbed;
  out.expected_calibration = (residual_map * camera.covariance).cwiseProduct(residual_map).sum();
  out.expected_noise = sigma_px * sigma_px * (2.0 * n - 6.0);
  return out;
}

HoldoutCheck holdoutCheck(const CalibrationResult& result, const CalibrationOptions& options, int folds_wanted,
                          double level) {
  const std::vector<int> used = usedViews(result);
  const int folds = std::min(folds_wanted, static_cast<int>(used.size()));
  if (folds < 2) throw std::invalid_argument("the held-out check needs at least 2 folds");
  if (static_cast<int>(used.size()) - (static_cast<int>(used.size()) + folds - 1) / folds < 3)
    throw std::invalid_argument("the held-out check with " + std::to_string(folds) + " folds leaves fewer than 3 of " +
                                std::to_string(used.size()) + " views to calibrate each fold");
  HoldoutCheck check;
  check.folds = folds;
  check.names = result.camera.parameterNames();
  std::vector<std::vector<double>> fold_params;
  std::vector<double> ratios;
  double ssr = 0.0, expected = 0.0, noise = 0.0, calibration_part = 0.0;
  int points = 0;
  for (int fold = 0; fold < folds; ++fold) {
    std::vector<int> training, held;
    for (std::size_t j = 0; j < used.size(); ++j)
      (static_cast<int>(j) % folds == fold ? held : training).push_back(used[j]);
    const CalibrationResult trained = refit(result, options, result.model, {}, training);
    fold_params.push_back(trained.camera.params);
    const std::vector<CalibrationView> held_views = inlierViews(result, held);
    for (std::size_t h = 0; h < held.size(); ++h) {
      const CalibrationViewResult& view = result.views[static_cast<std::size_t>(held[h])];
      Pose start;
      start << view.rotation, view.translation;
      const HeldOutView out =
          evaluateHeldOut(trained.camera, trained.sigma_px, result.target_points, held_views[h], start);
      const double e = out.expected_noise + out.expected_calibration;
      ssr += out.ssr;
      expected += e;
      noise += out.expected_noise;
      calibration_part += out.expected_calibration;
      points += out.points;
      ratios.push_back(out.ssr / e);
    }
  }
  check.views = static_cast<int>(ratios.size());
  check.measured_rms_px = std::sqrt(ssr / points);
  check.predicted_rms_px = std::sqrt(expected / points);
  check.noise_only_rms_px = std::sqrt(noise / points);
  check.ratio = check.measured_rms_px / check.predicted_rms_px;
  check.calibration_sigma_scale = ssr > noise && calibration_part > 0.0 ? std::sqrt((ssr - noise) / calibration_part)
                                                                        : std::numeric_limits<double>::quiet_NaN();
  const double mean = std::accumulate(ratios.begin(), ratios.end(), 0.0) / ratios.size();
  double spread = 0.0;
  for (const double r : ratios) spread += (r - mean) * (r - mean);
  const double standard_error = std::sqrt(spread / std::max<std::size_t>(1, ratios.size() - 1) / ratios.size());
  check.t_statistic = standard_error > 0.0 ? (mean - 1.0) / standard_error : 0.0;
  check.p_value = tUpperTail(static_cast<int>(ratios.size()) - 1, check.t_statistic);
  check.significant = check.p_value < level;
  // Delete-a-fold jackknife: (K − 1)/K Σ (θ_k − θ̄)².
  const std::vector<double> printed = result.camera.sigmas();
  for (std::size_t i = 0; i < result.camera.params.size(); ++i) {
    double average = 0.0;
    for (const auto& params : fold_params) average += params[i] / folds;
    double sum = 0.0;
    for (const auto& params : fold_params) sum += (params[i] - average) * (params[i] - average);
    const double jackknife = std::sqrt((folds - 1.0) / folds * sum);
    check.jackknife_sigma.push_back(jackknife);
    check.jackknife_ratio.push_back(i < printed.size() && printed[i] > 0.0 ? jackknife / printed[i]
                                                                           : std::numeric_limits<double>::quiet_NaN());
  }
  return check;
}

// Reasons and suggestions from the three tests.
void concludeVerdict(const CalibrationResult& result, ModelCheck* check) {
  const ResidualStructure& structure = check->structure;
  std::vector<const NestedModelTest*> significant;
  for (const auto& test : check->nested)
    if (test.significant) significant.push_back(&test);
  std::sort(significant.begin(), significant.end(),
            [](const NestedModelTest* a, const NestedModelTest* b) { return a->p_value < b->p_value; });
  for (const NestedModelTest* test : significant) {
    std::string shifts;
    const char* names[4] = {"fx", "fy", "cx", "cy"};
    for (int i = 0; i < kIntrinsicCount; ++i)
      if (std::abs(test->intrinsic_shift_sigma[static_cast<std::size_t>(i)]) > 3.0)
        shifts +=
            std::string(shifts.empty() ? "; with them " : ", ") + names[i] + " moves " +
            number(test->intrinsics[static_cast<std::size_t>(i)] - result.camera.params[static_cast<std::size_t>(i)], 2) +
            " px";
    check->reasons.push_back(joined(test->terms, " ") + " significant (likelihood ratio chi2(" +
                             std::to_string(test->dof) + ") = " + number(test->statistic, 1) + ", " +
                             pText(test->p_value) + shifts + ")");
    if (std::find(check->suggestions.begin(), check->suggestions.end(), test->suggestion) == check->suggestions.end())
      check->suggestions.push_back(test->suggestion);
  }
  if (structure.significant) {
    check->reasons.push_back("residuals structured in " + std::to_string(structure.significant_bins) + " of " +
                             std::to_string(structure.tested_bins) + " image bins (" + pText(structure.corrected_p_value) +
                             " after Bonferroni; bin means " + number(structure.structured_rms_px, 3) + " px RMS)");
    if (significant.empty()) {
      bool outer_only = true;
      for (std::size_t b = 0; b < structure.bins.size(); ++b)
        if (structure.bins[b].significant && static_cast<int>(b) / structure.sectors != structure.rings - 1)
          outer_only = false;
      check->suggestions.push_back("more views at the edges");
      // Already refined: suggesting it again would send the user in a circle.
      if (!outer_only && !result.target_refined)
        check->suggestions.push_back("--refine-target (a board that is not flat)");
    }
  }
  if (check->holdout && check->holdout->significant) {
    check->reasons.push_back("held-out views " + number(check->holdout->ratio, 2) + "x the predicted error (t = " +
                             number(check->holdout->t_statistic, 1) + ", " + pText(check->holdout->p_value) + ")");
    if (significant.empty() && !structure.significant) {
      check->suggestions.push_back("more views");
      if (!result.target_refined) check->suggestions.push_back("--refine-target (a board that is not flat)");
    }
  }
  check->adequate = check->reasons.empty();
}

}  // namespace

std::string ModelCheck::verdictLine() const {
  if (adequate) return "model check: adequate";
  return "model check: insufficient (" + joined(reasons, "; ") +
         (suggestions.empty() ? std::string() : "; try " + joined(suggestions, ", ")) + ")";
}

ResidualStructure residualStructure(const CalibrationResult& result, const ModelCheckOptions& options) {
  struct Observation {
    double radius, angle;
    Eigen::Vector2d residual;
    int view;
  };
  const Eigen::Vector2d centre(result.camera.cx(), result.camera.cy());
  std::vector<Observation> observations;
  for (std::size_t v = 0; v < result.views.size(); ++v) {
    const auto& view = result.views[v];
    if (!view.used) continue;
    for (std::size_t k = 0; k < view.ids.size(); ++k) {
      if (!view.inlier[k]) continue;
      const Eigen::Vector2d d = view.pixels[k] - centre;
      observations.push_back({d.norm(), std::atan2(d.y(), d.x()), view.residuals[k], static_cast<int>(v)});
    }
  }
  ResidualStructure out;
  out.rings = std::max(1, options.rings);
  out.sectors = std::max(1, options.sectors);
  if (observations.empty()) return out;
  std::vector<double> radii;
  for (const auto& o : observations) radii.push_back(o.radius);
  std::sort(radii.begin(), radii.end());
  out.ring_edges_px.push_back(0.0);
  for (int r = 1; r < out.rings; ++r)
    out.ring_edges_px.push_back(radii[static_cast<std::size_t>(r) * radii.size() / static_cast<std::size_t>(out.rings)]);
  out.ring_edges_px.push_back(radii.back());
  const double sector_width = 2.0 * support::kPi / out.sectors;
  out.bins.resize(static_cast<std::size_t>(out.rings * out.sectors));
  std::vector<std::vector<int>> members(out.bins.size());
  for (std::size_t i = 0; i < observations.size(); ++i) {
    const auto& o = observations[i];
    int ring = static_cast<int>(std::upper_bound(out.ring_edges_px.begin() + 1, out.ring_edges_px.end() - 1, o.radius) -
                                (out.ring_edges_px.begin() + 1));
    ring = std::min(ring, out.rings - 1);
    const int sector = std::min(out.sectors - 1, static_cast<int>((o.angle + support::kPi) / sector_width));
    members[static_cast<std::size_t>(ring * out.sectors + sector)].push_back(static_cast<int>(i));
  }
  double structured = 0.0;
  for (std::size_t b = 0; b < out.bins.size(); ++b) {
    ResidualBin& bin = out.bins[b];
    const int ring = static_cast<int>(b) / out.sectors, sector = static_cast<int>(b) % out.sectors;
    bin.radius_min_px = out.ring_edges_px[static_cast<std::size_t>(ring)];
    bin.radius_max_px = out.ring_edges_px[static_cast<std::size_t>(ring + 1)];
    bin.angle_min_rad = -support::kPi + sector * sector_width;
    bin.angle_max_rad = bin.angle_min_rad + sector_width;
    std::map<int, std::pair<Eigen::Vector2d, int>> per_view;
    for (const int i : members[b]) {
      auto& entry =
          per_view.try_emplace(observations[static_cast<std::size_t>(i)].view, Eigen::Vector2d::Zero(), 0).first->second;
      entry.first += observations[static_cast<std::size_t>(i)].residual;
      ++entry.second;
      bin.mean_px += observations[static_cast<std::size_t>(i)].residual;
    }
    bin.points = static_cast<int>(members[b].size());
    bin.views = static_cast<int>(per_view.size());
    if (bin.points == 0) continue;
    bin.mean_px /= bin.points;
    structured += bin.points * bin.mean_px.squaredNorm();
    if (bin.views < std::max(3, options.min_bin_views)) continue;
    // Views as clusters: the mean's covariance from the per-view sums' scatter.
    Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
    for (const auto& [view, entry] : per_view) {
      const Eigen::Vector2d d = entry.first - entry.second * bin.mean_px;
      scatter += d * d.transpose();
    }
    const int g = bin.views;
    const Eigen::Matrix2d covariance = scatter * (static_cast<double>(g) / (g - 1)) / (double(bin.points) * bin.points);
    if (!(covariance.determinant() > 0.0)) continue;
    bin.tested = true;
    bin.t2 = bin.mean_px.dot(covariance.ldlt().solve(bin.mean_px));
    const double f = (g - 2.0) / (2.0 * (g - 1.0)) * bin.t2;
    bin.p_value = f2UpperTail(g - 2, f);
    ++out.tested_bins;
    out.min_p_value = std::min(out.min_p_value, bin.p_value);
  }
  out.structured_rms_px = std::sqrt(structured / observations.size());
  out.corrected_p_value = std::min(1.0, out.min_p_value * std::max(1, out.tested_bins));
  for (auto& bin : out.bins) {
    bin.significant = bin.tested && bin.p_value * out.tested_bins < options.level;
    out.significant_bins += bin.significant ? 1 : 0;
  }
  out.significant = out.significant_bins > 0;
  return out;
}

ModelCheck checkCalibrationModel(const CalibrationResult& result, const CalibrationOptions& options,
                                 const ModelCheckOptions& check_options) {
  ModelCheck check;
  check.level = check_options.level;
  check.structure = residualStructure(result, check_options);
  const std::vector<int> used = usedViews(result);
  const std::vector<Candidate> candidates = candidatesFor(result.model);
  for (const auto& candidate : candidates) {
    NestedModelTest test = testCandidate(result, options, candidate, used);
    test.significant = test.dof > 0 && test.p_value * candidates.size() < check_options.level;
    check.nested.push_back(std::move(test));
  }
  if (check_options.holdout_folds > 0)
    check.holdout = holdoutCheck(result, options, check_options.holdout_folds, check_options.level);
  concludeVerdict(result, &check);
  return check;
}

}  // namespace mire::calibration
