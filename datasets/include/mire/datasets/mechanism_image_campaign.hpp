#pragma once
// The paper's experiment in simulation (paper §5–6; doc/mechanisms.md, "Evaluation criteria"), for every
// mechanism of the table (registry.hpp; doc/demo-mechanisms.md): a simulated true robot with its unmodelled
// defects (mechanism_true_robots.hpp: the H4's tilted arm axes and imperfect parallelograms, the Delta's
// differing legs and tilting plate, the hexapod's gains and eccentricities, a described robot's bent
// readings) carries the demo's chessboard through its protocol poses (the H4's 81 of paper §6,
// doc/mechanisms.md for the others), seen by the reference camera. Generates, deterministically for a
// seed, what a user would record on the real robot, as files in the formats of doc/file-formats.md:
//   <dir>/target.yaml                      the target
//   <dir>/calibration/images/view_XXX.png  calibration images
//   <dir>/poses/<pose_id>/img_XX.png       81 (H4, hexapod) or 27 (Delta) poses × N images
//   <dir>/joints.csv                       encoder readings (q<i>_rad or q<i>_m) at the poses
//   <dir>/lines.csv                        encoder readings along two straight lines (V3)
//   <dir>/legs.yaml                        with leg_radius_m: the legs drawn as rods (campaign_legs.hpp)
// and, for scoring only (never read by the pipeline): <dir>/truth/ (true camera, true geometry and
// mountings, true poses).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mire/calibration/camera_model.hpp"
#include "mire/datasets/mechanism_true_robots.hpp"
#include "mire/datasets/png.hpp"
#include "mire/datasets/render.hpp"
#include "mire/datasets/simulation.hpp"

namespace mire::datasets {

struct MechanismImageCampaignSpec {
  // A family of the table (registry.hpp) or a description file; set by reference().
  std::string mechanism;
  std::filesystem::path camera_file;  // true camera; default: the reference camera
  std::filesystem::path target_file;  // default: datasets/specs/target_h4.yaml
  int calibration_views = 25;
  int images_per_pose = 10;
  int line_points = 21;             // per straight line (V3); the H4's reference: 20
  double encoder_noise_rad = 2e-5;  // rotary joints (H4, Delta)
  double encoder_noise_m = 1e-6;    // prismatic joints (hexapod): a 1 µm linear scale
  RenderOptions render;
  NoiseOptions noise;
  std::uint64_t seed = 2004;
  // The true robot's draw; unset: `seed`. Set, it keeps one robot while `seed` renews the
  // images and encoder noise (benchmarks/bench_chain.cpp).
  std::optional<std::uint64_t> robot_seed;
  // The H4's manufacturing errors and unmodelled defects (h4_true_robot.hpp); reference("h4")
  // makes them as large as the paper's robot's.
  H4ErrorSizes h4_errors;
  // false: the true robot is exactly of its geometry model (H4: model 12; Delta: no plate tilt,
  // the legs still differ, so exactly `delta-legs`; hexapod: unit encoder gains, no eccentricity,
  // so exactly `gough-stewart`), for studies of the σ rather than of the model error.
  bool unmodelled_defects = true;
  // false: the Delta's legs are identical (only the common geometry's errors), so that without
  // its unmodelled defects it is exactly the simple `delta` model.
  bool delta_legs_differ = true;
  // The camera's placement in the robot's base; unset: mechanismBaseTCamera(mechanism). The H4's
  // chain study draws one per chain so that the detector's systematic feature error differs
  // between chains (doc/uncertainty.md).
  std::optional<Eigen::Isometry3d> base_T_camera;
  // The camera on the effector, the target fixed (doc/mechanisms.md, "Camera on the effector"):
  // placed by eyeInHandMounting(); not the H4's.
  bool camera_on_effector = false;
  // Set: the pose images show the true robot's legs as rods of this radius [m], and the campaign
  // writes legs.yaml and truth/legs.csv (campaign_legs.hpp; the hexapod and the Delta, camera fixed).
  std::optional<double> leg_radius_m;
  // The images are read back once by the pipeline: stored PNG, 10x cheaper to write and 7x
  // to read than compressed, for twice the disk space (png.hpp).
  PngEncoding png = PngEncoding::Stored;

