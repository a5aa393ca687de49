#pragma once
// A simulated ISO 9283 pose test (doc/accuracy.md, "The ISO 9283 test"): a true robot driven by a
// controller to the standard's 5 positions on a diagonal plane of a cube inside the workspace
// (ISO 9283 §6.2: P1 the cube's centre, P2..P5 on the diagonals at 10 % of their length from the
// corners) for `cycles` cycles (§7.2.1: 30), the target measured by the camera at every stop.
// What `mire accuracy` reads: commanded.csv (pose_id, position, pose), the measured poses.csv with
// σ columns, and the controller's joint commands; for scoring, the true attained poses.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mire/datasets/mechanism_true_robots.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/mechanism.hpp"

namespace mire::datasets {

struct Iso9283Spec {
  int cycles = 30;
  // The cube: its centre pose (the controller's pose components: components beyond x, y, z are
  // the commanded orientation of every position) and side [m].
  Eigen::VectorXd centre;
  double side = 0.1;
  // The robot's own scatter: Gaussian noise on every joint command it executes [rad or m].
  double joint_repeatability = 0.0;
  // Camera noise on the measured cTm, per translation / rotation-vector component (paper §5).
  double noise_t = 0.2e-3, noise_r = 0.03 * 3.14159265358979323846 / 180.0;
  std::uint64_t seed = 9283;
};

// Where the true robot goes for joint commands q (its effector bTe); nullopt when it cannot.
using TrueRobotReach = std::function<std::optional<Eigen::Isometry3d>(const Eigen::VectorXd& joints)>;
// What the camera reports for a true target pose before its noise: the true pose for an ideal
// camera; through a calibrated camera, its systematic error (the one the identification shares).
using CameraReading = std::function<mechanism::PoseVector(const Eigen::Isometry3d& true_cTm)>;

struct Iso9283Test {
  std::vector<std::string> ids, positions;           // per stop: "c<cycle>_P<k>", "P<k>"
  std::vector<Eigen::VectorXd> commanded;            // the controller's pose components, base frame
  std::vector<Eigen::VectorXd> joints;               // the controller's commands (before the robot's scatter)
  std::vector<Eigen::Isometry3d> attained;           // true bTe
  std::vector<mechanism::PoseObservation> measured;  // cTm with noise and its covariance; joints empty
};

// ISO 9283's 5 positions on the cube's diagonal plane through the corners (−,−,−), (+,+,−),
// (+,+,+), (−,−,+) (relative to `centre`): P1 = centre, P2..P5 = centre + 0.8 × corner.
std::vector<Eigen::VectorXd> iso9283Positions(const Eigen::VectorXd& centre, double side);

// The largest cube centred on the box of `positions` that fits in it (side = the box's smallest
// extent), for a test inside a protocol's volume.
std::pair<Eigen::Vector3d, double> cubeInside(const std::vector<Eigen::Vector3d>& positions);

// The true robot of a simulated campaign as TrueRobotReach (its own FKM, defects included;
// encoder readings in, effector out).
TrueRobotReach reachOf(const TrueRobot& robot);

// The test inside the protocol's volume of a campaign robot (mechanism_campaign.hpp's protocol
// poses; the H4's protocol grid, iso9283SpecFor(H4ProtocolGrid{})): the cube centred on it, as
// large as its smallest extent, the orientation of the reference pose.
Iso9283Spec iso9283SpecFor(const TrueRobot& robot);
Iso9283Spec iso9283SpecFor(const H4ProtocolGrid& grid);

// Runs the test: each cycle visits P1..P5 in order, commanded through `controller`'s IKM at
// `controller_geometric`; `reach` (the true robot) moves; the camera at bTc sees the target at
// mTe and reports `camera` (default: the true pose) plus the spec's noise. Throws
// std::runtime_error naming the position when the controller or the robot cannot reach it.
Iso9283Test simulateIso9283Test(const mechanism::Mechanism& controller, const Eigen::VectorXd& controller_geometric,
                                const TrueRobotReach& reach, const Eigen::Isometry3d& bTc, const Eigen::Isometry3d& mTe,
                                const Iso9283Spec& spec, const CameraReading& camera = {});

// Writes <dir>/commanded.csv, <dir>/poses.csv (σ columns from the spec's noise) and
// <dir>/joints.csv (the controller's commands), each atomically.
void writeIso9283Test(const std::filesystem::path& dir, const Iso9283Test& test, const mechanism::Mechanism& controller,
                      const Iso9283Spec& spec);

// The parameter file `mire accuracy --params` reads the test's cycles through, for scoring: the
// true geometry `truth` of the model `model_key` names (a registered name or a description file
// beside `path`) and the true mountings in the full form (tx_CB..rz_EM: cTb = bTc⁻¹, eTm = mTe⁻¹).
void writeIso9283Truth(const std::filesystem::path& path, const mechanism::ParameterSet& truth,
                       const std::string& model_key, const Eigen::Isometry3d& bTc, const Eigen::Isometry3d& mTe);

}  // namespace mire::datasets
