#pragma once
// Experiment design for the identification (doc/plan-and-select.md): which N poses to measure
// so that the geometric parameters are best determined, the mounting (external) parameters
// being nuisance parameters. The paper draws random subsets of its 81 poses (§6.2); here the
// poses are chosen from a candidate set by an exchange algorithm on the Fisher information of
// the identification (the Jacobian of eq. 4, whitened by the joint covariance that the pose
// measurement noise induces, Σq = J Σ_cTm Jᵀ, as identify() weights it).
//
// Criterion (all on the Schur complement M_gg − M_ge M_ee⁻¹ M_eg, i.e. the information on the
// geometric parameters once the external ones are estimated too):
//   D: Ds-optimality, maximise log det(M) − log det(M_ee) (= log det of the Schur complement);
//   A: minimise Σ_g σ_g² / σ_g,ref², σ_g,ref² the variance from one "average" candidate pose
//      (the parameters have mixed units: the ratio makes the sum dimensionless);
//   E: maximise the smallest eigenvalue of the Schur complement in the same scaling.
// Exchange: DETMAX (Mitchell 1974) with one-point excursions — add the candidate that improves
// the criterion most, remove the design point whose removal costs least, until the point
// removed is the one just added — started from a greedy sequential design.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism {

// A closed interval [min, max] (SI).
struct Interval {
  double min = 0.0;
  double max = 0.0;
  double width() const { return max - min; }
  double centre() const { return 0.5 * (min + max); }
};

// Where the effector may go, in the base frame. A cylinder is inscribed in the x/y box (axis
// along z_B through the box centre, radius half the smaller side). Rotations: theta for a
// Schoenflies motion; rx, ry, rz (rotation-vector components) for a spatial one; none for a
// translating plate.
struct Workspace {
  enum class Shape { Box, Cylinder };
  Shape shape = Shape::Box;
  Interval x, y, z;                 // [m]
  std::vector<Interval> rotations;  // [rad], one per rotational pose component
  // Margin to the IKM's reach limit (serial singularity) and to the joints' workable range:
  // a candidate is kept only when every pose one "margin" of joint motion away, in every pose
  // direction, is still reachable ([rad] for revolute joints, [m] for prismatic ones).
  double joint_margin = 0.0;
  // Parallel-singularity guard: the smallest singular value of ∂q/∂X (rotations scaled by
  // 0.1 m) must be at least this fraction of the largest.
  double min_jacobian_ratio = 1e-3;
};

// The volume of the simulation protocol (doc/mechanisms.md): H4 ±100 mm in x, y, ±75 mm in z
// around the reference pose, θ ±20°; Delta ±150 mm, z −725..−575 mm; Gough–Stewart ±40 mm,
// ±30 mm in z around home, ±6° per rotation-vector component; joint margin 1° / 1 mm.
Workspace protocolWorkspace(const Mechanism& mechanism, const Eigen::VectorXd& geometric);

// Rejects a workspace whose rotation count does not match the mechanism, or an empty interval.
void validateWorkspace(const Workspace& workspace, const Mechanism& mechanism);

// Uniformly drawn poses (mechanism pose components) inside the workspace that pass the
// reachability / margin checks, reproducible for a seed. Throws std::runtime_error when fewer
// than `count` are found in 50·count draws (the message says how many were kept).
std::vector<Eigen::VectorXd> generateCandidatePoses(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                                    const Workspace& workspace, int count, unsigned seed);
// Whether one pose passes the checks of generateCandidatePoses().
bool candidateAcceptable(const Mechanism& mechanism, const Eigen::VectorXd& geometric, const Workspace& workspace,
                         const Eigen::VectorXd& pose);

