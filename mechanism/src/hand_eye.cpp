// Joint least-squares hand-eye calibration with the robot's poses as nuisance parameters
// (doc/mechanisms.md, "Hand-eye calibration"); see hand_eye.hpp.
#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>

#include "hand_eye_cost.hpp"
#include "mire/mechanism/hand_eye.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {

namespace {

using detail::CameraCost;
using detail::cameraWhitening;
using detail::Matrix6;
using detail::RobotPrior;

// Second principal rotation of the robot's relative motions below this fraction of the first:
// rotations about one axis only (doc/mechanisms.md, "Hand-eye calibration").
constexpr double kOneAxisRatio = 1e-3;

void validate(const std::vector<HandEyeObservation>& poses) {
  if (poses.size() < 3)
    throw std::invalid_argument("hand-eye: at least 3 poses are needed, " + std::to_string(poses.size()) + " given");
  std::set<std::string> ids;
  bool any_covariance = false, all_covariance = true;
  for (const HandEyeObservation& p : poses) {
    if (!ids.insert(p.id).second) throw std::invalid_argument("hand-eye: pose id '" + p.id + "' repeats");
    if (!p.bTe.allFinite() || !p.cTm.allFinite())
      throw std::invalid_argument("hand-eye: pose '" + p.id + "': non-finite value");
    if (!(p.robot_sigma.translation_m > 0.0) || !(p.robot_sigma.rotation_rad > 0.0))
      throw std::invalid_argument("hand-eye: pose '" + p.id + "': the robot's sigma must be > 0");
    any_covariance = any_covariance || p.cTm_covariance.has_value();
    all_covariance = all_covariance && p.cTm_covariance.has_value();
  }
  if (any_covariance && !all_covariance)
    throw std::invalid_argument("hand-eye: some poses have a covariance and others not: give it for all or none");
}

// Singular values of the robot's relative rotations (rotation vectors of R_iᵀ·R_j, in the
// effector frame, over all pairs: independent of the order) and the principal axes.
struct RotationSpread {
  Eigen::Vector3d values;  // RMS rad along each axis, descending
  Eigen::Matrix3d axes;    // columns, same order
};
RotationSpread rotationSpread(const std::vector<HandEyeObservation>& poses) {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  std::vector<Eigen::Matrix3d> R;
  for (const HandEyeObservation& p : poses) R.push_back(fromRotationVector(p.bTe.tail<3>()));
  double pairs = 0.0;
  for (std::size_t i = 0; i < R.size(); ++i)
    for (std::size_t j = i + 1; j < R.size(); ++j) {
      const Eigen::Vector3d w = rotationVector(R[i].transpose() * R[j]);
      scatter += w * w.transpose();
      pairs += 1.0;
    }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter / std::max(1.0, pairs));
  RotationSpread spread;
  for (int k = 0; k < 3; ++k) {
    spread.values[k] = std::sqrt(std::max(0.0, eigen.eigenvalues()[2 - k]));
    spread.axes.col(k) = eigen.eigenvectors().col(2 - k);
  }
  return spread;
}

std::string vectorText(const Eigen::Vector3d& v) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.3f, %.3f, %.3f)", v.x(), v.y(), v.z());
  return buffer;
}

// The Ceres problem of one set of poses.
struct Fit {
  PoseVector x, z;
  std::vector<PoseVector> d;
  std::vector<CameraCost> cameras;
  std::vector<RobotPrior> priors;
  ceres::Problem problem;
  std::vector<ceres::ResidualBlockId> blocks;  // camera j, prior j, ...
  std::vector<double*> parameters;             // x, z, d_0, ...
};

void buildProblem(Fit& fit, const std::vector<HandEyeObservation>& poses, HandEyeMounting mounting) {
  const std::size_t n = poses.size();
  fit.d.assign(n, PoseVector::Zero());
  fit.parameters = {fit.x.data(), fit.z.data()};
  for (std::size_t j = 0; j < n; ++j) {
    const HandEyeObservation& p = poses[j];
    const Eigen::Isometry3d bTe = toIsometry(p.bTe), cTm = toIsometry(p.cTm);
    fit.cameras.push_back(
        {mounting, bTe.linear(), cTm.linear(), bTe.translation(), cTm.translation(), cameraWhitening(p)});
    fit.priors.push_back({p.robot_sigma.translation_m, p.robot_sigma.rotation_rad});
  }
  for (std::size_t j = 0; j < n; ++j) {
    fit.parameters.push_back(fit.d[j].data());
    fit.blocks.push_back(fit.problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<CameraCost, 6, 6, 6, 6>(new CameraCost(fit.cameras[j])), nullptr, fit.x.data(),
        fit.z.data(), fit.d[j].data()));
    fit.blocks.push_back(fit.problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<RobotPrior, 6, 6>(new RobotPrior(fit.priors[j])), nullptr, fit.d[j].data()));
  }
}

