// Leg observations and the model's prediction of them (leg_observation.hpp, doc/legs.md).
#include "mire/mechanism/leg_observation.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <stdexcept>

namespace mire::mechanism {

support::Line3d predictedLegLine(const Mechanism& mechanism, const ExternalParameterization& external,
                                 const Eigen::VectorXd& geometric, const Eigen::VectorXd& external_values,
                                 const Eigen::Isometry3d& bTe, int leg) {
  const std::vector<LegSegment> segments = mechanism.legSegments(geometric, bTe);
  if (leg < 0 || leg >= static_cast<int>(segments.size()))
    throw std::runtime_error(mechanism.name() + ": leg " + std::to_string(leg + 1) + " has no segment at this pose");
  const LegSegment& s = segments[static_cast<std::size_t>(leg)];
  const Eigen::Isometry3d cTb = external.baseFromCamera(external_values).inverse();
  return support::Line3d::throughPoints(cTb * s.from, cTb * s.to);
}

void validateLegObservations(const std::vector<LegObservation>& legs, int leg_count) {
  for (const LegObservation& o : legs) {
    const std::string where = "pose '" + o.pose_id + "', leg " + std::to_string(o.leg + 1);
    if (o.leg < 0 || o.leg >= leg_count)
      throw std::invalid_argument(where + ": the mechanism has " + std::to_string(leg_count) + " observable legs");
    if (!o.line.direction.allFinite() || !o.line.moment.allFinite() || !o.covariance.allFinite())
      throw std::invalid_argument(where + ": a value is not finite");
    if (std::abs(o.line.direction.norm() - 1.0) > 1e-6)
      throw std::invalid_argument(where + ": the direction d is not a unit vector");
    if (std::abs(o.line.direction.dot(o.line.moment)) > 1e-6 * std::max(1.0, o.line.moment.norm()))
      throw std::invalid_argument(where + ": the moment m is not perpendicular to d");
    if (!o.covariance.isApprox(o.covariance.transpose(), 1e-9) ||
        Eigen::LLT<Eigen::Matrix4d>(o.covariance).info() != Eigen::Success)
      throw std::invalid_argument(where + ": the covariance is not symmetric positive definite");
  }
}

}  // namespace mire::mechanism
