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

struct IdentificationResult {
  IdentificationModel model;            // identified values (fixed ones unchanged)
  std::vector<std::string> free_names;  // the unknowns (tie leaders), covariance order
  Eigen::MatrixXd covariance;           // of the free parameters, SI
  // The part of `covariance` due to the estimated rotation-axis alignment (aligned forms:
  // AxisAlignment::covariance propagated through the solution's sensitivity to the tilts).
  Eigen::MatrixXd alignment_covariance;
  // S = ∂ξ̂/∂δ (free parameters × 4 tilts; empty for the full form): the estimate's
  // sensitivity to the alignment, so that predictions through the aligned mounting can carry
  // the alignment's own uncertainty jointly with the parameters' (prediction.cpp).
  Eigen::MatrixXd alignment_sensitivity;
  Eigen::VectorXd sigma;                          // per parameter in model.parameters order; 0 if fixed
  double sigmaOf(const std::string& name) const;  // throws for an unknown name

  bool weighted = false;  // residuals whitened by the pose covariances
  double chi2 = 0.0;      // Σ whitened residual² (without priors)
  int dof = 0;            // residual count − free parameter count (+ prior count)
  // Unweighted: σ̂ = √(χ²_rad/dof) [rad], covariance = σ̂²(JᵀJ)⁻¹.
  // Weighted: √(χ²/dof) (≈ 1 when the pose covariances are right); covariance = (JᵀWJ)⁻¹,
  // not rescaled (the measured covariances set the scale).
  double residual_scale = 0.0;
  double rms_joint_residual = 0.0;  // [rad], unweighted, over all joints of all poses
  // Covariance stage (identification_covariance.hpp, doc/uncertainty.md): which σ is printed.
  // "measured" (weighted, χ² consistent), "residual-scaled" (× covariance_scale2 = χ²/dof: the
  // misfit of a weighted fit, or an unweighted fit), plus "+ shared" once the calibration's
  // shared term is added (shared_covariance).
  std::string covariance_method;
  double covariance_scale2 = 1.0;
  double outlier_scale2 = 1.0;             // scale² of the outlier test (achieved, robust)
  Eigen::MatrixXd information_inverse;     // (AᵀA)⁻¹ of the whitened problem, unscaled
  std::vector<Eigen::MatrixXd> whitening;  // W_j of every pose (4 × 4 for the H4)
  Eigen::MatrixXd shared_covariance;       // G Σ_k Gᵀ when added (else empty)
  // With the shared term by refits: its columns G·√Σ_k (free parameters × n, shared_covariance =
  // columns·columnsᵀ) and the same directions' change of the alignment tilts (4 × n; empty for the
  // full form), so that predictions carry the calibration's error through both jointly.
  Eigen::MatrixXd shared_columns, shared_alignment_columns;
  std::vector<PoseResidual> poses;
  std::vector<std::string> outliers;  // pose ids

  IdentifiabilityReport identifiability;  // at the solution, over the free parameters
  bool converged = false;
  int iterations = 0;
  double solve_seconds = 0.0;
  std::string solver_report;  // Ceres brief report
};

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
