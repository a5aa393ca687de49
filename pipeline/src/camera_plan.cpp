#include "mire/pipeline/camera_plan.hpp"

#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <sstream>

#include "mire/mechanism/pose.hpp"
#include "mire/metrology/pose_estimation.hpp"
#include "mire/support/constants.hpp"

namespace mire::pipeline {
namespace {

namespace mech = mire::mechanism;
using support::kPi;

}  // namespace

Eigen::Isometry3d plannedCameraTMarker(const mech::Mechanism& mechanism, const mech::MountingGuess& mounting,
                                       const Eigen::VectorXd& pose) {
  return mounting.targetInCamera(mechanism.poseToTransform(pose));
}

CameraCandidates visibleCandidates(const mech::Mechanism& mechanism, const mech::MountingGuess& mounting,
                                   const calibration::Camera& camera, const metrology::Target& target,
                                   const std::vector<Eigen::VectorXd>& poses, const CameraPlanOptions& options) {
  CameraCandidates result;
  for (const Eigen::VectorXd& pose : poses) {
    const metrology::Visibility v =
        metrology::targetVisibility(camera, target, plannedCameraTMarker(mechanism, mounting, pose), options.visibility);
    if (v.visible) {
      result.visible.push_back(pose);
      continue;
    }
    // The tilt is only tested once the target is inside the image.
    const bool oblique = v.tilt_deg > options.visibility.max_tilt_deg;
    ++(oblique ? result.oblique : result.outside);
    if (result.example_reason.empty()) result.example_reason = v.reason;
  }
  return result;
}

CameraPoseModel cameraPoseModel(const calibration::Camera& camera, const metrology::Target& target,
                                const CameraPlanOptions& options) {
  using Key = std::array<double, 6>;
  auto predictions = std::make_shared<std::map<Key, metrology::PosePrediction>>();
  const auto predict = [camera, points = target.points(), prediction = options.prediction,
                        predictions](const mech::PoseVector& cTm) -> const metrology::PosePrediction& {
    const Key key{cTm[0], cTm[1], cTm[2], cTm[3], cTm[4], cTm[5]};
    const auto found = predictions->find(key);
    if (found != predictions->end()) return found->second;
    return predictions->emplace(key, metrology::predictPoseCovariance(camera, points, mech::toIsometry(cTm), prediction))
        .first->second;
  };
  CameraPoseModel model;
  model.covariance = [predict](const mech::PoseVector& cTm) -> std::optional<mech::PoseCovariance> {
    const metrology::PosePrediction& p = predict(cTm);
    if (!p.valid) return std::nullopt;
    return mech::PoseCovariance(p.covariance);
  };
  if (camera.covariance.size() == 0) return model;
  model.shared.covariance = camera.covariance;
  model.shared.sensitivity = [predict, n = camera.covariance.rows()](const mech::PoseVector& cTm) -> Eigen::MatrixXd {
    const metrology::PosePrediction& p = predict(cTm);
    // Not observable: the candidate carries no information either (no rows), so no shared part.
    return p.valid ? p.intrinsics_sensitivity : Eigen::MatrixXd::Zero(6, n);
  };
  return model;
}

std::vector<PoseSigma> plannedPoseSigmas(const mech::CandidateInformation& info, const std::vector<int>& design,
                                         const calibration::Camera& camera, const metrology::Target& target,
                                         const CameraPlanOptions& options) {
  std::vector<PoseSigma> sigmas;
  for (const int j : design) {
    const mech::PoseVector& cTm = info.observations[static_cast<std::size_t>(j)].cTm;
    const metrology::PosePrediction p =
        metrology::predictPoseCovariance(camera, target.points(), mech::toIsometry(cTm), options.prediction);
    sigmas.push_back(p.valid ? metrology::PoseEstimate::sigmas(p.covariance)
                             : PoseSigma::Constant(std::numeric_limits<double>::quiet_NaN()));
  }
  return sigmas;
}

std::string cameraPlanText(const CameraPlanSummary& summary) {
  const CameraPlanOptions& options = summary.options;
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof line,
                "camera: %zu of %zu candidates visible (%d outside the image or its %.3g px margin, %d tilted "
                "beyond %.3g deg)\n",
                summary.visible, summary.drawn, summary.outside, options.visibility.margin_px, summary.oblique,
                options.visibility.max_tilt_deg);
  out << line;
  const metrology::PredictionOptions& p = options.prediction;
  if (p.systematic_model == metrology::SystematicModel::Constant)
    std::snprintf(line, sizeof line,
                  "pose noise: %.3g px per feature per image, %d images per pose, %.3g px systematic "
                  "(feature sigma %.3g px)\n",
                  p.pixel_sigma, p.images, p.systematic_px, p.featureSigma());
  else
    std::snprintf(line, sizeof line,
                  "pose noise: %.3g px per feature per image, %d images per pose, systematic (%.3g + %.3g cos 4a) "
                  "x %.3g px / s px (s: projected square, a: its edges' angle to the pixel rows)\n",
                  p.pixel_sigma, p.images, p.systematic_mean_px, p.systematic_grid_px, p.reference_square_px);
  out << line
      << (summary.shared_term ? "camera calibration error: in every pose's sigma below, and in the parameters' "
                                "sigma once, as the error all poses share\n"
                              : "camera calibration error: not included (the camera file carries no covariance)\n");
  out << "predicted pose sigma per planned pose (tx ty tz mm, rx ry rz deg):\n";
  for (std::size_t k = 0; k < summary.sigmas.size(); ++k) {
    const PoseSigma& s = summary.sigmas[k];
    std::snprintf(line, sizeof line, "  p%03zu  %.4f %.4f %.4f  %.5f %.5f %.5f\n", k + 1, s[0] * 1e3, s[1] * 1e3,
                  s[2] * 1e3, s[3] * 180.0 / kPi, s[4] * 180.0 / kPi, s[5] * 180.0 / kPi);
    out << line;
  }
  return out.str();
}

}  // namespace mire::pipeline