  // The demo's optics (a slightly soft lens, a noisy sensor: paper §5) for `mechanism`, and the
  // H4's errors and line points; throws std::invalid_argument naming an unknown mechanism.
  static MechanismImageCampaignSpec reference(const std::string& mechanism);
};

struct MechanismImageCampaign {
  TrueRobot robot;                         // true geometry and defects (scoring only)
  calibration::Camera camera;              // true camera (scoring only)
  Eigen::Isometry3d bTc, mTe;              // true mountings (scoring only)
  std::vector<Eigen::VectorXd> commanded;  // protocol poses X (the true robot's pose coordinates)
  std::vector<Eigen::Isometry3d> bTe;      // true effector transforms (the Delta's tilt included)
  std::vector<std::string> pose_ids;
  std::array<std::vector<Eigen::VectorXd>, 2> lines;  // commanded straight-line poses (V3)

  std::filesystem::path directory;
  // With the camera on the effector (MechanismImageCampaignSpec::camera_on_effector): the true
  // eTc and bTm; bTc and mTe are then those the view was derived from (eyeInHandMounting()).
  bool camera_on_effector = false;
  Eigen::Isometry3d eTc = Eigen::Isometry3d::Identity(), bTm = Eigen::Isometry3d::Identity();
  std::filesystem::path target_file() const { return directory / "target.yaml"; }
  std::filesystem::path calibration_images() const { return directory / "calibration" / "images"; }
  std::filesystem::path pose_images() const { return directory / "poses"; }
  std::filesystem::path joints_file() const { return directory / "joints.csv"; }
  std::filesystem::path lines_file() const { return directory / "lines.csv"; }
  std::filesystem::path legs_file() const { return directory / "legs.yaml"; }
  // The true cTm at `pose_id` (scoring); std::out_of_range for an unknown id.
  Eigen::Isometry3d trueCameraTMarker(const std::string& pose_id) const;
};

// The camera and target placement of the demo: the camera below an H4 or a Delta looking up,
// above a hexapod looking down; the target centred on the effector facing the camera.
Eigen::Isometry3d mechanismBaseTCamera(const std::string& mechanism);
Eigen::Isometry3d mechanismMarkerTEffector(const std::string& mechanism, const metrology::Target& target);

// The camera on the effector with the camera-fixed campaign's view at the robot's home `bTe_home`:
// the camera turned by a half turn about the base's x axis (a Delta's looks down at a target
// below, a hexapod's up at one above) and 30 mm from the effector origin, the target placed where
// that camera sees it as the fixed camera sees the target on the effector. The protocol's
// displacements, symmetric about the home, then give the fixed campaign's views mirrored.
// Returns (eTc, bTm).
std::pair<Eigen::Isometry3d, Eigen::Isometry3d> eyeInHandMounting(const Eigen::Isometry3d& bTc,
                                                                  const Eigen::Isometry3d& mTe,
                                                                  const Eigen::Isometry3d& bTe_home);

// The spec's true robot (geometry and defects) as generateMechanismImageCampaign draws it, without
// rendering: a campaign's robot run again, e.g. by `mire simulate iso9283` with compensated
// commands. Its mountings are mechanismBaseTCamera() (or the spec's) and mechanismMarkerTEffector()
// (the H4's kinematics hold them too, for the spec's target file).
TrueRobot trueRobotOf(const MechanismImageCampaignSpec& spec);

// Generates the campaign under `directory` (created; existing files are replaced atomically).
// Throws std::runtime_error naming the pose, before writing anything, when a target feature
// would leave the image (less than 10 px inside) at a protocol pose; std::invalid_argument for
// the H4 with the camera on the effector, and for legs (leg_radius_m) on another robot than the
// hexapod and the Delta, or with the camera on the effector. `progress` is called after each image written.
MechanismImageCampaign generateMechanismImageCampaign(const MechanismImageCampaignSpec& spec,
                                                      const std::filesystem::path& directory,
                                                      const ProgressCallback& progress = {});

}  // namespace mire::datasets