bool solve(Fit& fit) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_SCHUR;
  options.max_num_iterations = 200;
  options.function_tolerance = 1e-15;
  options.gradient_tolerance = 1e-15;
  options.parameter_tolerance = 1e-15;
  options.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &fit.problem, &summary);
  return summary.termination_type == ceres::CONVERGENCE;
}

// Residuals (camera j, prior j, ...) and the dense Jacobian over (x, z, d_0, ...).
void evaluate(Fit& fit, Eigen::VectorXd& residuals, Eigen::MatrixXd& jacobian) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = fit.parameters;
  options.residual_blocks = fit.blocks;
  std::vector<double> r;
  ceres::CRSMatrix crs;
  fit.problem.Evaluate(options, nullptr, &r, nullptr, &crs);
  residuals = Eigen::Map<Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size()));
  jacobian = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int k = crs.rows[static_cast<std::size_t>(row)]; k < crs.rows[static_cast<std::size_t>(row) + 1]; ++k)
      jacobian(row, crs.cols[static_cast<std::size_t>(k)]) = crs.values[static_cast<std::size_t>(k)];
}

// Information of the 12 unknowns with the nuisance poses marginalised (Schur complement).
Eigen::Matrix<double, 12, 12> marginalInformation(const Eigen::MatrixXd& jacobian) {
  const Eigen::MatrixXd H = jacobian.transpose() * jacobian;
  const Eigen::Index m = H.rows() - 12;
  const Eigen::MatrixXd Hgn = H.topRightCorner(12, m);
  const Eigen::LDLT<Eigen::MatrixXd> nuisance(H.bottomRightCorner(m, m));
  return H.topLeftCorner<12, 12>() - Hgn * nuisance.solve(Hgn.transpose());
}

// A square root of the information, for the identifiability analysis (same normal matrix).
Eigen::MatrixXd informationRoot(const Eigen::Matrix<double, 12, 12>& information) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 12, 12>> eigen(information);
  const Eigen::VectorXd root = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();
  return root.asDiagonal() * eigen.eigenvectors().transpose();
}

// Wilson–Hilferty quantile of χ² with k dof at the normal quantile z.
double chi2Quantile(double k, double z) {
  const double a = 2.0 / (9.0 * k);
  return k * std::pow(1.0 - a + z * std::sqrt(a), 3.0);
}

HandEyePoseScore scorePose(const Fit& fit, std::size_t j, const HandEyeObservation& pose,
                           const Eigen::VectorXd& residuals, HandEyeMounting mounting, double scale2) {
  HandEyePoseScore score;
  score.id = pose.id;
  score.chi2 = residuals.segment(static_cast<Eigen::Index>(12 * j), 12).squaredNorm() / scale2;
  const Eigen::Isometry3d X = toIsometry(fit.x), Z = toIsometry(fit.z);
  Eigen::Isometry3d bTe = toIsometry(pose.bTe);
  const Eigen::Isometry3d bTe_reported = bTe;
  bTe.linear() = fromRotationVector(fit.d[j].tail<3>()) * bTe.linear();
  bTe.translation() += fit.d[j].head<3>();
  const Eigen::Isometry3d predicted = handEyePredictedTarget(mounting, X, Z, bTe), measured = toIsometry(pose.cTm);
  score.camera_t_m = measured.translation() - predicted.translation();
  score.camera_r_rad = Eigen::AngleAxisd(measured.linear() * predicted.linear().transpose()).angle();
  score.robot_t_m = bTe.translation() - bTe_reported.translation();
  score.robot_r_rad = Eigen::AngleAxisd(bTe.linear() * bTe_reported.linear().transpose()).angle();
  return score;
}

// The message of data that do not determine the transforms.
std::string weakDataMessage(const IdentifiabilityReport& report, const RotationSpread& spread) {
  std::ostringstream out;
  out << "hand-eye: the poses do not determine the two transforms (rank " << report.rank << " of 12)";
  const double degrees = support::kDegreesPerRadian;
  if (spread.values[1] < kOneAxisRatio * std::max(spread.values[0], 1e-12))
    out << ": the robot turns about one axis only, " << vectorText(spread.axes.col(0))
        << " in the effector frame (spread " << spread.values[0] * degrees << " deg, second axis "
        << spread.values[1] * degrees << " deg): rotate it about a second axis";
  for (const UnidentifiableCombination& c : report.combinations) out << "\n  " << c.text();
  return out.str();
}

