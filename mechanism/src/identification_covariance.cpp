// The covariance stage of the identification: misfit scaling, the achieved-scale outlier test
// and the calibration's shared term (identification_covariance.hpp, doc/uncertainty.md).
#include "mire/mechanism/identification_covariance.hpp"

#include "mire/mechanism/external.hpp"
#include "mire/support/csv.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <set>
#include <stdexcept>

namespace mire::mechanism {

namespace {

const char* const kAxes[6] = {"tx", "ty", "tz", "rx", "ry", "rz"};

int axisIndex(const std::string& text) {
  for (int k = 0; k < 6; ++k)
    if (text == kAxes[k]) return k;
  return -1;
}

// (I − H_jj)^(−1/2), H_jj = A_j H⁻¹ A_jᵀ the pose's leverage block (Bell and McCaffrey's CR2
// adjustment): a residual of a pose the fit leans on is smaller than that pose's error, by
// (I − H_jj) in expectation. Eigenvalues of I − H_jj are held above 1e-3 (a pose that alone
// fixes a direction says nothing of its error along it).
Eigen::MatrixXd leverageAdjustment(const Eigen::MatrixXd& A_j, const Eigen::MatrixXd& H_inv) {
  const Eigen::MatrixXd complement = Eigen::MatrixXd::Identity(A_j.rows(), A_j.rows()) - A_j * H_inv * A_j.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(complement);
  const Eigen::VectorXd inverse_root = eigen.eigenvalues().cwiseMax(1e-3).cwiseSqrt().cwiseInverse();
  return eigen.eigenvectors() * inverse_root.asDiagonal() * eigen.eigenvectors().transpose();
}

}  // namespace

double robustPoseScale2(const std::vector<double>& pose_chi2, int joint_count) {
  if (pose_chi2.size() < 3 || joint_count < 1) return 1.0;
  std::vector<double> values = pose_chi2;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return std::max(1.0, *middle / chi2Quantile(joint_count, 0.5));
}

double misfitScale2(double chi2, int dof, double p) {
  if (dof < 1 || !(chi2 >= 0.0)) return 1.0;
  const bool outside = chi2 > chi2Quantile(dof, p) || chi2 < chi2Quantile(dof, p, /*lower=*/true);
  return outside ? chi2 / dof : 1.0;
}

Eigen::MatrixXd SharedPoseTerm::poseCovariance(const std::string& pose_id) const {
  const auto it = sensitivity.find(pose_id);
  if (it == sensitivity.end()) return Eigen::MatrixXd::Zero(6, 6);
  return it->second * covariance * it->second.transpose();
}

SharedPoseTerm readSharedTermCsv(const std::filesystem::path& path) {
  const support::CsvTable table = support::readCsv(path);
  const std::size_t kind_col = table.column("kind"), id_col = table.column("id"), row_col = table.column("row");
  SharedPoseTerm shared;
  for (std::size_t c = 0; c < table.header.size(); ++c)
    if (c != kind_col && c != id_col && c != row_col) shared.names.push_back(table.header[c]);
  const auto n = static_cast<Eigen::Index>(shared.names.size());
  if (n == 0) throw std::runtime_error(path.string() + ": no parameter columns after kind,id,row");
  // The shared parameters are a camera's (at most 18): n² values are allocated below.
  if (n > 64)
    throw std::runtime_error(path.string() + ": " + std::to_string(n) +
                             " parameter columns after kind,id,row; a shared term has at most 64");
  shared.covariance = Eigen::MatrixXd::Constant(n, n, std::nan(""));
  const auto valueRow = [&](std::size_t r) {
    Eigen::RowVectorXd v(n);
    for (Eigen::Index k = 0; k < n; ++k)
      v[k] = table.number(r, table.column(shared.names[static_cast<std::size_t>(k)]));
    return v;
  };
  std::map<std::string, std::set<int>> seen;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const std::string& kind = table.rows[r][kind_col];
    const std::string& row = table.rows[r][row_col];
    if (kind == "covariance") {
      const auto it = std::find(shared.names.begin(), shared.names.end(), row);
      if (it == shared.names.end())
        throw std::runtime_error(table.where(r) + ": column 'row': '" + row + "' is not a parameter column");
      shared.covariance.row(it - shared.names.begin()) = valueRow(r);
    } else if (kind == "sensitivity") {
      const std::string& id = table.rows[r][id_col];
      const int axis = axisIndex(row);
      if (axis < 0)
        throw std::runtime_error(table.where(r) + ": column 'row': '" + row + "' is not one of tx ty tz rx ry rz");
      if (!seen[id].insert(axis).second)
        throw std::runtime_error(table.where(r) + ": duplicate row '" + row + "' of pose '" + id + "'");
      shared.sensitivity.try_emplace(id, Eigen::MatrixXd::Zero(6, n)).first->second.row(axis) = valueRow(r);
    } else {
      throw std::runtime_error(table.where(r) + ": column 'kind': '" + kind + "' is not 'covariance' or 'sensitivity'");
    }
  }
  for (const auto& [id, rows] : seen)
    if (rows.size() != 6)
      throw std::runtime_error(path.string() + ": pose '" + id + "' has " + std::to_string(rows.size()) +
                               " of the 6 sensitivity rows");
  if (!shared.covariance.allFinite())
    throw std::runtime_error(path.string() + ": the camera covariance needs one 'covariance' row per parameter");
  if ((shared.covariance - shared.covariance.transpose()).cwiseAbs().maxCoeff() >
      1e-9 * shared.covariance.cwiseAbs().maxCoeff())
    throw std::runtime_error(path.string() + ": the camera covariance is not symmetric");
  return shared;
}

