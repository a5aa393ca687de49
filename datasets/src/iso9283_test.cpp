// A simulated ISO 9283 pose test (iso9283_test.hpp).
#include "mire/datasets/iso9283_test.hpp"

#include <algorithm>
#include <random>
#include <sstream>
#include <stdexcept>

#include "mire/mechanism/external.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/mechanism/pose.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/constants.hpp"
#include "mire/support/csv.hpp"

namespace mire::datasets {

namespace mech = mire::mechanism;

std::vector<Eigen::VectorXd> iso9283Positions(const Eigen::VectorXd& centre, double side) {
  if (centre.size() < 3 || !(side > 0.0)) throw std::invalid_argument("ISO 9283 cube: a centre pose and a side > 0");
  const double h = 0.5 * side;
  const Eigen::Vector3d corners[4] = {{-h, -h, -h}, {h, h, -h}, {h, h, h}, {-h, -h, h}};
  std::vector<Eigen::VectorXd> out{centre};
  for (const Eigen::Vector3d& c : corners) {
    Eigen::VectorXd p = centre;
    p.head<3>() += 0.8 * c;  // 10 % of the diagonal from the corner (§6.2)
    out.push_back(p);
  }
  return out;
}

std::pair<Eigen::Vector3d, double> cubeInside(const std::vector<Eigen::Vector3d>& positions) {
  if (positions.empty()) throw std::invalid_argument("ISO 9283 cube: no positions");
  Eigen::Vector3d low = positions.front(), high = positions.front();
  for (const Eigen::Vector3d& p : positions) {
    low = low.cwiseMin(p);
    high = high.cwiseMax(p);
  }
  return {0.5 * (low + high), (high - low).minCoeff()};
}

TrueRobotReach reachOf(const TrueRobot& robot) {
  return [&robot](const Eigen::VectorXd& q) -> std::optional<Eigen::Isometry3d> {
    try {
      return robot.effector(robot.fkm(q));
    } catch (const std::runtime_error&) {
      return std::nullopt;  // the FKM left the workspace
    }
  };
}

Iso9283Spec iso9283SpecFor(const TrueRobot& robot) {
  if (robot.h4) return iso9283SpecFor(H4ProtocolGrid{});
  const mech::Mechanism& m = robot.mechanism();
  std::vector<Eigen::Vector3d> positions;
  for (const Eigen::Isometry3d& T : protocolPoses(m, robot.geometry.values())) positions.push_back(T.translation());
  Iso9283Spec spec;
  const auto [centre, side] = cubeInside(positions);
  spec.centre = m.referencePose(robot.geometry.values());
  spec.centre.head<3>() = centre;
  spec.side = side;
  return spec;
}

Iso9283Spec iso9283SpecFor(const H4ProtocolGrid& grid) {
  Iso9283Spec spec;
  spec.centre = H4Pose(grid.centre[0], grid.centre[1], grid.centre[2], 0.0);
  spec.side = grid.extent.minCoeff();
  return spec;
}

Iso9283Test simulateIso9283Test(const mech::Mechanism& controller, const Eigen::VectorXd& controller_geometric,
                                const TrueRobotReach& reach, const Eigen::Isometry3d& bTc, const Eigen::Isometry3d& mTe,
                                const Iso9283Spec& spec, const CameraReading& camera) {
  if (spec.cycles < 2) throw std::invalid_argument("ISO 9283 test: at least 2 cycles");
  const std::vector<Eigen::VectorXd> positions = iso9283Positions(spec.centre, spec.side);
  std::vector<Eigen::VectorXd> commands;
  for (std::size_t k = 0; k < positions.size(); ++k) {
    const mech::IkmResult ikm =
        controller.inverseKinematics(controller_geometric, controller.poseToTransform(positions[k]));
    if (!ikm.reachable() || !ikm.withinStroke())
      throw std::runtime_error("ISO 9283 test: position P" + std::to_string(k + 1) +
                               " is out of the controller's reach");
    commands.push_back(ikm.joints);
  }
  std::mt19937_64 rng(spec.seed);
  std::normal_distribution<double> normal;
  mech::PoseCovariance covariance = mech::PoseCovariance::Zero();
  covariance.diagonal() << Eigen::Vector3d::Constant(spec.noise_t * spec.noise_t),
      Eigen::Vector3d::Constant(spec.noise_r * spec.noise_r);
  Iso9283Test test;
  for (int cycle = 1; cycle <= spec.cycles; ++cycle)
    for (std::size_t k = 0; k < positions.size(); ++k) {
      const std::string position = "P" + std::to_string(k + 1);
      Eigen::VectorXd q = commands[k];
      for (Eigen::Index j = 0; j < q.size(); ++j) q[j] += spec.joint_repeatability * normal(rng);
      const std::optional<Eigen::Isometry3d> bTe = reach(q);
      if (!bTe) throw std::runtime_error("ISO 9283 test: the robot does not reach position " + position);
      mech::PoseObservation seen;
      seen.id = "c" + std::to_string(cycle) + "_" + position;
      const Eigen::Isometry3d cTm = bTc.inverse() * *bTe * mTe.inverse();
      seen.cTm = camera ? camera(cTm) : mech::toPoseVector(cTm);
      for (int c = 0; c < 3; ++c) seen.cTm[c] += spec.noise_t * normal(rng);
      for (int c = 3; c < 6; ++c) seen.cTm[c] += spec.noise_r * normal(rng);
      seen.covariance = covariance;
      test.ids.push_back(seen.id);
      test.positions.push_back(position);
      test.commanded.push_back(positions[k]);
      test.joints.push_back(commands[k]);
      test.attained.push_back(*bTe);
      test.measured.push_back(seen);
    }
  return test;
}

void writeIso9283Test(const std::filesystem::path& dir, const Iso9283Test& test, const mech::Mechanism& controller,
                      const Iso9283Spec& spec) {
  std::ostringstream commanded, poses;
  commanded << "pose_id,position";
  const auto names = controller.poseComponentNames();
  const auto units = controller.poseComponentUnits();
  for (std::size_t k = 0; k < names.size(); ++k) commanded << ',' << names[k] << '_' << mech::unitName(units[k]);
  commanded << '\n';
  poses << "pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,sigma_tx_mm,sigma_ty_mm,"
           "sigma_tz_mm,sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px\n";
  for (std::size_t i = 0; i < test.ids.size(); ++i) {
    commanded << test.ids[i] << ',' << test.positions[i];
    for (Eigen::Index k = 0; k < test.commanded[i].size(); ++k)
      commanded << ',' << support::formatNumber(test.commanded[i][k]);
    commanded << '\n';
    // A pose measured directly (no images): images 1/1, no reprojection residual.
    poses << test.ids[i] << ",1,1";
    for (int k = 0; k < 6; ++k) poses << ',' << support::formatNumber(test.measured[i].cTm[k]);
    for (int k = 0; k < 3; ++k) poses << ',' << support::formatNumber(spec.noise_t * 1e3);
    for (int k = 0; k < 3; ++k) poses << ',' << support::formatNumber(spec.noise_r * 180.0 / support::kPi);
    poses << ",0\n";
  }
  std::filesystem::create_directories(dir);
  support::writeFileAtomically(dir / "commanded.csv", commanded.str());
  support::writeFileAtomically(dir / "poses.csv", poses.str());
  mech::writeJointsCsv(dir / "joints.csv", test.ids, test.joints, controller.jointColumnNames());
}

void writeIso9283Truth(const std::filesystem::path& path, const mech::ParameterSet& truth, const std::string& model_key,
                       const Eigen::Isometry3d& bTc, const Eigen::Isometry3d& mTe) {
  mech::ParameterSet all = truth;
  mech::ParameterSet mounting = mech::ExternalParameterization(mech::ExternalForm::Full).parameters();
  Eigen::VectorXd values(12);
  values << mech::toPoseVector(bTc.inverse()), mech::toPoseVector(mTe.inverse());
  mounting.setValues(values);
  for (const mech::Parameter& p : mounting.parameters()) all.add(p);
  mech::writeParameterFile(path, all, {}, {{"model", model_key}, {"created_by", "mire simulate campaign"}},
                           "True geometry and mountings of the simulated robot (SI): the frame of the ISO 9283 "
                           "test's commanded poses (iso9283/commanded.csv)");
}

}  // namespace mire::datasets
