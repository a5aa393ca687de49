#pragma once
// Evaluation of an identification (paper §6; doc/mechanisms.md, "Evaluation criteria"):
//  V1 mean joint residual on validation poses (eq. 27), V2 its RMS (eq. 28),
//  V3 straightness of two straight-line motions rebuilt with the model's numerical FKM
//  (eq. 29), the square side errors of paper §6.4 (Table 4), and the Monte-Carlo study of
//  paper §6.2 (random pose subsets identified many times, the other poses validate).
#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/pose.hpp"

namespace mire::mechanism {

// ---- V1, V2 -----------------------------------------------------------------------------
struct JointResidualCriteria {
  double v1_rad = 0.0;                   // eq. 27: (1/4N) Σ (q̄ − f), signed mean over all joints
  double v2_rad = 0.0;                   // eq. 28: √((1/4N) Σ (q̄ − f)²)
  int pose_count = 0;                    // validation poses used (reachable ones)
  std::vector<std::string> unreachable;  // ids skipped because the IKM fails there
};
// Residuals q̄ − f(X(ξe, cTm), ξg) at the model's current values.
JointResidualCriteria jointResidualCriteria(const IdentificationModel& model,
                                            const std::vector<PoseObservation>& validation);

// ---- V3 ---------------------------------------------------------------------------------
// The least-squares 3-D line of points: through their centroid along the principal axis of their
// scatter (largest eigenvalue). Needs ≥ 2 points.
struct FittedLine {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  Eigen::Vector3d direction = Eigen::Vector3d::UnitX();  // unit
  Eigen::Vector3d projection(const Eigen::Vector3d& p) const {
    return centroid + (p - centroid).dot(direction) * direction;
  }
  double distance(const Eigen::Vector3d& p) const { return (p - projection(p)).norm(); }
};
FittedLine fitLine(const std::vector<Eigen::Vector3d>& points);

// RMS distance of points to their least-squares 3-D line: the straightness R of paper §6.1.
// Needs ≥ 2 points.
double straightness(const std::vector<Eigen::Vector3d>& points);

struct StraightnessResult {
  std::vector<double> per_line_m;                    // R of each line
  double v3_m = 0.0;                                 // eq. 29: mean over the lines
  std::vector<std::vector<Eigen::Vector3d>> points;  // rebuilt effector positions
  bool ok = true;                                    // false when the FKM failed somewhere
  std::string message;
};
// Rebuilds the effector positions of every recorded joint vector with the numerical FKM of
// `mechanism` at `geometric` (warm-started along each line from referencePose()), then V3.
StraightnessResult straightnessCriterion(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                         const std::vector<std::vector<Eigen::VectorXd>>& line_joints);

// ---- square test (paper §6.4) -------------------------------------------------------------
// Encoder readings a controller running `mechanism` at `geometric` commands for each pose
// (the model's IKM at poseToTransform(pose)); throws naming the pose when unreachable.
std::vector<Eigen::VectorXd> commandJoints(const Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                           const std::vector<Eigen::VectorXd>& poses);
// Corners (x, y, z, θ = 0) of a `side` square at constant z centred on `centre`, in order.
std::vector<Eigen::VectorXd> squareCorners(const Eigen::Vector3d& centre, double side);
// Side errors (m): ‖c_{k+1} − c_k‖ in the (x, y) plane minus `side`, for reached corners.
std::vector<double> squareSideErrors(const std::vector<Eigen::Vector3d>& reached_corners, double side);

// ---- Monte-Carlo study (paper §6.2) -------------------------------------------------------
struct MonteCarloOptions {
  std::vector<int> subset_sizes{6, 15, 71};
  int repeats = 100;
  std::uint64_t seed = 1;
  int threads = 2;                       // std::thread workers; results do not depend on it
  IdentificationOptions identification;  // compute_identifiability is forced off per run
  // Called after every identification (from worker threads): e.g. Progress::advance.
  std::function<void()> on_run_done;
};

struct MonteCarloRun {
  std::vector<std::string> subset;  // pose ids identified on
  bool ok = false;
  std::string error;
  Eigen::VectorXd values;             // all parameters, model order
  double v1_rad = 0.0, v2_rad = 0.0;  // on the other poses
  double v3_m = 0.0;                  // NaN without lines or when the FKM failed
};

struct MonteCarloSummary {
  int subset_size = 0;
  int runs_ok = 0, runs_failed = 0;
  Eigen::VectorXd mean, sigma;  // of every parameter (model order), sample σ (n − 1)
  double v1_mean = 0, v1_sigma = 0, v2_mean = 0, v2_sigma = 0, v3_mean = 0, v3_sigma = 0;
  std::vector<MonteCarloRun> runs;
};

struct MonteCarloStudy {
  std::vector<std::string> parameter_names;
  std::vector<MonteCarloSummary> summaries;  // one per subset size
  double seconds = 0.0;
};

// For each subset size, `repeats` subsets drawn without replacement (from `seed`, before any
// work starts, so the result is deterministic whatever the thread count), each identified
// from `initial`'s values; the remaining poses give V1, V2 and `line_joints` (may be empty)
// V3. Throws std::invalid_argument when a size is < 1 or ≥ the pose count.
MonteCarloStudy runMonteCarloStudy(const IdentificationModel& initial, const std::vector<PoseObservation>& poses,
                                   const std::vector<std::vector<Eigen::VectorXd>>& line_joints,
                                   const MonteCarloOptions& options);

}  // namespace mire::mechanism
