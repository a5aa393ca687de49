// A campaign's legs as rods and their files (campaign_legs.hpp).
#include "mire/datasets/campaign_legs.hpp"

#include "mire/mechanism/delta.hpp"
#include "mire/mechanism/legs_csv.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/support/yaml.hpp"

#include <random>
#include <sstream>
#include <stdexcept>

namespace mire::datasets {
namespace {

bool hasTruthModelOf(const TrueRobot& robot, SimulatedDefects family) {
  return !robot.h4 && robot.geometry_model.name == familyWithDefects(family).truth_model;
}
bool isDelta(const TrueRobot& robot) { return hasTruthModelOf(robot, SimulatedDefects::PlateTilt); }

void requireLegs(const TrueRobot& robot) {
  if (!isDelta(robot) && !hasTruthModelOf(robot, SimulatedDefects::GainsAndEccentricity))
    throw std::invalid_argument("legs as rods: the hexapod's and the Delta's only, not " + robot.title());
}

// The Delta's forearms in its `delta-legs` geometry: arm V_i = Rz(ψ_i)·Rx(β_i)·Rz(φ_i)·(−1, 0, 0)
// (eq. 17), elbow p_i + L_i·V_i, plate joint at the plate centre t (the legs' effective pivots
// p_i hold R − r), both moved out by the nominal r along p_i's azimuth.
std::vector<LegSegment> deltaForearms(const TrueRobot& robot, const Eigen::VectorXd& X) {
  const Eigen::Vector3d t = X.head<3>();
  const IkmResult ikm =
      robot.mechanism().inverseKinematics(robot.geometry.values(), robot.mechanism().poseToTransform(X));
  if (!ikm.reachable()) throw std::runtime_error("legs as rods: the Delta's pose is unreachable");
  const double plate_radius = DeltaNominal{}.r;
  std::vector<LegSegment> legs;
  for (int i = 0; i < 3; ++i) {
    const auto value = [&](const char* name) { return robot.geometry.value(name + std::to_string(i + 1)); };
    const Eigen::Vector3d pivot(value("px"), value("py"), value("pz"));
    const double phi = ikm.joints[i] + value("q0");
    const Eigen::Vector3d arm = Eigen::AngleAxisd(value("psi"), Eigen::Vector3d::UnitZ()) *
                                (Eigen::AngleAxisd(value("beta"), Eigen::Vector3d::UnitX()) *
                                 (Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitZ()) * Eigen::Vector3d(-1.0, 0.0, 0.0)));
    const Eigen::Vector3d out = plate_radius * Eigen::Vector3d(pivot.x(), pivot.y(), 0.0).normalized();
    legs.push_back({pivot + value("L") * arm + out, t + out});
  }
  return legs;
}

}  // namespace

bool campaignDrawsLegs(const std::string& mechanism) {
  if (isDescriptionFile(mechanism)) return false;
  const SimulatedDefects defects = mechanismFamily(mechanism).defects;
  return defects == SimulatedDefects::GainsAndEccentricity || defects == SimulatedDefects::PlateTilt;
}

std::string legsModel(const TrueRobot& robot) {
  requireLegs(robot);
  // The truth model when it has legs (the hexapod's), else the simplest of the family's models that
  // has (the Delta's `delta`: its `delta-legs` truth holds R - r, not where the forearms are).
  if (robot.mechanism().legCount() > 0) return robot.geometry_model.name;
  for (const std::string& name : mechanism::mechanismFamily(mechanism::modelInfo(robot.geometry_model.name).family).models)
    if (mechanism::makeRegisteredModel(name).mechanism->legCount() > 0) return name;
  throw std::invalid_argument("legs as rods: no model of " + robot.title() + "'s family has legs");
}

std::vector<LegSegment> trueLegSegments(const TrueRobot& robot, const Eigen::VectorXd& X) {
  requireLegs(robot);
  if (isDelta(robot)) return deltaForearms(robot, X);
  // The hexapod's base joint centre is off by the eccentricity ε ⟂ its leg (TrueRobot::joints).
  std::vector<LegSegment> legs = robot.mechanism().legSegments(robot.geometry.values(), robot.effector(X));
  for (LegSegment& leg : legs)
    leg.from += robot.eccentricity * Eigen::Vector3d::UnitZ().cross(leg.to - leg.from).normalized();
  return legs;
}

std::vector<Rod> legRods(const TrueRobot& robot, const Eigen::VectorXd& X, const Eigen::Isometry3d& bTc, double radius_m) {
  const Eigen::Isometry3d cTb = bTc.inverse();
  std::vector<Rod> rods;
  for (const LegSegment& leg : trueLegSegments(robot, X)) rods.push_back({cTb * leg.from, cTb * leg.to, radius_m});
  return rods;
}

Eigen::Isometry3d rulerBaseTCamera(const Eigen::Isometry3d& bTc, std::uint64_t seed) {
  std::mt19937_64 rng(seed ^ 0x5DEECE66DULL);
  std::normal_distribution<double> normal;
  const auto direction = [&] { return Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized(); };
  Eigen::Isometry3d ruler = bTc;
  ruler.translation() += 5e-3 * direction();
  ruler.linear() = Eigen::AngleAxisd(kCampaignDeg, direction()).toRotationMatrix() * bTc.linear();
  return ruler;
}

std::string legsYaml(const std::string& model, double radius_m, const Eigen::Isometry3d& approximate_bTc, int search_px) {
  const Eigen::Vector3d t = approximate_bTc.translation() * 1e3;
  const Eigen::AngleAxisd turn(approximate_bTc.linear());
  const Eigen::Vector3d r = turn.axis() * turn.angle() / kCampaignDeg;
  const auto triple = [](const Eigen::Vector3d& v) {
    return "[" + support::formatYamlNumber(v.x()) + ", " + support::formatYamlNumber(v.y()) + ", " +
           support::formatYamlNumber(v.z()) + "]";
  };
  std::ostringstream out;
  out << "# The legs seen as rods (doc/file-formats.md, \"legs.yaml\"): read by mire measure --legs.\n"
      << "model: " << model << "\n"
      << "radius_mm: " << support::formatYamlNumber(radius_m * 1e3) << "\n"
      << "base_T_camera:  # approximate (a ruler's), to predict where to search\n"
      << "  t_mm: " << triple(t) << "\n"
      << "  r_deg: " << triple(r) << "  # rotation vector\n"
      << "search_px: " << search_px << "\n";
  return out.str();
}

void writeTrueLegs(const std::filesystem::path& legs_csv, const TrueRobot& robot,
                   const std::vector<Eigen::VectorXd>& poses, const std::vector<std::string>& pose_ids,
                   const Eigen::Isometry3d& bTc) {
  const Eigen::Isometry3d cTb = bTc.inverse();
  std::vector<LegObservation> legs;
  for (std::size_t j = 0; j < poses.size(); ++j) {
    const std::vector<LegSegment> segments = trueLegSegments(robot, poses[j]);
    for (std::size_t i = 0; i < segments.size(); ++i) {
      LegObservation o;
      o.pose_id = pose_ids[j];
      o.leg = static_cast<int>(i);
      o.line = support::Line3d::throughPoints(cTb * segments[i].from, cTb * segments[i].to);
      o.covariance = 1e-24 * Eigen::Matrix4d::Identity();
      legs.push_back(o);
    }
  }
  writeLegsCsv(legs_csv, legs);
}

}  // namespace mire::datasets