Eigen::MatrixXd sandwichCovariance(const IdentificationResult& result, const std::vector<PoseObservation>& poses) {
  const int J = result.model.mechanism->jointCount();
  const Eigen::MatrixXd J_rad = identificationJacobian(result.model, poses);
  const Eigen::MatrixXd& H_inv = result.information_inverse;
  Eigen::MatrixXd meat = Eigen::MatrixXd::Zero(J_rad.cols(), J_rad.cols());
  for (std::size_t j = 0; j < poses.size(); ++j) {
    if (!result.poses.at(j).used) continue;
    const Eigen::MatrixXd& W = result.whitening.at(j);
    const Eigen::MatrixXd A_j = W * J_rad.middleRows(static_cast<Eigen::Index>(j) * J, J);
    const Eigen::VectorXd score = A_j.transpose() * (leverageAdjustment(A_j, H_inv) * (W * result.poses[j].residual));
    meat += score * score.transpose();
  }
  return H_inv * meat * H_inv;
}

namespace {

// ∂ξ̂/∂k with the axis alignment held (implicit function theorem at the solution).
Eigen::MatrixXd analyticSensitivity(const IdentificationResult& result, const std::vector<PoseObservation>& poses,
                                    const SharedPoseTerm& shared) {
  const IdentificationModel& model = result.model;
  const int J = model.mechanism->jointCount();
  const Eigen::MatrixXd J_rad = identificationJacobian(model, poses);  // unwhitened, free columns
  const Eigen::VectorXd g = model.geometricValues(), e = model.externalValues();
  // Aᵀ ∂r_w/∂k summed over the poses used: r_j = q̄_j − f(cTm_j), ∂r_j/∂k = −J_p,j D_j.
  Eigen::MatrixXd At_dr = Eigen::MatrixXd::Zero(J_rad.cols(), static_cast<Eigen::Index>(shared.names.size()));
  for (std::size_t j = 0; j < poses.size(); ++j) {
    if (j < result.poses.size() && !result.poses[j].used) continue;
    const Eigen::MatrixXd& W = result.whitening.at(j);
    const Eigen::MatrixXd A_j = W * J_rad.middleRows(static_cast<Eigen::Index>(j) * J, J);
    const Eigen::MatrixXd Jp = model.mechanism->jointJacobianWrtPose(model.external, g, e, poses[j].cTm);
    At_dr -= A_j.transpose() * (W * (Jp * shared.sensitivity.at(poses[j].id)));
  }
  return -result.information_inverse * At_dr;
}

Eigen::VectorXd freeValues(const IdentificationResult& r) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(r.free_names.size()));
  for (std::size_t f = 0; f < r.free_names.size(); ++f)
    v[static_cast<Eigen::Index>(f)] = r.model.parameters.value(r.free_names[f]);
  return v;
}

