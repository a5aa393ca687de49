#pragma once
// `mire plan --camera camera.yaml --target target.yaml` (doc/plan-and-select.md, "--camera"):
// the candidates where the target would not be seen whole, or too obliquely, are excluded
// before the design is chosen, and every remaining candidate is weighted by the pose
// covariance `measure` will deliver there (metrology/pose_prediction.hpp).
#include <filesystem>
#include <string>
#include <vector>

#include "mire/calibration/camera_model.hpp"
#include "mire/mechanism/experiment_design.hpp"
#include "mire/metrology/pose_prediction.hpp"
#include "mire/metrology/target.hpp"

namespace mire::pipeline {

struct CameraPlanOptions {
  metrology::VisibilityOptions visibility;
  metrology::PredictionOptions prediction;
};

// The candidates split by what the camera sees.
struct CameraCandidates {
  std::vector<Eigen::VectorXd> visible;  // mechanism pose components, in the input's order
  int outside = 0;                       // a feature or the board's outline not (well) inside the image
  int oblique = 0;                       // tilt beyond the limit
  std::string example_reason;            // the first exclusion's reason, for messages
};

// cTm at a mechanism pose with the mounting guess: bTc⁻¹ · bTe · mTe⁻¹, or eTc⁻¹ · bTe⁻¹ · bTm
// with the camera on the effector (MountingGuess::targetInCamera).
Eigen::Isometry3d plannedCameraTMarker(const mechanism::Mechanism& mechanism, const mechanism::MountingGuess& mounting,
                                       const Eigen::VectorXd& pose);

CameraCandidates visibleCandidates(const mechanism::Mechanism& mechanism, const mechanism::MountingGuess& mounting,
                                   const calibration::Camera& camera, const metrology::Target& target,
                                   const std::vector<Eigen::VectorXd>& poses, const CameraPlanOptions& options);

// What mechanism::candidateInformation needs from the camera: the per-candidate covariance of
// cTm and, when the camera file carries a covariance, the calibration's error shared by every
// pose (Camera::covariance and each pose's ∂cTm/∂k; empty otherwise). Both come from one
// prediction per pose, kept for the second question (the calls are sequential).
struct CameraPoseModel {
  mechanism::PoseCovarianceProvider covariance;
  mechanism::SharedTermModel shared;
};
CameraPoseModel cameraPoseModel(const calibration::Camera& camera, const metrology::Target& target,
                                const CameraPlanOptions& options);

using PoseSigma = Eigen::Matrix<double, 6, 1>;

// What `mire plan` reports on the camera.
struct CameraPlanSummary {
  CameraPlanOptions options;
  std::size_t drawn = 0;          // candidates drawn in the workspace
  std::size_t visible = 0;        // of them, visible
  int outside = 0, oblique = 0;   // excluded
  std::vector<PoseSigma> sigmas;  // per planned pose
  bool shared_term = false;       // the camera's covariance is in the parameters' σ, once
};

// Predicted σ of cTm at each planned pose: tx ty tz [m], rx ry rz [rad] (total, as poses.csv's
// sigma_ columns); NaN when the pose is not observable.
std::vector<PoseSigma> plannedPoseSigmas(const mechanism::CandidateInformation& info, const std::vector<int>& design,
                                         const calibration::Camera& camera, const metrology::Target& target,
                                         const CameraPlanOptions& options);

// The report's lines on the camera: the exclusions and the predicted σ per planned pose (mm, deg).
std::string cameraPlanText(const CameraPlanSummary& summary);

}  // namespace mire::pipeline
