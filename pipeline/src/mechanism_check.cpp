// `mire check-mechanism` (mechanism_check.hpp).
#include "mire/pipeline/mechanism_check.hpp"

#include "mire/datasets/mechanism_campaign.hpp"

#include <Eigen/SVD>

#include <cmath>
#include <limits>
#include <sstream>

namespace mire::pipeline {
namespace mech = mire::mechanism;

namespace {

std::string legList(const std::vector<int>& joints) {
  std::string list;
  for (const int j : joints) list += (list.empty() ? "" : ", ") + std::to_string(j + 1);
  return list;
}

// ∂q/∂X at pose X by central differences through poseToTransform, so that every mechanism (its
// pose components in metres and radians) is checked the same way; empty when a step leaves the
// workspace.
Eigen::MatrixXd jointJacobianAtPose(const mech::Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                    const Eigen::VectorXd& X) {
  const double step = 1e-6;
  Eigen::MatrixXd jacobian(mechanism.jointCount(), X.size());
  for (Eigen::Index k = 0; k < X.size(); ++k) {
    Eigen::VectorXd plus = X, minus = X;
    plus[k] += step;
    minus[k] -= step;
    const mech::IkmResult a = mechanism.inverseKinematics(geometric, mechanism.poseToTransform(plus));
    const mech::IkmResult b = mechanism.inverseKinematics(geometric, mechanism.poseToTransform(minus));
    if (!a.reachable() || !b.reachable()) return {};
    jacobian.col(k) = (a.joints - b.joints) / (2 * step);
  }
  return jacobian;
}

// Condition number of J with unit-norm columns (unit-invariant, as the identifiability
// analysis scales its Jacobian); infinite for a zero column or a rank loss.
double scaledCondition(Eigen::MatrixXd jacobian) {
  for (Eigen::Index k = 0; k < jacobian.cols(); ++k) {
    const double norm = jacobian.col(k).norm();
    if (!(norm > 0)) return std::numeric_limits<double>::infinity();
    jacobian.col(k) /= norm;
  }
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(jacobian).singularValues();
  return s[s.size() - 1] > 0 ? s[0] / s[s.size() - 1] : std::numeric_limits<double>::infinity();
}

// The legs that do not assemble a little away from X (±1 mm along each position component, ±1°
// about each rotation one): a home at the edge of a leg's reach, where its rod is stretched
// straight or its two branches meet (a serial singularity), cannot host a campaign.
std::vector<int> legsAtTheirReachLimit(const mech::Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                       const Eigen::VectorXd& X) {
  std::vector<bool> limited(static_cast<std::size_t>(mechanism.jointCount()), false);
  const std::vector<mech::Unit> units = mechanism.poseComponentUnits();
  for (Eigen::Index k = 0; k < X.size(); ++k)
    for (const double sign : {-1.0, 1.0}) {
      Eigen::VectorXd moved = X;
      moved[k] += sign * (units[static_cast<std::size_t>(k)] == mech::Unit::Radian ? 0.01745 : 1e-3);
      for (const int j : mechanism.inverseKinematics(geometric, mechanism.poseToTransform(moved)).unreachable_joints)
        limited[static_cast<std::size_t>(j)] = true;
    }
  std::vector<int> legs;
  for (std::size_t j = 0; j < limited.size(); ++j)
    if (limited[j]) legs.push_back(static_cast<int>(j));
  return legs;
}

void checkSingularity(const mech::Mechanism& mechanism, const Eigen::VectorXd& geometric,
                      const MechanismCheckOptions& options, MechanismCheck& check) {
  const Eigen::MatrixXd jacobian = jointJacobianAtPose(mechanism, geometric, check.home);
  check.home_condition = jacobian.size() ? scaledCondition(jacobian) : std::numeric_limits<double>::infinity();
  std::ostringstream condition;
  condition << "the home pose is " << (check.home_condition >= options.singular_condition ? "" : "near ")
            << "a singularity of the platform (condition number of dq/dX " << check.home_condition << ")";
  if (check.home_condition >= options.singular_condition)
    check.errors.push_back(condition.str() + ": the joints cannot determine the pose there");
  else if (check.home_condition >= options.near_singular_condition)
    check.warnings.push_back(condition.str() + ": the FKM and the identification lose precision around it");
}

void checkHome(const mech::Mechanism& mechanism, const Eigen::VectorXd& geometric, const MechanismCheckOptions& options,
               MechanismCheck& check) {
  check.home = mechanism.referencePose(geometric);
  const mech::IkmResult ikm = mechanism.inverseKinematics(geometric, mechanism.poseToTransform(check.home));
  check.home_joints = ikm.joints;
  if (!ikm.reachable()) {
    check.errors.push_back("the home pose does not assemble: leg(s) " + legList(ikm.unreachable_joints) +
                           " have no solution on their branch there (a rod too short or too long for the distance "
                           "from its actuator to its platform joint; check base, platform, rod and branch, or "
                           "give a `home:` every leg reaches)");
    return;
  }
  if (!ikm.withinStroke())
    check.errors.push_back("the home pose is outside the stroke of leg(s) " + legList(ikm.out_of_stroke_joints));
  const std::vector<int> limited = legsAtTheirReachLimit(mechanism, geometric, check.home);
  if (!limited.empty()) {
    check.errors.push_back("the home pose is at the edge of the reach of leg(s) " + legList(limited) +
                           ": within 1 mm or 1 degree of it they do not assemble (a rod stretched straight, or "
                           "the leg's two branches meeting); move `home:` or change the rods");
    return;
  }
  checkSingularity(mechanism, geometric, options, check);
  // The FKM from the home readings, started 0.5 mm away, must come back: a branch that
  // assembles the platform in another mode sends it elsewhere.
  Eigen::VectorXd start = check.home;
  start.head(3).array() += 0.5e-3;
  const mech::FkmResult fkm = mechanism.forwardKinematics(geometric, ikm.joints, start);
  if (!fkm.converged || (fkm.pose - check.home).norm() > 1e-6)
    check.errors.push_back("the FKM from the home readings does not return to the home pose (" +
                           (fkm.converged ? std::string("it converges elsewhere") : fkm.message) +
                           "): the platform assembles in another mode there");
}

// The protocol poses (datasets/mechanism_campaign.hpp) that simulate campaign, plan and the
// demos use, at the nominal geometry; those reachable within the strokes.
std::vector<Eigen::Isometry3d> reachableProtocol(const mech::Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                                 MechanismCheck& check) {
  std::vector<Eigen::Isometry3d> reachable;
  const std::vector<Eigen::Isometry3d> protocol = datasets::protocolPoses(mechanism, geometric);
  for (const Eigen::Isometry3d& bTe : protocol) {
    const mech::IkmResult ikm = mechanism.inverseKinematics(geometric, bTe);
    if (ikm.reachable() && ikm.withinStroke()) reachable.push_back(bTe);
  }
  check.protocol_poses = static_cast<int>(protocol.size());
  check.protocol_scale = datasets::protocolScale(mechanism, geometric, mechanism.referencePose(geometric));
  check.protocol_reachable = static_cast<int>(reachable.size());
  if (reachable.size() < protocol.size())
    check.warnings.push_back(std::to_string(protocol.size() - reachable.size()) + " of the " +
                             std::to_string(protocol.size()) +
                             " protocol poses around home are out of reach: `mire simulate campaign` and the "
                             "demos need them all; plan a campaign with `mire plan --candidates`");
  return reachable;
}

// An exact-model campaign at `protocol` (the camera and target placed as simulateCampaign places
// them), noise-free so that the analysis sees the model alone.
std::vector<mech::PoseObservation> exactCampaign(const mech::Mechanism& mechanism, const Eigen::VectorXd& geometric,
                                                 const std::vector<Eigen::Isometry3d>& protocol) {
  const auto [bTc, mTe] = datasets::campaignMountings(mechanism);
  const double t = 0.2e-3, r = 0.03 * datasets::kCampaignDeg;
  mech::PoseCovariance covariance = mech::PoseCovariance::Zero();
  covariance.diagonal() << t * t, t * t, t * t, r * r, r * r, r * r;
  std::vector<mech::PoseObservation> poses;
  for (const Eigen::Isometry3d& bTe : protocol) {
    mech::PoseObservation pose;
    pose.id = std::to_string(poses.size() + 1);
    pose.joints = mechanism.inverseKinematics(geometric, bTe).joints;
    pose.cTm = mech::toPoseVector(bTc.inverse() * bTe * mTe.inverse());
    pose.covariance = covariance;
    poses.push_back(pose);
  }
  return poses;
}

void checkIdentifiability(const ModelChoice& choice, const std::vector<mech::PoseObservation>& poses,
                          MechanismCheck& check) {
  try {
    const InitialModel initial = initialModel(choice, poses);
    check.gauge = initial.gauge ? *initial.gauge : mech::analyzeGauge(initial.model, poses);
    // The counts before the gauge was held: the analysis's columns.
    for (const std::string& name : check.gauge->report.parameter_names)
      ++(initial.model.parameters.index(name) < static_cast<std::size_t>(initial.model.geometricCount())
             ? check.geometric_free
             : check.external_free);
  } catch (const std::exception& error) {
    check.errors.push_back(std::string("the identifiability analysis failed on an exact-model campaign: ") + error.what());
  }
}

}  // namespace

MechanismCheck checkMechanism(const ModelChoice& choice, const MechanismCheckOptions& options) {
  const mech::RegisteredModel model = choice.registered();
  const mech::Mechanism& mechanism = *model.mechanism;
  const Eigen::VectorXd geometric = model.nominal.values();
  MechanismCheck check;
  check.label = choice.label();
  check.joints = mechanism.jointCount();
  check.pose_dof = mechanism.poseDof();
  checkHome(mechanism, geometric, options, check);
  if (!check.ok()) return check;
  const std::vector<Eigen::Isometry3d> protocol = reachableProtocol(mechanism, geometric, check);
  if (static_cast<int>(protocol.size()) < 3) {
    check.errors.push_back("fewer than 3 protocol poses around home are reachable: no campaign can be simulated");
    return check;
  }
  checkIdentifiability(choice, exactCampaign(mechanism, geometric, protocol), check);
  return check;
}

}  // namespace mire::pipeline
