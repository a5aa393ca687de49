#pragma once
// The H4 demo's campaign (h4_campaign.hpp) for the other parallel mechanisms (doc/demo-mechanisms.md): a
// simulated true Delta or Gough–Stewart with unmodelled defects (mechanism_true_robots.hpp) carries the
// H4 demo's chessboard through the protocol poses of doc/mechanisms.md, seen by the same reference camera
// and rendered by the same renderer. Generates, deterministically for a seed, what a user would record:
//   <dir>/target.yaml                      the target
//   <dir>/calibration/images/view_XXX.png  calibration images
//   <dir>/poses/<pose_id>/img_XX.png       81 (hexapod) or 27 (Delta) poses × N images
//   <dir>/joints.csv                       encoder readings (q<i>_rad or q<i>_m) at the poses
//   <dir>/lines.csv                        encoder readings along two straight lines (V3)
// and, for scoring only: <dir>/truth/ (true camera, true geometry and mountings, true poses).
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
  // A family of the table (registry.hpp) other than the H4: the Delta (legs differ, plate tilts) or
  // the hexapod (gains, eccentricities); set by reference().
  std::string mechanism;
  std::filesystem::path camera_file;  // true camera; default: the reference camera
  std::filesystem::path target_file;  // default: datasets/specs/target_h4.yaml
  int calibration_views = 25;
  int images_per_pose = 10;
  int line_points = 21;             // per straight line (V3)
  double encoder_noise_rad = 2e-5;  // rotary joints (Delta), as the H4 demo
  double encoder_noise_m = 1e-6;    // prismatic joints (hexapod): a 1 µm linear scale
  RenderOptions render;
  NoiseOptions noise;
  std::uint64_t seed = 2004;
  // The true robot's draw; unset: `seed`. Set, it keeps one robot while `seed` renews the
  // images and encoder noise (benchmarks/bench_chain_mechanisms.cpp).
  std::optional<std::uint64_t> robot_seed;
  // false: the true robot is exactly of its geometry model (Delta: no plate tilt, the legs
  // still differ, so exactly `delta-legs`; hexapod: unit encoder gains, no eccentricity, so
  // exactly `gough-stewart`), for studies of the σ rather than of the model error.
  bool unmodelled_defects = true;
  // false: the Delta's legs are identical (only the common geometry's errors), so that without
  // its unmodelled defects it is exactly the simple `delta` model.
  bool delta_legs_differ = true;
  // The camera's placement in the robot's base; unset: mechanismBaseTCamera(mechanism).
  std::optional<Eigen::Isometry3d> base_T_camera;
  // The camera on the effector, the target fixed (doc/mechanisms.md, "Camera on the effector"):
  // placed by eyeInHandMounting().
  bool camera_on_effector = false;
  PngEncoding png = PngEncoding::Stored;

  // The H4 demo's optics (slight defocus, sensor noise) for `mechanism`; throws
  // std::invalid_argument naming an unknown mechanism.
  static MechanismImageCampaignSpec reference(const std::string& mechanism);
};

struct MechanismImageCampaign {
  DefectiveRobot robot;                    // true geometry and defects (scoring only)
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
  // The true cTm at `pose_id` (scoring); std::out_of_range for an unknown id.
  Eigen::Isometry3d trueCameraTMarker(const std::string& pose_id) const;
};

// The camera and target placement of the demo: the camera below a Delta looking up (as the
// H4's), above a hexapod looking down; the target centred on the effector facing the camera.
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
// rendering; its mountings are mechanismBaseTCamera() (or the spec's) and mechanismMarkerTEffector().
DefectiveRobot trueRobotOf(const MechanismImageCampaignSpec& spec);

// Generates the campaign under `directory`. Throws std::runtime_error naming the pose when a
// target feature would leave the image (less than 10 px inside) at a protocol pose.
MechanismImageCampaign generateMechanismImageCampaign(const MechanismImageCampaignSpec& spec,
                                                      const std::filesystem::path& directory,
                                                      const ProgressCallback& progress = {});

}  // namespace mire::datasets
