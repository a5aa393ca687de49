#pragma once
// The image folders of a simulated campaign (the H4 demo's and the mechanism demos'):
// DIR/calibration/images/ (calibration views) and DIR/poses/<pose_id>/ (images per pose),
// rendered from one SimulationSpec, with the simulator's truth files moved to a truth folder.
#include <Eigen/Geometry>

#include <filesystem>
#include <string>

#include "mire/datasets/simulation.hpp"

namespace mire::datasets {

// The simulator's input common to the campaigns: their camera, target, rendering, noise, seed,
// calibration views and images per pose (`CampaignSpec` has those fields:
// MechanismImageCampaignSpec); the caller adds one SimulatedPose per protocol pose.
template <class CampaignSpec>
SimulationSpec campaignSimulationBase(const CampaignSpec& spec, const calibration::Camera& camera,
                                      const metrology::Target& target) {
  SimulationSpec simulation;
  simulation.camera = camera;
  simulation.target = target;
  simulation.render = spec.render;
  simulation.noise = spec.noise;
  simulation.seed = spec.seed;
  simulation.png = spec.png;
  simulation.calibration.views = spec.calibration_views;
  simulation.images_per_pose = spec.images_per_pose;
  simulation.poses_from_grid = false;
  return simulation;
}

// Throws std::runtime_error("<what>: the target leaves the image at pose <id>") unless every
// target feature projects at least 10 px inside the image at every pose of `simulation` (the
// measurement needs the whole board).
void checkTargetInView(const SimulationSpec& simulation, const std::string& what);

// Renders the calibration views, then the poses (one progress count over both), into
// `directory`'s calibration/images and poses folders (a previous campaign's images there are
// removed first), and moves the simulator's camera.yaml, truth.yaml and truth_poses.csv to
// `truth_dir` as camera.yaml, calibration_truth.yaml, poses_truth.yaml and poses_truth.csv.
void renderCampaignImages(const SimulationSpec& simulation, const std::filesystem::path& directory,
                          const std::filesystem::path& truth_dir, const ProgressCallback& progress);

// The campaigns' pose ids: p001, p002, … (index 0 → p001); they name the pose folders.
std::string campaignPoseId(std::size_t index);

// Mean of the target's feature points (frame M): where the campaigns centre the board.
Eigen::Vector3d targetCentroid(const metrology::Target& target);

// `key: [16 numbers]`, the 4 × 4 matrix row by row, as the campaigns' truth files write their
// mountings (numbers PyYAML also reads as floats, doc/file-formats.md).
std::string isometryYaml(const std::string& key, const Eigen::Isometry3d& transform);

}  // namespace mire::datasets
