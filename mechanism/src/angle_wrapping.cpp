// Identified angles in their canonical range (identification.hpp, wrapPeriodicAngles).
#include <cmath>

#include "mire/mechanism/identification.hpp"

namespace mire::mechanism {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The IKM at a few poses around the reference pose: equal joints before and after a change of
// the geometry means the kinematics cannot tell the two apart.
bool sameJoints(const Mechanism& mechanism, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const Eigen::VectorXd reference = mechanism.referencePose(a);
  for (int k = 0; k <= reference.size(); ++k) {
    Eigen::VectorXd pose = reference;
    if (k < reference.size())
      pose[k] += (mechanism.poseComponentUnits()[static_cast<std::size_t>(k)] == Unit::Metre) ? 0.01 : 0.02;
    const Eigen::Isometry3d bTe = mechanism.poseToTransform(pose);
    const IkmResult qa = mechanism.inverseKinematics(a, bTe);
    const IkmResult qb = mechanism.inverseKinematics(b, bTe);
    if (!qa.reachable() || !qb.reachable() || (qa.joints - qb.joints).cwiseAbs().maxCoeff() > 1e-9) return false;
  }
  return true;
}

}  // namespace

std::vector<std::string> wrapPeriodicAngles(IdentificationModel& model, const Eigen::VectorXd& reference) {
  std::vector<std::string> wrapped;
  const Mechanism& mechanism = *model.mechanism;
  for (int i = 0; i < model.geometricCount(); ++i) {
    const Parameter& p = model.parameters[static_cast<std::size_t>(i)];
    if (p.unit != Unit::Radian || std::abs(p.value - reference[i]) <= kPi) continue;
    const Eigen::VectorXd before = model.geometricValues();
    Eigen::VectorXd after = before;
    after[i] = reference[i] + std::remainder(p.value - reference[i], 2.0 * kPi);
    if (!sameJoints(mechanism, before, after)) continue;
    wrapped.push_back(p.name);
    model.parameters.setValue(p.name, after[i]);
  }
  return wrapped;
}

}  // namespace mire::mechanism
