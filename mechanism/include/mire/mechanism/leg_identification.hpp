#pragma once
// Identification with leg observations (doc/legs.md, after Renaud, Andreff, Gogu and Martinet's
// leg-based calibration of the Gough–Stewart platform and the H4): the measured leg axes, the
// measured target poses, or both, in one least-squares problem over the parameters ξ = ξg ∪ ξe and
// one pose X_j per calibration pose (the mechanism's pose components):
//   encoder   (q̄_j − f(X_j, ξg)) / σ_q                     (joints, per pose; σ_q small: a constraint)
//   legs      W_jl · δ(ℓ̂_jl(X_j, ξg, ξe), ℓ_jl)            (4 per observed leg, W = L⁻¹, Σ = L Lᵀ)
//   target    W_j · (cTm(X_j, ξe) ⊖ cT̄m_j)                 (6 per pose, W from the pose covariance)
// where δ is the line difference of support/line_3d.hpp in the measured line's tangent basis and
// ⊖ the translation difference and the rotation log(R̂ R̄ᵀ) (the pose covariance carried onto it).
// With the target only, this is the paper's problem (eq. 4) with X_j made explicit; `identify()`
// (identification.hpp) stays the target-only reference. The covariance of the free parameters is
// the block of the pseudo-inverse of the whitened information over [ξ, X] (the poses marginalised),
// unscaled: the measured covariances set the scale, and χ²/dof says whether they are right.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "mire/mechanism/identifiability.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/leg_observation.hpp"
#include "mire/mechanism/pose.hpp"

namespace mire::mechanism {

enum class Observations { Target, Legs, Both };
std::string observationsName(Observations observations);  // "target", "legs", "both"
// From "target", "legs" or "both"; throws std::invalid_argument naming the accepted values.
Observations parseObservations(const std::string& text);

struct LegIdentificationOptions {
  Observations observations = Observations::Both;
  std::vector<std::string> fix;      // also hold these at their current values
  std::vector<std::string> release;  // free these even if fixed by default
  // Encoder noise in the joints' unit: small, so that the joints tie each X_j to the geometry.
  double joint_sigma = 1e-6;
  int max_iterations = 200;
  // As identify() (doc/uncertainty.md): scale the covariance by χ²/dof when the χ² test at 1e-3
  // (two-sided) rejects the observations' covariances, so that a misfit widens σ.
  bool scale_on_misfit = true;
  bool compute_identifiability = true;
  IdentifiabilityOptions identifiability;
};

struct LegIdentificationResult {
  IdentificationModel model;            // identified values
  std::vector<std::string> free_names;  // covariance order
  Eigen::MatrixXd covariance;           // of the free parameters, poses marginalised, SI
  Eigen::VectorXd sigma;                // per parameter in model.parameters order; 0 if fixed
  double sigmaOf(const std::string& name) const;
  std::vector<Eigen::Isometry3d> bTe;  // identified effector pose per calibration pose
  double chi2 = 0.0;                   // Σ whitened residual²
  int dof = 0;
  double covariance_scale2 = 1.0;  // applied to `covariance` (scale_on_misfit; 1: the χ² test passed)
  int leg_rows = 0, target_rows = 0, joint_rows = 0;
  IdentifiabilityReport identifiability;  // of the free parameters with the poses marginalised
  bool converged = false;
  int iterations = 0;
};

// The base frame in the camera frame from leg observations alone, for mechanisms whose legs start
// at a joint fixed to the base (extensible legs: the hexapod): each leg's base end is the point
// nearest to all its measured lines, and cTb is the rigid fit (Umeyama) of the model's base ends
// to those points. Throws std::invalid_argument when a leg has fewer than two poses, or the legs'
// base ends move with the pose (Delta, H4 forearms: initialise from the target instead).
Eigen::Isometry3d cameraFromBaseByLegs(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                       const std::vector<LegObservation>& legs);

// The model's starting values for a legs-only identification: `geometric` and the Full-form external
// values with cTb from cameraFromBaseByLegs() and eTm at identity (no influence without a target).
IdentificationModel makeLegsInitialModel(std::shared_ptr<const Mechanism> mechanism, const ParameterSet& geometric,
                                         const std::vector<LegObservation>& legs);

// The parameters a legs-only identification cannot see and the gauge it holds (doc/legs.md): the
// target's mounting eTm (6, no influence), the camera mounting cTb (6: the base frame is the
// camera's initial estimate of it) and, for a 6-DoF platform with px1..pz3, six coordinates of the
// first three platform joints (the effector frame). Names of the model's Full-form parameters.
std::vector<std::string> legsOnlyGauge(const IdentificationModel& model);

// Runs the identification from the model's current values (any external form).
// Throws std::invalid_argument on bad input (a pose without joints, unknown names, leg observations
// of an unknown pose, too few residuals) and std::runtime_error where no starting pose is found.
LegIdentificationResult identifyWithLegs(const IdentificationModel& initial, const std::vector<PoseObservation>& poses,
                                         const std::vector<LegObservation>& legs,
                                         const LegIdentificationOptions& options = {});

}  // namespace mire::mechanism
