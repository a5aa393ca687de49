#include "mire/datasets/campaign_images.hpp"

#include "mire/support/yaml.hpp"

#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>

namespace mire::datasets {
namespace fs = std::filesystem;
namespace {

// Moves a file the simulator wrote beside the images into the truth folder.
void moveToTruth(const fs::path& from, const fs::path& truth_dir, const std::string& name) {
  if (!fs::exists(from)) return;
  fs::create_directories(truth_dir);
  fs::rename(from, truth_dir / name);
}

}  // namespace

void renderCampaignImages(const SimulationSpec& simulation, const fs::path& directory, const fs::path& truth_dir,
                          const ProgressCallback& progress) {
  const std::size_t calibration_images =
      static_cast<std::size_t>(simulation.calibration.views) * static_cast<std::size_t>(simulation.images_per_view);
  const std::size_t total =
      calibration_images + simulation.poses.size() * static_cast<std::size_t>(simulation.images_per_pose);
  const auto offset_progress = [&](std::size_t offset) -> ProgressCallback {
    if (!progress) return {};
    return [&progress, offset, total](std::size_t done, std::size_t) { progress(offset + done, total); };
  };

  // A previous campaign in the same folder: its images go (a smaller run would leave stale
  // views behind, and renaming onto a non-empty poses/ folder fails).
  const fs::path calibration_dir = directory / "calibration";
  const fs::path pose_images = directory / "poses";
  fs::remove_all(calibration_dir / "images");
  fs::remove_all(pose_images);
  simulateCalibration(simulation, calibration_dir, offset_progress(0));
  moveToTruth(calibration_dir / "camera.yaml", truth_dir, "camera.yaml");
  moveToTruth(calibration_dir / "truth.yaml", truth_dir, "calibration_truth.yaml");
  fs::remove(calibration_dir / "target.yaml");

  const fs::path measurement_dir = directory / "measurement";
  fs::remove_all(measurement_dir);  // left by an interrupted run
  simulatePoses(simulation, measurement_dir, offset_progress(calibration_images));
  fs::rename(measurement_dir / "poses", pose_images);
  moveToTruth(measurement_dir / "truth.yaml", truth_dir, "poses_truth.yaml");
  moveToTruth(measurement_dir / "truth_poses.csv", truth_dir, "poses_truth.csv");
  fs::remove_all(measurement_dir);
}

void checkTargetInView(const SimulationSpec& simulation, const std::string& what) {
  constexpr double kMargin = 10.0;
  const calibration::Camera& camera = simulation.camera;
  for (const SimulatedPose& pose : simulation.poses)
    for (const Eigen::Vector3d& point : simulation.target.points()) {
      Eigen::Vector2d pixel;
      const Eigen::Vector3d in_camera = pose.camera_T_target * point;
      const bool inside = in_camera.z() > 0.0 && camera.project(in_camera, &pixel) && pixel.x() >= kMargin &&
                          pixel.y() >= kMargin && pixel.x() <= camera.width - 1 - kMargin &&
                          pixel.y() <= camera.height - 1 - kMargin;
      if (!inside) throw std::runtime_error(what + ": the target leaves the image at pose " + pose.id);
    }
}

std::string campaignPoseId(std::size_t index) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "p%03zu", index + 1);
  return buffer;
}

Eigen::Vector3d targetCentroid(const metrology::Target& target) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& point : target.points()) sum += point;
  return sum / static_cast<double>(target.points().size());
}

std::string isometryYaml(const std::string& key, const Eigen::Isometry3d& transform) {
  std::ostringstream out;
  out << key << ": [";
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      out << support::formatYamlNumber(transform.matrix()(r, c)) << (r == 3 && c == 3 ? "" : ", ");
  out << "]\n";
  return out.str();
}

}  // namespace mire::datasets
