#pragma once
// The paper's experiment in simulation (paper §5–6; doc/mechanisms.md, "Evaluation criteria"): a simulated
// true H4 carrying a target, seen by the reference camera. Generates, deterministically for a seed, everything a
// user would have recorded on the real robot, as files in the formats of doc/file-formats.md:
//   <dir>/target.yaml                      the target
//   <dir>/calibration/images/view_XXX.png  calibration images of the reference camera
//   <dir>/poses/<pose_id>/img_XX.png       81 poses × N images of the target on the effector
//   <dir>/joints.csv                       encoder readings at the 81 poses
//   <dir>/lines.csv                        encoder readings along the two straight lines (V3)
// and, kept apart for scoring only (never read by the pipeline):
//   <dir>/truth/...                        true camera, true robot geometry, true poses
#include "mire/datasets/h4_true_robot.hpp"
#include "mire/datasets/render.hpp"
#include "mire/datasets/simulation.hpp"

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace mire::datasets {

struct H4CampaignSpec {
  std::filesystem::path camera_file;  // true camera (camera.yaml); default: the reference camera
  std::filesystem::path target_file;  // default: datasets/specs/target_h4.yaml
  int calibration_views = 25;
  int images_per_pose = 10;  // paper §5 (doc/measurement.md)
  int line_points = 20;      // per straight line (V3)
  H4ProtocolGrid grid;       // the 81-pose protocol (paper §6)
  H4ErrorSizes errors;       // manufacturing errors and unmodelled defects
  double encoder_noise_rad = 2e-5;
  RenderOptions render;
  NoiseOptions noise;
  std::uint64_t seed = 2004;
  // The true robot's draw (its errors); unset: `seed`. Set, it keeps one robot while `seed`
  // renews the images and encoder noise (benchmarks/bench_chain.cpp).
  std::optional<std::uint64_t> robot_seed;
  // The camera's placement bTc; unset: defaultBaseTCamera(). The chain study draws one per chain
  // so that the detector's systematic feature error differs between chains (doc/uncertainty.md).
  std::optional<Eigen::Isometry3d> base_T_camera;
  // The images are read back once by the pipeline: stored PNG, 10x cheaper to write and 7x
  // to read than compressed, for twice the disk space (png.hpp).
  PngEncoding png = PngEncoding::Stored;

  // The defaults above with realistic optics: slight defocus and sensor noise.
  static H4CampaignSpec reference();
};

// What was generated: the true robot and mounting (for scoring), and where the files are.
struct H4Campaign {
  H4TrueRobot robot;
  calibration::Camera camera;  // true camera (scoring only)
  std::vector<H4Pose> poses;   // true effector poses, in pose-id order
  std::vector<std::string> pose_ids;
  std::array<std::vector<H4Pose>, 2> lines;  // commanded line motions (for reference)

  std::filesystem::path directory;
  std::filesystem::path target_file() const { return directory / "target.yaml"; }
  std::filesystem::path calibration_images() const { return directory / "calibration" / "images"; }
  std::filesystem::path pose_images() const { return directory / "poses"; }
  std::filesystem::path joints_file() const { return directory / "joints.csv"; }
  std::filesystem::path lines_file() const { return directory / "lines.csv"; }
  // The true cTm at the pose named `pose_id` (scoring); std::out_of_range for an unknown id.
  Eigen::Isometry3d trueCameraTMarker(const std::string& pose_id) const;
};

// The spec's true robot with its mountings (the camera's, the target's for the spec's target
// file), as generateH4Campaign draws it, without rendering: a campaign's robot run again, e.g.
// by `mire simulate iso9283` with compensated commands.
H4TrueRobot trueRobotOf(const H4CampaignSpec& spec);

// Generates the campaign under `directory` (created; existing files are replaced atomically).
// Throws std::runtime_error naming the pose, before writing anything, when a target feature
// would come within 10 px of the image border at a protocol pose (campaign_images.hpp).
// `progress` is called after each image written.
H4Campaign generateH4Campaign(const H4CampaignSpec& spec, const std::filesystem::path& directory,
                              const ProgressCallback& progress = {});

}  // namespace mire::datasets