// The tilts δ (AxisAlignment::covariance's order) that turn `from` into `to`.
Eigen::Vector4d tiltsBetween(const AxisAlignment& from, const AxisAlignment& to) {
  const Eigen::AngleAxisd camera(from.camera.transpose() * to.camera), target(from.target.transpose() * to.target);
  const Eigen::Vector3d c = camera.angle() * camera.axis(), m = target.angle() * target.axis();
  return Eigen::Vector4d(c.x(), c.y(), m.x(), m.y());
}

CovarianceTerm namedTerm(const char* name) {
  CovarianceTerm term;
  term.name = name;
  return term;
}

// The shared term by refits: G·√Σ_k by central differences of the whole estimator along Σ_k's
// principal directions (its columns), and the alignment tilts' change along them (aligned forms).
CovarianceTerm refitSharedTerm(const IdentificationResult& result, const std::vector<PoseObservation>& poses,
                               const SharedPoseTerm& shared, const Refit& refit) {
  // Σ_k = S C Sᵀ (S = diag σ_k, C the correlation), C = U Λ Uᵀ: the steps S u_i √λ_i are
  // well scaled whatever the units of k.
  const auto n = shared.covariance.rows();
  const Eigen::VectorXd scale = shared.covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
  Eigen::VectorXd inverse_scale = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) inverse_scale[i] = scale[i] > 0.0 ? 1.0 / scale[i] : 0.0;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(inverse_scale.asDiagonal() * shared.covariance *
                                                             inverse_scale.asDiagonal());
  const bool aligned = result.model.external.form() == ExternalForm::AxisAligned ||
                       result.model.external.form() == ExternalForm::CameraFrame;
  Eigen::MatrixXd columns = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(result.free_names.size()), n);
  Eigen::MatrixXd tilts = Eigen::MatrixXd::Zero(aligned ? 4 : 0, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double lambda = eigen.eigenvalues()[i];
    if (!(lambda > 0.0)) continue;
    const Eigen::VectorXd step = scale.asDiagonal() * eigen.eigenvectors().col(i) * std::sqrt(lambda);
    Eigen::VectorXd values[2];
    Eigen::Vector4d tilt[2];
    for (int side = 0; side < 2; ++side) {
      std::vector<PoseObservation> shifted = poses;
      for (PoseObservation& p : shifted) p.cTm += (side == 0 ? 1.0 : -1.0) * shared.sensitivity.at(p.id) * step;
      const IdentificationResult r = refit(shifted);
      if (r.free_names != result.free_names)
        throw std::runtime_error("shared calibration term: the refit changed the free parameters");
      values[side] = freeValues(r);
      tilt[side] = tiltsBetween(result.model.external.alignment(), r.model.external.alignment());
    }
    columns.col(i) = 0.5 * (values[0] - values[1]);
    if (aligned) tilts.col(i) = 0.5 * (tilt[0] - tilt[1]);
  }
  CovarianceTerm term = namedTerm(CovarianceTerm::kShared);
  term.covariance = columns * columns.transpose();
  term.columns = std::move(columns);
  term.alignment_columns = std::move(tilts);
  return term;
}

// The fit's own term when the pose covariances include the shared part D_j Σ_k D_jᵀ: the
// weights W_j whiten Σ_j, but the error that varies from pose to pose has only the
// independent part, so the estimator's covariance is the sandwich
//   H⁻¹ Aᵀ (I − M) A H⁻¹ = H⁻¹ − H⁻¹ B H⁻¹,  B = Σ_j A_jᵀ M_j A_j,  M_j = (W_j J_p,j D_j) Σ_k (…)ᵀ
// (the shared part is added once, as shared, by G Σ_k Gᵀ). For the same reason χ² is expected
// below its dof, E[χ²] = n − tr M − p + tr(H⁻¹ B): the misfit test compares χ² with that.
struct FitTerm {
  Eigen::MatrixXd covariance;
  double chi2 = 0.0, expected_chi2 = 0.0;
  int dof = 0;
};

// M_j with its eigenvalues clipped at 1: the shared part of a pose's error cannot exceed the
// whole, so that H − B = Σ_j A_jᵀ(I − M_j)A_j stays positive semi-definite. It exceeds it in
// measure's files where the detector's shared-bias modes are larger than the pose's own
// covariance in one direction (that covariance is the features' scatter × the fit's reduced χ²,
// which holds the bias on the trace, not direction by direction: doc/uncertainty.md): on a
// described 6-RUS campaign (81 poses, 66 free parameters) M_j's largest eigenvalue was 1.0–11.4,
// and H⁻¹ − H⁻¹BH⁻¹ had a negative variance (σ NaN).
Eigen::MatrixXd atMostIdentity(const Eigen::MatrixXd& M) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(0.5 * (M + M.transpose()));
  if (eigen.eigenvalues().maxCoeff() <= 1.0) return M;
  const Eigen::VectorXd clipped = eigen.eigenvalues().cwiseMin(1.0);
  return eigen.eigenvectors() * clipped.asDiagonal() * eigen.eigenvectors().transpose();
}

