// The simulated true robots (mechanism_true_robots.hpp): readings, poses and their draws.
#include "mire/datasets/mechanism_true_robots.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <random>
#include <stdexcept>

namespace mire::datasets {

Eigen::Isometry3d TrueRobot::effector(const Eigen::VectorXd& X) const {
  if (h4) return h4->baseTEffector(H4Pose(X));
  Eigen::Isometry3d T = mechanism().poseToTransform(X);
  if (mechanism().motionType() == MotionType::Translation) {
    const Eigen::Vector3d omega = tilt_per_m * Eigen::Vector3d::UnitZ().cross(X.head<3>() - level_pose);
    if (omega.norm() > 0) T.linear() = Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix();
  }
  return T;
}

Eigen::VectorXd TrueRobot::joints(const Eigen::VectorXd& X) const {
  if (h4) {
    const std::optional<H4Joints> q = h4->joints(H4Pose(X));
    return q ? Eigen::VectorXd(*q) : Eigen::VectorXd();
  }
  const Eigen::Isometry3d T = mechanism().poseToTransform(X);
  if (mechanism().motionType() == MotionType::Translation) {
    const IkmResult ikm = mechanism().inverseKinematics(geometry.values(), T);
    return ikm.reachable() && ikm.withinStroke() ? bentReadings(ikm.joints) : Eigen::VectorXd();
  }
  if (encoder_gain.empty()) {  // a described full platform
    const IkmResult ikm = mechanism().inverseKinematics(geometry.values(), T);
    return ikm.reachable() && ikm.withinStroke() ? bentReadings(ikm.joints) : Eigen::VectorXd();
  }
  // The hexapod's legs stop at their strokes (the model's leg_min..leg_max).
  if (!mechanism().inverseKinematics(geometry.values(), T).withinStroke()) return Eigen::VectorXd();
  Eigen::VectorXd q(6);
  for (int i = 0; i < 6; ++i) {
    const std::string n = std::to_string(i + 1);
    const Eigen::Vector3d b(geometry.value("bx" + n), geometry.value("by" + n), geometry.value("bz" + n));
    const Eigen::Vector3d p(geometry.value("px" + n), geometry.value("py" + n), geometry.value("pz" + n));
    const Eigen::Vector3d leg = T * p - b;
    const Eigen::Vector3d side = Eigen::Vector3d::UnitZ().cross(leg).normalized();
    const double rho = (T * p - (b + eccentricity * side)).norm();
    q[i] = encoder_gain[static_cast<std::size_t>(i)] * (rho - geometry.value("rho0" + n));
  }
  return q;
}

Eigen::VectorXd TrueRobot::bentReadings(Eigen::VectorXd q) const {
  for (std::size_t i = 0; i < encoder_curvature.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    q[k] += encoder_curvature[i] * (q[k] - curvature_origin[k]) * (q[k] - curvature_origin[k]);
  }
  return q;
}

Eigen::VectorXd TrueRobot::fkm(const Eigen::VectorXd& q) const {
  if (h4) {
    const Eigen::Vector3d centre = H4ProtocolGrid{}.centre;
    const std::optional<H4Pose> X = h4->pose(H4Joints(q), H4Pose(centre[0], centre[1], centre[2], 0.0));
    if (!X) throw std::runtime_error("true robot: FKM left the workspace");
    return *X;
  }
  const Mechanism& m = mechanism();
  Eigen::VectorXd X = m.referencePose(geometry.values());
  for (int it = 0; it < 50; ++it) {
    const Eigen::VectorXd r = joints(X) - q;
    if (r.size() == 0) throw std::runtime_error("true robot: FKM left the workspace");
    if (r.cwiseAbs().maxCoeff() < 1e-13) return X;
    Eigen::MatrixXd J(q.size(), X.size());
    for (Eigen::Index k = 0; k < X.size(); ++k) {
      Eigen::VectorXd a = X, b = X;
      a[k] += 1e-7;
      b[k] -= 1e-7;
      const Eigen::VectorXd qa = joints(a), qb = joints(b);
      if (qa.size() == 0 || qb.size() == 0) throw std::runtime_error("true robot: FKM left the workspace");
      J.col(k) = (qa - qb) / 2e-7;
    }
    X -= J.colPivHouseholderQr().solve(r);
  }
  return X;
}

TrueRobot makeTrueH4(const H4ErrorSizes& sizes, std::uint64_t seed, const Eigen::Isometry3d& base_T_camera,
                     const Eigen::Isometry3d& marker_T_effector) {
  TrueRobot robot;
  robot.geometry_model = makeRegisteredModel(familyWithDefects(SimulatedDefects::H4Parallelograms).truth_model);
  robot.geometry = h4Model12Parameters(drawModel12Values(H4Model12Values{}, sizes, seed));
  robot.h4.emplace(makeTrueGeometry(H4Model12Values{}, sizes, seed), base_T_camera, marker_T_effector);
  return robot;
}

TrueRobot makeDefectiveDelta(unsigned seed, bool legs_differ, double tilt_per_m, double metre, double radian) {
  const MechanismFamily& delta = familyWithDefects(SimulatedDefects::PlateTilt);
  TrueRobot robot;
  robot.geometry_model = makeRegisteredModel(delta.truth_model);
  const ParameterSet common = perturbedBy(makeRegisteredModel(delta.models.front()).nominal, seed, metre, radian);
  robot.geometry =
      legs_differ ? perturbedBy(deltaLegsFromDelta(common), seed + 1, metre, radian) : deltaLegsFromDelta(common);
  robot.tilt_per_m = tilt_per_m;
  return robot;
}

TrueRobot makeDefectiveHexapod(unsigned seed, double gain_error, double eccentricity, double metre) {
  TrueRobot robot;
  robot.geometry_model = makeRegisteredModel(familyWithDefects(SimulatedDefects::GainsAndEccentricity).truth_model);
  robot.geometry = perturbedBy(robot.geometry_model.nominal, seed, metre, 0.0);
  std::mt19937 rng(seed + 7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 6; ++i) robot.encoder_gain.push_back(1.0 + gain_error * u(rng));
  robot.eccentricity = eccentricity;
  return robot;
}

TrueRobot makeDefectiveDescribed(const RegisteredModel& model, unsigned seed, bool defects, double metre, double radian) {
  TrueRobot robot;
  robot.geometry_model = model;
  robot.geometry = perturbedBy(model.nominal, seed, metre, radian);
  if (!defects) return robot;
  const Mechanism& m = robot.mechanism();
  const Eigen::VectorXd home = m.referencePose(robot.geometry.values());
  robot.curvature_origin = m.inverseKinematics(robot.geometry.values(), m.poseToTransform(home)).joints;
  std::mt19937 rng(seed + 11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const Unit unit : m.jointUnits())
    robot.encoder_curvature.push_back((unit == Unit::Radian ? 0.02 : 0.1) * u(rng));
  if (m.motionType() == MotionType::Translation) {
    robot.tilt_per_m = 0.0116;
    robot.level_pose = home.head<3>();
  }
  return robot;
}

Campaign simulateDefectiveCampaign(const TrueRobot& robot, const std::string& model_name, unsigned seed, double noise_t,
                                   double noise_r, int extra, double spread) {
  Campaign c = simulateCampaign(model_name, seed, 0.0, 0.0, extra);  // mountings, protocol (+ extra)
  c.truth = robot.geometry;
  const Eigen::Vector3d centre =
      robot.mechanism().poseToTransform(robot.mechanism().referencePose(c.truth.values())).translation();
  for (Eigen::Isometry3d& T : c.bTe) T.translation() = centre + spread * (T.translation() - centre);
  std::mt19937 rng(seed + 3000);
  std::normal_distribution<double> normal;
  PoseCovariance cov = PoseCovariance::Zero();
  cov.diagonal() << noise_t * noise_t, noise_t * noise_t, noise_t * noise_t, noise_r * noise_r, noise_r * noise_r,
      noise_r * noise_r;
  for (std::size_t j = 0; j < c.poses.size(); ++j) {
    const Eigen::VectorXd X = robot.mechanism().transformToPose(c.bTe[j]);
    c.bTe[j] = robot.effector(X);
    PoseObservation& p = c.poses[j];
    p.joints = robot.joints(X);
    if (p.joints.size() == 0) throw std::logic_error("defective robot: protocol pose " + p.id + " is out of reach");
    p.cTm = toPoseVector(c.bTc.inverse() * c.bTe[j] * c.mTe.inverse());
    for (int k = 0; k < 3; ++k) p.cTm[k] += noise_t * normal(rng);
    for (int k = 3; k < 6; ++k) p.cTm[k] += noise_r * normal(rng);
    p.covariance = cov;
  }
  return c;
}

std::vector<Eigen::VectorXd> protocolCoordinates(const TrueRobot& robot) {
  std::vector<Eigen::VectorXd> poses;
  if (robot.h4) {
    for (const H4Pose& X : protocolPoses(H4ProtocolGrid{})) poses.emplace_back(X);
    return poses;
  }
  const Mechanism& m = robot.mechanism();
  for (const Eigen::Isometry3d& bTe : protocolPoses(m, robot.geometry.values()))
    poses.push_back(m.transformToPose(bTe));
  return poses;
}

std::array<std::vector<Eigen::VectorXd>, 2> straightLinePoses(const TrueRobot& robot, int points, double reach) {
  if (robot.h4) {  // the lines of paper §6.1 through the H4's protocol grid (`reach` unused)
    std::array<std::vector<Eigen::VectorXd>, 2> lines;
    const std::array<std::vector<H4Pose>, 2> motions = straightLineMotions(H4ProtocolGrid{}, points);
    for (std::size_t line = 0; line < 2; ++line)
      for (const H4Pose& X : motions[line]) lines[line].emplace_back(X);
    return lines;
  }
  const bool translation = robot.mechanism().motionType() == MotionType::Translation;
  const Eigen::VectorXd ref = robot.mechanism().referencePose(robot.geometry.values());
  const double size = reach * protocolScale(robot.mechanism(), robot.geometry.values(), ref);
  const double a = size * (translation ? 0.12 : 0.04), dz = size * (translation ? 0.05 : 0.025);
  std::array<std::vector<Eigen::VectorXd>, 2> lines;
  for (int line = 0; line < 2; ++line) {
    const double sign = line == 0 ? 1.0 : -1.0;
    for (int k = 0; k < points; ++k) {
      const double s = -1.0 + 2.0 * k / (points - 1);
      Eigen::VectorXd X = ref;
      X[0] += a * s;
      X[1] += sign * a * s;
      X[2] += dz * s;
      lines[static_cast<std::size_t>(line)].push_back(X);
    }
  }
  return lines;
}

std::array<double, 4> positioningTestSides(const TrueRobot& robot, const Mechanism& model,
                                           const Eigen::VectorXd& geometric, double side) {
  const double corners[5][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {-1, -1}};
  const Eigen::VectorXd centre = model.referencePose(geometric);
  std::vector<Eigen::Vector3d> reached;
  for (const auto& corner : corners) {
    Eigen::VectorXd X = centre;
    X[0] += 0.5 * side * corner[0];
    X[1] += 0.5 * side * corner[1];
    const IkmResult ikm = model.inverseKinematics(geometric, model.poseToTransform(X));
    if (!ikm.reachable()) throw std::runtime_error("positioning test: a corner is unreachable for " + model.name());
    reached.push_back(robot.fkm(ikm.joints).head<3>());
  }
  std::array<double, 4> sides{};
  for (std::size_t k = 0; k < 4; ++k) sides[k] = (reached[k + 1] - reached[k]).norm() - side;
  return sides;
}

}  // namespace mire::datasets
