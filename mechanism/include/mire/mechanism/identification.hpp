#pragma once
// Identification (paper eq. 2/4; doc/mechanisms.md, "Identification"): minimise Σ‖W_j (q̄_j − f(X(ξe,
// cTm_j), ξg))‖² over the free parameters with Ceres, optional Gaussian priors, a robust loss with outlier
// poses reported, weighting by the measured pose covariances (Σq = J Σ_X Jᵀ, J = ∂f/∂cTm),
// then the covariance of the estimate and the identifiability report at the solution.
#include <Eigen/Core>

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "mire/mechanism/external.hpp"
#include "mire/mechanism/identifiability.hpp"
#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/parameter_set.hpp"
#include "mire/mechanism/pose.hpp"

namespace mire::mechanism {

// A mechanism, an external parameterisation and the combined parameter set ξ = ξg ∪ ξe
// (geometric names first, then external), with values, fixed flags and ties.
struct IdentificationModel {
  std::shared_ptr<const Mechanism> mechanism;
  ExternalParameterization external{ExternalForm::AxisAligned};
  ParameterSet parameters;

  // From the combined set (the mechanism's own count builds its nominal set: per-pose callers).
  int geometricCount() const { return static_cast<int>(parameters.size()) - external.size(); }
  Eigen::VectorXd geometricValues() const;  // first geometricCount() values
  Eigen::VectorXd externalValues() const;   // the rest
  // IKM prediction for a measured pose at the current values.
  IkmResult predictJoints(const PoseVector& cTm) const;
};

// Builds the combined model; `geometric` must have the mechanism's names (in order) and
// `external` the form's names. Throws std::invalid_argument otherwise.
IdentificationModel makeIdentificationModel(std::shared_ptr<const Mechanism> mechanism, const ParameterSet& geometric,
                                            const ExternalParameterization& external,
                                            const ParameterSet& external_values);

// Nominal geometry + external values estimated from the data (estimateExternal()).
IdentificationModel makeInitialModel(std::shared_ptr<const Mechanism> mechanism, const ParameterSet& geometric,
                                     const std::vector<PoseObservation>& poses, ExternalForm form, double z_ME = 0.0);

// Brings each geometric angle more than π from its `reference` value (the nominal geometry) that
// the kinematics sees only through its sine and cosine (the IKM unchanged by a whole turn: an
// arm axis's ψ_i, not a revolute joint's offset q0_i) back within π of it, so that an identified
// angle reads as its nominal plus the change and files hold angles every reader takes
// (doc/file-formats.md). Returns the names of the angles it moved; their covariance is unchanged.
std::vector<std::string> wrapPeriodicAngles(IdentificationModel& model, const Eigen::VectorXd& reference);

// Ids of the poses whose IKM is unreachable at the model's current values.
std::vector<std::string> unreachablePoses(const IdentificationModel& model, const std::vector<PoseObservation>& poses);

enum class RobustLoss { None, Huber, Cauchy };

struct GaussianPrior {
  std::string name;
  double mean = 0.0;   // SI
  double sigma = 0.0;  // SI, > 0
};

struct IdentificationOptions {
  std::vector<std::string> fix;      // also hold these at their current values
  std::vector<std::string> release;  // free these even if fixed by default (e.g. "z_ME")
  std::vector<GaussianPrior> priors;
  // Weight by Σq = J Σ_X Jᵀ when every pose has a covariance (else unweighted).
  bool use_pose_covariances = true;
  // Without pose covariances, residuals are divided by this assumed joint σ [rad] so that
  // priors and the robust loss scale are in σ units; the reported covariance is rescaled by
  // the residual variance estimate anyway.
  double joint_sigma = 1e-3;
  RobustLoss loss = RobustLoss::None;
  double loss_scale = 3.0;  // in σ units of the whitened residual
  // A pose is an outlier when its whitened χ² (J dof; scaled by σ̂² when unweighted)
  // exceeds the χ² quantile at 1 − outlier_probability.
  double outlier_probability = 1e-3;
  // Weighted fits: scale the covariance by χ²/dof when the χ² test at outlier_probability
  // (two-sided) rejects the measured pose covariances (model error, doc/uncertainty.md).
  bool scale_on_misfit = true;
  // Solver iterations per solve. 500: a Delta on planned (extreme) poses, weighted with a large
  // shared calibration part, crawls along a curved valley (at 100, 35 of 200 such campaigns
  // stopped short; at 500, none: doc/studies/2026-11-24-chain-study-delta-gough-stewart.md, "Planning").
  int max_iterations = 500;
  bool compute_identifiability = true;
  IdentifiabilityOptions identifiability;
};

struct PoseResidual {
  std::string id;
  Eigen::VectorXd residual;  // q̄ − f [rad], unwhitened
  double chi2 = 0.0;         // whitened (σ̂-normalised when unweighted)
  bool outlier = false;
  bool used = true;  // in the covariance (false: an outlier left out under a robust loss)
};

// One named part of the estimate's covariance (doc/uncertainty.md, "How the terms add up"); the
// covariance of an identification is the sum of its terms, taken once (setCovarianceTerms()).
struct CovarianceTerm {
  static constexpr const char* kFit = "fit";              // the pose errors that vary from pose to pose
  static constexpr const char* kAlignment = "alignment";  // the estimated rotation axis (aligned forms)
  // The error every pose shares: the camera's parameters and, when `mire measure` found one, the
  // detector's shared bias modes (the shared-term file's columns, identification_covariance.hpp).
  static constexpr const char* kShared = "shared calibration";
  std::string name;
  // The fit's: how its term is taken ("measured", "residual-scaled", "residual sandwich") and the
  // factor applied to (AᵀA)⁻¹ (1 unless residual-scaled).
  std::string method;
  double scale2 = 1.0;
  Eigen::MatrixXd covariance;  // of the free parameters, SI
  // A term that also moves the estimated axis alignment δ (aligned forms; else empty):
  // covariance = X Σ Xᵀ, Cov(ξ, δ) = X Σ Δᵀ, Cov(δ) = Δ Σ Δᵀ (Σ = I when empty), so that predictions
  // through the aligned mounting carry ξ and δ jointly (prediction.cpp). The alignment term: X =
  // ∂ξ̂/∂δ, Δ = I, Σ = Σδ; the shared term by refits: X = G·√Σ_k, Δ the tilts' change, Σ = I.
  Eigen::MatrixXd columns, alignment_columns, source_covariance;
};

struct IdentificationResult {
  // ---- The fit, as identify() solved it; the covariance stage reads it and does not change it ----
  IdentificationModel model;            // identified values (fixed ones unchanged)
  std::vector<std::string> free_names;  // the unknowns (tie leaders), covariance order
  bool weighted = false;                // residuals whitened by the pose covariances
  double chi2 = 0.0;                    // Σ whitened residual² (without priors)
  int dof = 0;                          // residual count − free parameter count (+ prior count)
  // Unweighted: σ̂ = √(χ²_rad/dof) [rad], covariance = σ̂²(JᵀJ)⁻¹.
  // Weighted: √(χ²/dof) (≈ 1 when the pose covariances are right); covariance = (JᵀWJ)⁻¹,
  // not rescaled (the measured covariances set the scale).
  double residual_scale = 0.0;
  double rms_joint_residual = 0.0;  // [rad], unweighted, over all joints of all poses
  // The factor the fit alone puts on (AᵀA)⁻¹: χ²/dof when unweighted or when the misfit test
  // rejects the measured pose covariances (doc/uncertainty.md), else 1.
  double misfit_scale2 = 1.0;
  double outlier_scale2 = 1.0;             // scale² of the outlier test (achieved, robust)
  Eigen::MatrixXd information_inverse;     // (AᵀA)⁻¹ of the whitened problem, unscaled
  std::vector<Eigen::MatrixXd> whitening;  // W_j of every pose (4 × 4 for the H4)
  // S = ∂ξ̂/∂δ (free parameters × 4 tilts; empty for the full form): the estimate's sensitivity to
  // the estimated rotation-axis alignment (the alignment term's columns).
  Eigen::MatrixXd alignment_sensitivity;
  bool rank_deficient = false;  // AᵀA singular: the unidentifiable combinations' members get σ = ∞
  std::vector<PoseResidual> poses;
  std::vector<std::string> outliers;  // pose ids