FitTerm independentFitTerm(const IdentificationResult& result, const std::vector<PoseObservation>& poses,
                           const SharedPoseTerm& shared) {
  const IdentificationModel& model = result.model;
  const int J = model.mechanism->jointCount();
  const Eigen::MatrixXd J_rad = identificationJacobian(model, poses);
  const Eigen::VectorXd g = model.geometricValues(), e = model.externalValues();
  const Eigen::MatrixXd& H_inv = result.information_inverse;
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(H_inv.rows(), H_inv.cols());
  FitTerm fit;
  double trace_m = 0.0;
  int rows = 0;
  for (std::size_t j = 0; j < poses.size(); ++j) {
    if (j < result.poses.size() && !result.poses[j].used) continue;
    const Eigen::MatrixXd& W = result.whitening.at(j);
    const Eigen::MatrixXd A_j = W * J_rad.middleRows(static_cast<Eigen::Index>(j) * J, J);
    const Eigen::MatrixXd Jp = model.mechanism->jointJacobianWrtPose(model.external, g, e, poses[j].cTm);
    const Eigen::MatrixXd WJD = W * (Jp * shared.sensitivity.at(poses[j].id));
    const Eigen::MatrixXd M = atMostIdentity(WJD * shared.covariance * WJD.transpose());
    B += A_j.transpose() * M * A_j;
    trace_m += M.trace();
    fit.chi2 += (W * result.poses.at(j).residual).squaredNorm();
    rows += J;
  }
  const auto p = static_cast<int>(H_inv.rows());
  fit.covariance = H_inv - H_inv * B * H_inv;
  fit.dof = rows - p;
  fit.expected_chi2 = static_cast<double>(rows) - trace_m - p + (H_inv * B).trace();
  return fit;
}

// Poses per free parameter from which the fit's term is taken from the residuals.
constexpr int kResidualSandwichPosesPerParameter = 3;

// The fit's term when the shared term is added (in place of (AᵀA)⁻¹ × misfit_scale2):
//  * with at least 3 poses per free parameter, the cluster-robust sandwich of the residuals
//    (sandwichCovariance, one cluster per pose): it holds the pose errors as they are, the
//    detector's systematic feature error included, where the modelled independent part
//    Σ_j − D_j Σ_k D_jᵀ misses it — on rendered H4 chains the modelled term left σ up to 2.2×
//    too small, the residual term brought 16 of 19 parameters into [0.8, 1.25]
//    (doc/studies/2026-11-24-chain-study-h4.md);
//  * with fewer poses (the sandwich would rest on too few residual degrees of freedom), the
//    modelled sandwich above, scaled when χ² lies outside the band around its expected value
//    (only when the fit was scaled at all).
CovarianceTerm fitTermWithShared(const IdentificationResult& result, const std::vector<PoseObservation>& poses,
                                 const SharedPoseTerm& shared) {
  CovarianceTerm term = measuredFitTerm(result);
  if (!result.weighted || result.whitening.size() < poses.size()) return term;
  const auto used = std::count_if(result.poses.begin(), result.poses.end(), [](const auto& p) { return p.used; });
  if (used >= kResidualSandwichPosesPerParameter * result.information_inverse.rows()) {
    term.covariance = sandwichCovariance(result, poses);
    term.scale2 = 1.0;
    term.method = "residual sandwich";
    return term;
  }
  const FitTerm fit = independentFitTerm(result, poses, shared);
  if (fit.dof < 1 || !(fit.expected_chi2 > 0.0)) return term;
  const double scale2 =
      result.misfit_scale2 == 1.0 ? 1.0 : misfitScale2(fit.chi2 * fit.dof / fit.expected_chi2, fit.dof, 1e-3);
  term.covariance = fit.covariance * scale2;
  term.scale2 = scale2;
  term.method = scale2 == 1.0 ? "measured" : "residual-scaled";
  return term;
}