// The mounting guess: where the camera and the target are. Camera fixed (the default):
// bTc and mTe, cTm = bTc⁻¹ · bTe · mTe⁻¹. Camera on the effector (doc/mechanisms.md
// "Camera on the effector"): eTc and bTm, cTm = eTc⁻¹ · bTe⁻¹ · bTm.
struct MountingGuess {
  bool camera_on_effector = false;
  Eigen::Isometry3d bTc = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d mTe = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d eTc = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d bTm = Eigen::Isometry3d::Identity();
  // The target pose the camera sees with the effector at bTe.
  Eigen::Isometry3d targetInCamera(const Eigen::Isometry3d& bTe) const;
};
// Camera fixed: a camera 0.8 m beyond the workspace on its z axis, looking at it (below for a
// robot whose workspace is under its base, above otherwise), the target at the effector origin
// facing it. Camera on the effector: the same view at the workspace centre seen the other way
// round, the camera at the effector origin looking away from the base (a half turn about x) and
// the target fixed 0.8 m beyond the workspace, facing it.
MountingGuess defaultMountingGuess(const Workspace& workspace, bool camera_on_effector = false);

enum class DesignCriterion { D, A, E };
std::string designCriterionName(DesignCriterion criterion);  // "D", "A", "E"

// The model whose parameters are to be determined: the registry entry (its geometry set to the
// nominal values) and, for the H4, the model-12 nominal geometry (variants need it).
struct DesignModel {
  RegisteredModel registered;
  H4Nominal h4;
};

// The initial model `mire identify --model <name>` builds from these observations: mounting
// from the data (makeInitialModel, or variant H's route for h4-31c), gauge fixed (fixGauge).
IdentificationModel initialModelFor(const DesignModel& model, const std::vector<PoseObservation>& observations);

// The registry entry with the nominal geometry: for the H4 models from the model-12 values `h4`.
DesignModel makeDesignModel(const std::string& name, const H4Nominal& h4 = {});

// The model with the camera on the effector: its external form becomes CameraOnEffector (eTc,
// bTm), as `mire identify --mounting camera-on-effector` identifies it. Throws
// std::invalid_argument "<name> (<form> mounting) assumes the camera fixed (paper §4)" for a
// model whose form is not the full one (the H4's axis-aligned and camera-frame forms).
DesignModel withCameraOnEffector(DesignModel model);

struct DesignOptions {
  DesignCriterion criterion = DesignCriterion::D;
  int count = 15;  // N poses to choose
  // Pose measurement noise (per component of cTm) used when a candidate has no covariance.
  double sigma_translation = 0.2e-3;                    // [m]
  double sigma_rotation = 0.03 * support::kPi / 180.0;  // [rad]
  int random_designs = 50;                              // random N-subsets drawn for the comparison
  unsigned seed = 1;
  int max_exchanges = 500;
};

// The candidate set as the identification sees it: per candidate the whitened Jacobian rows
// of eq. 4 over the free parameters (W·∂ε/∂ξ, jointCount() rows).
struct CandidateInformation {
  IdentificationModel model;                  // nominal geometry, mounting from the guess, gauge fixed
  std::vector<std::string> free_names;        // columns, geometric free names first
  int geometric_free = 0;                     // the first ones are geometric
  std::vector<Eigen::VectorXd> poses;         // mechanism pose components
  std::vector<PoseObservation> observations;  // noise-free cTm and nominal IKM joints
  std::vector<Eigen::MatrixXd> rows;          // whitened Jacobian per candidate
  // The calibration error shared by every pose (SharedTermModel), when given: Σ_k (n × n) and
  // per candidate its whitened joint-space rows R_j = W_j·∂q/∂cTm·D_j (jointCount() × n).
  Eigen::MatrixXd shared_covariance;
  std::vector<Eigen::MatrixXd> shared_rows;
  bool hasSharedTerm() const { return !shared_rows.empty(); }
};

// Per-candidate pose covariance of cTm (e.g. from the camera model); empty: the options' σ.
using PoseCovarianceProvider = std::function<std::optional<PoseCovariance>(const PoseVector& cTm)>;

// The error every pose of the campaign will share: the camera calibration's, Σ_k over its
// parameters k, entering each pose through D = ∂cTm/∂k (6 × n, rows tx ty tz rx ry rz), as
// `mire identify` receives it from `mire measure` (identification_covariance.hpp,
// SharedPoseTerm). The per-candidate covariances should then include D Σ_k Dᵀ, as measure's do.
struct SharedTermModel {
  Eigen::MatrixXd covariance;                                     // Σ_k
  std::function<Eigen::MatrixXd(const PoseVector&)> sensitivity;  // D at a pose cTm
  bool empty() const { return covariance.size() == 0 || !sensitivity; }
};

