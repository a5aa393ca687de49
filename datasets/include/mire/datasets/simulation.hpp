#pragma once
// Simulated image sets with their ground truth (doc/simulation.md): calibration views, and images of
// a target carried by the effector at a set of poses (10 per pose, paper §5). The spec is a
// YAML file (cv::FileStorage) documented in datasets/specs/simulate_*.yaml; `mire simulate`
// and `mire demo` both call the functions here.
#include "mire/calibration/camera_model.hpp"
#include "mire/datasets/png.hpp"
#include "mire/datasets/render.hpp"
#include "mire/metrology/target.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace mire::datasets {

// Where to put the target in a view: its centre (the centroid of its features) on the ray
// of `centre_pixel` at `distance_m` from the camera centre; facing the camera, then tilted
// by `tilt_rad` about an in-plane axis at angle `tilt_axis_rad` from the target's x, then
// turned by `roll_rad` about the optical axis.
struct ViewPlacement {
  Eigen::Vector2d centre_pixel = Eigen::Vector2d::Zero();
  double distance_m = 0.5;
  double tilt_rad = 0.0;
  double tilt_axis_rad = 0.0;
  double roll_rad = 0.0;
};

// cTm for a placement (doc/conventions.md: target frame M to camera frame C).
Eigen::Isometry3d placeTarget(const calibration::Camera& camera, const metrology::Target& target,
                              const ViewPlacement& placement);

// Calibration views: stratified distances, tilts and image positions (corners included),
// every feature inside the image by at least `margin_px`.
struct CalibrationViewsSpec {
  int views = 25;
  double min_distance_m = 0.35;
  double max_distance_m = 0.7;
  double max_tilt_deg = 50.0;
  double max_roll_deg = 20.0;
  double margin_px = 15.0;
};

std::vector<Eigen::Isometry3d> generateCalibrationViews(const calibration::Camera& camera,
                                                        const metrology::Target& target,
                                                        const CalibrationViewsSpec& spec, std::uint64_t seed);

// A pose of the target seen by the fixed camera. For generated sets the effector pose
// (x, y, z, θ) in the base frame is kept for reference.
struct SimulatedPose {
  std::string id;
  Eigen::Isometry3d camera_T_target = Eigen::Isometry3d::Identity();
  bool has_effector = false;
  Eigen::Vector4d effector = Eigen::Vector4d::Zero();  // x, y, z (m), θ (rad) in frame B
  std::vector<Rod> rods;  // seen with the target (a robot's legs, camera frame); none by default
};

// Generated poses: the effector visits a grid (size_m, counts per axis, centred on the
// grid centre) and each θ; the target is fixed to the effector (eTm = identity: its plane
// is the effector's xy plane) and the camera looks down the base's -z axis at the grid
// centre from `camera_distance_m`, tilted by `camera_tilt_deg` about the base x axis.
struct PoseGridSpec {
  Eigen::Vector3d size_m{0.2, 0.2, 0.15};
  Eigen::Vector3i counts{3, 3, 3};
  std::vector<double> theta_deg{-20.0, 0.0, 20.0};
  double camera_distance_m = 0.7;
  double camera_tilt_deg = 15.0;
};

// bTc of the generated set's camera, and the generated poses (ids "p001", ... ).
Eigen::Isometry3d poseGridCamera(const metrology::Target& target, const PoseGridSpec& spec);
std::vector<SimulatedPose> generatePoseGrid(const metrology::Target& target, const PoseGridSpec& spec);

namespace detail {
inline metrology::TargetSpec placeholderTargetSpec() {
  metrology::TargetSpec spec;
  spec.cols = spec.rows = 3;
  spec.square_size_m = 0.01;
  return spec;
}
}  // namespace detail

// Everything a simulation needs, read from the spec file.
struct SimulationSpec {
  std::filesystem::path file;  // the spec (relative paths inside are relative to it)
  calibration::Camera camera;
  // Replaced by the spec's target; a placeholder because Target has no empty state.
  metrology::Target target{detail::placeholderTargetSpec()};
  RenderOptions render;
  NoiseOptions noise;
  std::uint64_t seed = 1;
  CalibrationViewsSpec calibration;
  int images_per_view = 1;           // calibration: noisy images per view (view_XXX.png, view_XXX_YY.png)
  std::vector<SimulatedPose> poses;  // poses: explicit list, or generated from `grid`
  bool poses_from_grid = true;
  PoseGridSpec grid;
  int images_per_pose = 10;
  // How the images are written (spec key `png: compressed | stored`, png.hpp).
  PngEncoding png = PngEncoding::Compressed;
};

// Reads a spec; throws std::runtime_error naming the file and the key on any problem.
SimulationSpec readSimulationSpec(const std::filesystem::path& path);

// Called after each image written (for a progress bar): images done, images in total.
using ProgressCallback = std::function<void(std::size_t done, std::size_t total)>;

struct SimulationResult {
  std::size_t images = 0;  // images written
  std::size_t views_or_poses = 0;
  double visible_fraction = 0.0;  // of all features over all views/poses
};

// Writes DIR/images/view_XXX.png, DIR/camera.yaml, DIR/target.yaml and DIR/truth.yaml
// (every view's cTm and projected features). All files written atomically.
SimulationResult simulateCalibration(const SimulationSpec& spec, const std::filesystem::path& output_dir,
                                     const ProgressCallback& progress = {});

// Writes DIR/poses/<pose_id>/img_XX.png (images_per_pose noisy images of one clean render),
// DIR/camera.yaml, DIR/target.yaml, DIR/truth.yaml and DIR/truth_poses.csv (the true cTm in
// poses.csv's columns, doc/file-formats.md, σ = 0).
SimulationResult simulatePoses(const SimulationSpec& spec, const std::filesystem::path& output_dir,
                               const ProgressCallback& progress = {});

}  // namespace mire::datasets