// The axis-alignment term (fitCovarianceTerms) takes the tilts' covariance from the full pose
// covariances, as if their shared part D_j Σ_k D_jᵀ were independent per pose. The refits above
// re-estimate the alignment from the shifted orientations, so they already carry that part, as
// shared: with them, the tilts' covariance is recomputed from the independent part
// Σ_j − D_j Σ_k D_jᵀ alone (doc/uncertainty.md, "The axis-alignment term").
Eigen::Matrix4d independentTiltCovariance(const IdentificationResult& result, const std::vector<PoseObservation>& poses,
                                          const SharedPoseTerm& shared) {
  std::vector<PoseObservation> independent = poses;
  for (PoseObservation& p : independent) {
    if (!p.covariance) return result.model.external.alignment().covariance;
    *p.covariance -= shared.poseCovariance(p.id);
  }
  AxisAlignment alignment = estimateAxisAlignment(independent);
  // The same tilt frames as the model's alignment (its axis may have been flipped along θ).
  if (alignment.camera.col(2).dot(result.model.external.alignment().camera.col(2)) < 0.0) {
    const Eigen::Matrix4d G = Eigen::Vector4d(1.0, -1.0, 1.0, -1.0).asDiagonal();
    alignment.covariance = G * alignment.covariance * G;
  }
  return alignment.covariance;
}

// S·Σδ·Sᵀ with its columns for predictions (none when the alignment is not estimated).
std::optional<CovarianceTerm> alignmentTerm(const IdentificationResult& result, const Eigen::MatrixXd& tilt_covariance) {
  const Eigen::MatrixXd& S = result.alignment_sensitivity;
  if (S.size() == 0) return std::nullopt;
  CovarianceTerm term = namedTerm(CovarianceTerm::kAlignment);
  term.covariance = S.lazyProduct(tilt_covariance).lazyProduct(S.transpose());
  term.columns = S;
  term.alignment_columns = Eigen::MatrixXd::Identity(4, 4);
  term.source_covariance = tilt_covariance;
  return term;
}

}  // namespace

CovarianceTerm measuredFitTerm(const IdentificationResult& fit) {
  CovarianceTerm term = namedTerm(CovarianceTerm::kFit);
  term.method = fit.weighted && fit.misfit_scale2 == 1.0 ? "measured" : "residual-scaled";
  term.scale2 = fit.misfit_scale2;
  term.covariance = fit.information_inverse * fit.misfit_scale2;
  return term;
}

std::vector<CovarianceTerm> fitCovarianceTerms(const IdentificationResult& fit) {
  std::vector<CovarianceTerm> terms{measuredFitTerm(fit)};
  if (auto alignment = alignmentTerm(fit, fit.model.external.alignment().covariance))
    terms.push_back(std::move(*alignment));
  return terms;
}

std::vector<CovarianceTerm> covarianceTermsWithShared(const IdentificationResult& fit,
                                                      const std::vector<PoseObservation>& poses,
                                                      const SharedPoseTerm& shared, const Refit& refit) {
  for (const PoseObservation& p : poses)
    if (!shared.sensitivity.count(p.id))
      throw std::runtime_error("pose '" + p.id + "' has no sensitivity in the shared-term file");
  std::vector<CovarianceTerm> terms{fitTermWithShared(fit, poses, shared)};
  if (fit.alignment_sensitivity.size() > 0)
    terms.push_back(*alignmentTerm(
        fit, refit ? independentTiltCovariance(fit, poses, shared) : fit.model.external.alignment().covariance));
  if (refit) {
    terms.push_back(refitSharedTerm(fit, poses, shared, refit));
  } else {
    const Eigen::MatrixXd G = analyticSensitivity(fit, poses, shared);
    CovarianceTerm term = namedTerm(CovarianceTerm::kShared);
    term.covariance = G * shared.covariance * G.transpose();
    terms.push_back(std::move(term));
  }
  return terms;
}

void addSharedTermCovariance(IdentificationResult& result, const std::vector<PoseObservation>& poses,
                             const SharedPoseTerm& shared, const Refit& refit) {
  if (shared.empty() || result.information_inverse.size() == 0) return;
  setCovarianceTerms(result, covarianceTermsWithShared(result, poses, shared, refit));
}

}  // namespace mire::mechanism