// One fit of a given set of poses (no outlier removal).
HandEyeResult fitOnce(const std::vector<HandEyeObservation>& poses, HandEyeMounting mounting) {
  HandEyeResult result;
  result.mounting = mounting;
  const RotationSpread spread = rotationSpread(poses);
  result.rotation_spread = spread.values;
  result.closed_form_method = mounting == HandEyeMounting::CameraOnEffector ? "park" : "shah";
  const HandEyeTransforms start = handEyeClosedForm(poses, mounting, result.closed_form_method);
  result.X_closed_form = start.X;
  result.Z_closed_form = start.Z;
  Fit fit;
  fit.x = toPoseVector(start.X);
  fit.z = toPoseVector(start.Z);
  buildProblem(fit, poses, mounting);
  result.converged = solve(fit);
  Eigen::VectorXd residuals;
  Eigen::MatrixXd jacobian;
  evaluate(fit, residuals, jacobian);
  const std::vector<std::string> names = handEyeParameterNames(mounting);
  const Eigen::Matrix<double, 12, 12> information = marginalInformation(jacobian);
  const Eigen::MatrixXd root = informationRoot(information);
  result.identifiability = analyzeJacobian(root, names);
  // Rotations about one axis leave a direction that noise in the reported rotations only makes
  // nearly (not exactly) null: named with a looser rank tolerance.
  const bool one_axis = spread.values[1] < kOneAxisRatio * spread.values[0];
  if (!result.identifiability.fullRank() || one_axis) {
    IdentifiabilityOptions loose;
    if (one_axis) {
      loose.rank_tolerance = 1e-3;
      loose.coefficient_tolerance = 1e-2;
    }
    throw std::invalid_argument(weakDataMessage(analyzeJacobian(root, names, loose), spread));
  }
  const auto n = static_cast<double>(poses.size());
  result.chi2 = residuals.squaredNorm();
  result.dof = static_cast<int>(6.0 * n) - 12;
  result.sigma_from_residuals = !poses.front().cTm_covariance.has_value();
  const double reduced = result.dof > 0 ? result.chi2 / result.dof : 1.0;
  // Stated σ are kept unless the fit contradicts them (χ² beyond its 0.999 quantile).
  if (result.sigma_from_residuals || (result.dof > 0 && result.chi2 > chi2Quantile(result.dof, 3.09)))
    result.scale2 = reduced;
  result.covariance = result.scale2 * information.inverse();
  result.sigma = result.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  for (std::size_t k = 0; k < 12; ++k) {
    const double value = k < 6 ? fit.x[static_cast<Eigen::Index>(k)] : fit.z[static_cast<Eigen::Index>(k - 6)];
    result.parameters.add(Parameter{names[k], value, k % 6 < 3 ? Unit::Metre : Unit::Radian, false,
                                    k % 6 < 3 ? "translation" : "rotation vector"});
  }
  result.X = toIsometry(fit.x);
  result.Z = toIsometry(fit.z);
  for (std::size_t j = 0; j < poses.size(); ++j)
    result.poses.push_back(scorePose(fit, j, poses[j], residuals, mounting, 1.0));
  return result;
}

// The scale of the per-pose χ² for the outlier screen: robust (median) so one outlier does not
// hide itself; with stated σ never below 1.
double screeningScale(const HandEyeResult& result) {
  std::vector<double> chi2;
  for (const HandEyePoseScore& s : result.poses) chi2.push_back(s.chi2);
  std::nth_element(chi2.begin(), chi2.begin() + static_cast<std::ptrdiff_t>(chi2.size() / 2), chi2.end());
  const double median = chi2[chi2.size() / 2];
  const double k = 6.0 - 12.0 / static_cast<double>(result.poses.size());
  const double robust = median / chi2Quantile(k, 0.0);
  return result.sigma_from_residuals ? robust : std::max(1.0, robust);
}

}  // namespace

Eigen::Isometry3d handEyePredictedTarget(HandEyeMounting mounting, const Eigen::Isometry3d& X,
                                         const Eigen::Isometry3d& Z, const Eigen::Isometry3d& bTe) {
  return mounting == HandEyeMounting::CameraOnEffector ? Eigen::Isometry3d(X.inverse() * bTe.inverse() * Z)
                                                       : Eigen::Isometry3d(X * bTe * Z);
}

HandEyeResult solveHandEye(const std::vector<HandEyeObservation>& poses, HandEyeMounting mounting,
                           const HandEyeOptions& options) {
  validate(poses);
  std::vector<HandEyeObservation> kept = poses;
  std::vector<HandEyePoseScore> removed;
  for (;;) {
    HandEyeResult result = fitOnce(kept, mounting);
    const double scale = screeningScale(result);
    std::size_t worst = 0;
    for (std::size_t j = 1; j < result.poses.size(); ++j)
      if (result.poses[j].chi2 > result.poses[worst].chi2) worst = j;
    const bool outlier = result.poses[worst].chi2 / scale > options.outlier_chi2;
    if (!outlier || !options.remove_outliers || kept.size() <= 4) {
      for (HandEyePoseScore& s : result.poses) s.chi2 /= result.scale2;
      result.outliers = removed;
      return result;
    }
    HandEyePoseScore score = result.poses[worst];
    score.chi2 /= scale;
    removed.push_back(score);
    kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(worst));
  }
}

}  // namespace mire::mechanism
