#pragma once
// The covariance stage of the identification (doc/uncertainty.md):
//  * misfit: the whitened residuals' χ²/dof tested against its χ² distribution; when the
//    measured pose covariances do not explain the residuals (model error, or covariances too
//    large or too small) the parameter covariance is scaled by χ²/dof (residual-scaled);
//  * the outlier-pose test at the residual scale actually achieved (a robust, median-based
//    scale), so model misfit shows as one χ²/dof figure, not as most poses "outliers";
//  * the error shared by every pose — the camera calibration — propagated exactly through the
//    estimator: Σ_ξ += G Σ_k Gᵀ with G = ∂ξ̂/∂k = −(AᵀA)⁻¹ Aᵀ ∂r_w/∂k (implicit function
//    theorem at the solution; A the whitened Jacobian, r_w the whitened residuals).
#include <Eigen/Core>

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/pose.hpp"
#include "mire/support/statistics.hpp"

namespace mire::mechanism {

// χ² quantile with k dof exceeded with probability p (lower tail with `lower`), Wilson–Hilferty.
using support::chi2Quantile;

// Scale² of the per-pose whitened χ² (J dof each) actually achieved, robust to a few outlier
// poses: median(χ²_j) / median of χ²_J, never below 1 (the pose covariances are the floor).
double robustPoseScale2(const std::vector<double>& pose_chi2, int joint_count);

// Scale² applied to (AᵀA)⁻¹ of a weighted fit: χ²/dof when it lies outside the central
// 1 − 2p band of its χ² distribution (misfit, or covariances that overstate the noise), else 1.
double misfitScale2(double chi2, int dof, double p);

// Sandwich (cluster-robust, one cluster per pose) covariance of the free parameters:
// H⁻¹ (Σ_j A_jᵀ r̃_j r̃_jᵀ A_j) H⁻¹, H⁻¹ = result.information_inverse, A_j and r_j the whitened
// Jacobian and residuals of the poses used, r̃_j = (I − A_j H⁻¹ A_jᵀ)^(−1/2) r_j (the CR2
// leverage adjustment of Bell and McCaffrey: unbiased when the weights are right, whatever the
// number of poses per parameter, where the uniform m/(m − p) factor over- and under-corrects).
Eigen::MatrixXd sandwichCovariance(const IdentificationResult& result, const std::vector<PoseObservation>& poses);

// What `mire measure` knows about the error shared by every pose: the camera's covariance
// Σ_k (n × n, over `names`) and each pose's sensitivity ∂cTm/∂k (6 × n, rows tx ty tz rx ry rz).
struct SharedPoseTerm {
  std::vector<std::string> names;
  Eigen::MatrixXd covariance;
  std::map<std::string, Eigen::MatrixXd> sensitivity;  // by pose id
  bool empty() const { return names.empty(); }
  // The per-pose part of the shared term, D_j Σ_k D_jᵀ (zero for an unknown id).
  Eigen::MatrixXd poseCovariance(const std::string& pose_id) const;
};

// Reads the shared-term side file (support::sharedTermSidePath(), written by `mire measure`:
// metrology/shared_term_csv.hpp); throws std::runtime_error naming the file, line and problem.
SharedPoseTerm readSharedTermCsv(const std::filesystem::path& path);

// The fit's term as the fit alone gives it: (AᵀA)⁻¹ × misfit_scale2, "measured" or "residual-scaled".
CovarianceTerm measuredFitTerm(const IdentificationResult& fit);

// The terms of a fit without the shared term (identify()): measuredFitTerm(), then the alignment's,
// S·Σδ·Sᵀ with the model's Σδ (aligned forms).
std::vector<CovarianceTerm> fitCovarianceTerms(const IdentificationResult& fit);

// The terms with the error shared by every pose (doc/uncertainty.md), of the fit `fit` of `poses`:
//  * "fit": with 3 poses per free parameter, the residual sandwich (sandwichCovariance()); else
//    the modelled independent part H⁻¹ − H⁻¹BH⁻¹, scaled on misfit against its expected χ²;
//  * "alignment": S·Σδ·Sᵀ, Σδ from the independent part Σ_j − D_j Σ_k D_jᵀ with `refit` (which
//    carries the shared part), else the model's;
//  * "shared calibration": G Σ_k Gᵀ. Without `refit`: G = −(AᵀA)⁻¹ Aᵀ ∂r_w/∂k at the solution,
//    the external axis alignment held at its estimate. With `refit` (the whole estimator,
//    initialisation included, run on perturbed poses): G by central differences of the estimate
//    along each principal direction u_i of Σ_k, ±√λ_i — this also carries the shared error
//    through the axis alignment estimated from the same orientations (2n refits).
// Throws std::runtime_error for a pose without a sensitivity in `shared`.
using Refit = std::function<IdentificationResult(const std::vector<PoseObservation>&)>;
std::vector<CovarianceTerm> covarianceTermsWithShared(const IdentificationResult& fit,
                                                      const std::vector<PoseObservation>& poses,
                                                      const SharedPoseTerm& shared, const Refit& refit = {});

// setCovarianceTerms(result, covarianceTermsWithShared(result, …)); no change without a shared
// term or without the fit's information matrix.
void addSharedTermCovariance(IdentificationResult& result, const std::vector<PoseObservation>& poses,
                             const SharedPoseTerm& shared, const Refit& refit = {});

}  // namespace mire::mechanism