// Builds the model (mounting initialised as identify() would from noise-free data at the
// nominal geometry; gauge fixed by analyzeGauge), then the whitened Jacobian of every candidate
// (and, with `shared`, the candidates' shared rows; throws std::invalid_argument when a
// sensitivity is not 6 × n, or when the model's external form and the guess disagree on where
// the camera is: ExternalForm::CameraOnEffector goes with camera_on_effector).
CandidateInformation candidateInformation(const DesignModel& model, const MountingGuess& mounting,
                                          const std::vector<Eigen::VectorXd>& poses, const DesignOptions& options,
                                          const PoseCovarianceProvider& covariance = {},
                                          const SharedTermModel& shared = {});

// Fisher information Σ_j AᵀA over the given candidates (free-parameter order).
Eigen::MatrixXd fisherInformation(const CandidateInformation& info, const std::vector<int>& design);
// Covariance of the free parameters for a design: the inverse of its information
// (pseudo-inverse when singular; σ of a parameter without information is +∞). With the shared
// term, what `mire identify` reports with it (identification_covariance.hpp): the fit's term
// from the independent part, H⁻¹ − H⁻¹ B H⁻¹ with B = Σ_j A_jᵀ R_j Σ_k R_jᵀ A_j, plus the
// shared error once, G Σ_k Gᵀ with G = H⁻¹ Σ_j A_jᵀ R_j — a floor that more poses do not lower.
Eigen::MatrixXd designCovariance(const CandidateInformation& info, const std::vector<int>& design);
Eigen::VectorXd designSigma(const CandidateInformation& info, const std::vector<int>& design);
// The shared term's part alone, G Σ_k Gᵀ (zero without the shared term).
Eigen::MatrixXd designSharedCovariance(const CandidateInformation& info, const std::vector<int>& design);

// Chooses `options.count` distinct candidates (indices into info.poses). Throws
// std::invalid_argument when count exceeds the candidates or is too small to determine the
// parameters (count·jointCount() < free parameters).
std::vector<int> chooseDesign(const CandidateInformation& info, const DesignOptions& options);

// Predicted effector position σ after identification at `poses` (mechanism pose components):
// the geometric covariance (the geometric block of designCovariance) propagated through the
// FKM, ∂X/∂ξg = −(∂q/∂X)⁺·∂q/∂ξg, with the rigid motion common to all `poses` projected out
// (a choice of base frame); per pose √trace of the position covariance [m].
std::vector<double> predictedPositionSigma(const CandidateInformation& info, const Eigen::MatrixXd& covariance,
                                           const std::vector<int>& poses);

// Everything `mire plan` reports.
struct DesignReport {
  DesignCriterion criterion = DesignCriterion::D;
  std::vector<int> design;         // chosen candidate indices, in order of choice
  std::vector<std::string> names;  // free parameters
  std::vector<Unit> units;
  int geometric_free = 0;
  Eigen::VectorXd sigma_plan;  // per free parameter [SI]
  // The part of sigma_plan from the calibration error shared by every pose, √diag(G Σ_k Gᵀ)
  // (empty without the shared term).
  Eigen::VectorXd sigma_plan_shared;
  Eigen::VectorXd sigma_random;  // median over the random designs of the same size
  Eigen::VectorXd sigma_all;     // the whole candidate set
  // median over the geometric parameters of σ_plan/σ_random: < 1 when the plan is better.
  double median_ratio_plan_random = 0.0;
  double position_sigma_plan_rms = 0.0;    // [m], RMS over evaluation poses
  double position_sigma_random_rms = 0.0;  // [m], median over random designs
  double position_sigma_plan_max = 0.0;
  int random_designs_used = 0;
  double seconds = 0.0;  // time to choose the design
};

DesignReport planExperiment(const CandidateInformation& info, const DesignOptions& options);
// Human summary (σ in mm / deg).
std::string designReportText(const DesignReport& report);

}  // namespace mire::mechanism