  IdentifiabilityReport identifiability;  // at the solution, over the free parameters
  bool converged = false;
  int iterations = 0;
  double solve_seconds = 0.0;
  std::string solver_report;  // Ceres brief report

  // ---- The uncertainty: named terms, summed once (setCovarianceTerms()) ----
  std::vector<CovarianceTerm> covariance_terms;  // the fit's first
  // The sum of the terms (of the free parameters, SI) and σ per parameter in model.parameters
  // order (0 if fixed, ∞ in an unidentifiable combination); kept as fields for their many readers.
  Eigen::MatrixXd covariance;
  Eigen::VectorXd sigma;
  double sigmaOf(const std::string& name) const;                  // throws for an unknown name
  const CovarianceTerm* term(const std::string& name) const;      // nullptr when absent
  Eigen::MatrixXd termCovariance(const std::string& name) const;  // zero when absent
  // What the printed σ is: the fit term's method, "+ shared calibration term" with that term.
  std::string covarianceMethod() const;
  double covarianceScale2() const;  // the fit term's factor
};

// Sets the result's terms and, from them once, its total covariance and σ.
void setCovarianceTerms(IdentificationResult& result, std::vector<CovarianceTerm> terms);

// A robust fit that gave up most poses (identify()): the poses and joints do not describe one
// robot of the model. Its own type so that a command can name the files it read them from.
struct PosesRejectedError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Runs the identification from the model's current values. Throws std::invalid_argument
// on bad input (unknown names in options, non-finite values, joint count mismatch,
// fewer residuals than unknowns) and std::runtime_error naming the unreachable pose ids
// when the IKM fails at the initial values. Under a robust loss, throws PosesRejectedError
// when more than half the poses fit worse than at the initial values and the whole χ² rose
// (doc/robustness.md).
IdentificationResult identify(const IdentificationModel& initial, const std::vector<PoseObservation>& poses,
                              const IdentificationOptions& options = {});

// J_ξ = ∂ε/∂ξ (unwhitened, rad per SI unit) over the model's free parameters at its
// current values, 4 rows per pose in pose order. Throws naming unreachable poses.
Eigen::MatrixXd identificationJacobian(const IdentificationModel& model, const std::vector<PoseObservation>& poses);

// analyzeJacobian(identificationJacobian(model, poses), model.parameters.freeNames()).
IdentifiabilityReport analyzeIdentifiability(const IdentificationModel& model, const std::vector<PoseObservation>& poses,
                                             const IdentifiabilityOptions& options = {});

}  // namespace mire::mechanism
