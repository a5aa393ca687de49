#pragma once
// The residual of one calibration pose in the identification with legs (leg_identification.hpp):
// encoder, observed legs and (optionally) the measured target pose, over the blocks [free ξ, X_j],
// differentiated numerically so that every mechanism's legSegments() serves as it is.
#include <Eigen/Core>

#include <memory>
#include <optional>
#include <vector>

#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/leg_observation.hpp"

#include "free_parameter_cost.hpp"

namespace ceres {
class CostFunction;
}

namespace mire::mechanism::detail {

struct LegPoseTerms {
  Eigen::VectorXd joints;                      // q̄
  double joint_sigma = 1e-6;                   // joints' unit
  std::vector<LegObservation> legs;            // observed legs of this pose
  std::vector<Eigen::Matrix4d> leg_whitening;  // L⁻¹ per leg, Σ = L Lᵀ
  std::optional<Eigen::Isometry3d> cTm;        // measured target pose (target observations)
  Eigen::Matrix<double, 6, 6> target_whitening = Eigen::Matrix<double, 6, 6>::Identity();
  int residualCount(int joint_count) const { return joint_count + 4 * static_cast<int>(legs.size()) + (cTm ? 6 : 0); }
};

// The whitening of a measured pose's residual [t̂ − t̄; log(R̂ R̄ᵀ)] from the covariance of its
// PoseVector (t, rotation vector): the rotation-vector block carried onto the rotation log.
Eigen::Matrix<double, 6, 6> targetWhitening(const PoseVector& cTm, const PoseCovariance& covariance);

// Evaluates the terms at ambient values and pose X (no derivatives); false where unreachable.
bool evaluateLegPose(const IdentificationModel& model, const Eigen::VectorXd& ambient, const double* pose,
                     const LegPoseTerms& terms, double* residuals);

std::unique_ptr<ceres::CostFunction> makeLegPoseCost(const IdentificationModel& model,
                                                     std::shared_ptr<const FreeParameterMap> map, LegPoseTerms terms);

}  // namespace mire::mechanism::detail
