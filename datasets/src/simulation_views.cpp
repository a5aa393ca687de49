// Where the simulated target goes: calibration views and the effector pose grid.
#include "mire/datasets/campaign_images.hpp"
#include "mire/datasets/simulation.hpp"
#include "mire/support/constants.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <stdexcept>

namespace mire::datasets {
namespace {

using support::kPi;
using support::kRadiansPerDegree;

// True when every feature, and the board's outline one feature spacing beyond them (a
// chessboard's outer squares, a grid's quiet zone), projects inside the image by `margin`.
bool fitsInImage(const calibration::Camera& camera, const metrology::Target& target, const Eigen::Isometry3d& pose,
                 double margin) {
  std::vector<Eigen::Vector3d> points = target.points();
  double min_x = points[0].x(), max_x = min_x, min_y = points[0].y(), max_y = min_y;
  for (const auto& p : points)
    min_x = std::min(min_x, p.x()), max_x = std::max(max_x, p.x()), min_y = std::min(min_y, p.y()),
    max_y = std::max(max_y, p.y());
  const double spacing = target.featureSpacing();
  for (const double x : {min_x - spacing, max_x + spacing})
    for (const double y : {min_y - spacing, max_y + spacing}) points.emplace_back(x, y, 0.0);
  for (const auto& point : points) {
    Eigen::Vector2d pixel;
    if (!camera.project(pose * point, &pixel)) return false;
    if (pixel.x() < margin || pixel.y() < margin || pixel.x() > camera.width - 1 - margin ||
        pixel.y() > camera.height - 1 - margin)
      return false;
  }
  return true;
}

std::vector<int> shuffled(int count, std::mt19937_64& random) {
  std::vector<int> order(static_cast<std::size_t>(count));
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), random);
  return order;
}

}  // namespace

Eigen::Isometry3d placeTarget(const calibration::Camera& camera, const metrology::Target& target,
                              const ViewPlacement& placement) {
  Eigen::Vector2d ray;
  if (!camera.unproject(placement.centre_pixel, &ray))
    throw std::invalid_argument("placeTarget: the centre pixel is outside the lens's field");
  // Facing the camera: target x, y along the image's u, v; z (into the board) along the
  // optical axis. Then the tilt about an in-plane axis, then the roll about the axis.
  const Eigen::Vector3d tilt_axis(std::cos(placement.tilt_axis_rad), std::sin(placement.tilt_axis_rad), 0.0);
  const Eigen::Matrix3d rotation =
      (Eigen::AngleAxisd(placement.roll_rad, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(placement.tilt_rad, tilt_axis))
          .toRotationMatrix();
  const Eigen::Vector3d centre = placement.distance_m * Eigen::Vector3d(ray.x(), ray.y(), 1.0).normalized();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  pose.translation() = centre - rotation * targetCentroid(target);
  return pose;
}

std::vector<Eigen::Isometry3d> generateCalibrationViews(const calibration::Camera& camera,
                                                        const metrology::Target& target,
                                                        const CalibrationViewsSpec& spec, std::uint64_t seed) {
  if (spec.views < 1) throw std::invalid_argument("calibration views must be at least 1");
  if (!(spec.min_distance_m > 0.0) || !(spec.max_distance_m >= spec.min_distance_m))
    throw std::invalid_argument("calibration distance range must be positive and ordered");
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Stratified samples: each view gets its own slice of distance, tilt and image position,
  // so that even a few views spread over the whole range (corners of the image included).
  const std::vector<int> distance_slot = shuffled(spec.views, random);
  const std::vector<int> tilt_slot = shuffled(spec.views, random);
  const int grid_cols = std::max(1, static_cast<int>(std::ceil(std::sqrt(spec.views * 4.0 / 3.0))));
  const int grid_rows = std::max(1, (spec.views + grid_cols - 1) / grid_cols);
  const std::vector<int> cell_slot = shuffled(grid_cols * grid_rows, random);
  const Eigen::Vector2d image_centre(camera.cx(), camera.cy());

  std::vector<Eigen::Isometry3d> views;
  for (int k = 0; k < spec.views; ++k) {
    ViewPlacement placement;
    placement.distance_m = spec.min_distance_m +
                           (spec.max_distance_m - spec.min_distance_m) * (distance_slot[k] + unit(random)) / spec.views;
    placement.tilt_rad = spec.max_tilt_deg * kRadiansPerDegree * (tilt_slot[k] + unit(random)) / spec.views;
    placement.tilt_axis_rad = 2.0 * kPi * unit(random);
    placement.roll_rad = spec.max_roll_deg * kRadiansPerDegree * (2.0 * unit(random) - 1.0);
    const int cell = cell_slot[static_cast<std::size_t>(k)];
    const int column = cell % grid_cols, row = cell / grid_cols;
    // Cell corners reach the image corners: the board is pushed there, then pulled back
    // toward the centre until it fits.
    const double fu = grid_cols == 1 ? 0.5 : (column + unit(random) * 0.3) / (grid_cols - 1 + 0.3);
    const double fv = grid_rows == 1 ? 0.5 : (row + unit(random) * 0.3) / (grid_rows - 1 + 0.3);
    Eigen::Vector2d wanted(fu * (camera.width - 1), fv * (camera.height - 1));
    Eigen::Isometry3d pose;
    bool fits = false;
    for (int attempt = 0; attempt < 200 && !fits; ++attempt) {
      placement.centre_pixel = wanted;
      pose = placeTarget(camera, target, placement);
      fits = fitsInImage(camera, target, pose, spec.margin_px);
      if (fits) break;
      wanted = image_centre + 0.9 * (wanted - image_centre);
      if (attempt % 10 == 9) placement.distance_m *= 1.05;  // too big for the image: step back
      if (attempt % 40 == 39) placement.tilt_rad *= 0.8;
    }
    if (!fits)
      throw std::runtime_error("cannot fit the target in the image for calibration view " + std::to_string(k) +
                               " (distance range too small for this target and camera?)");
    views.push_back(pose);
  }
  return views;
}

Eigen::Isometry3d poseGridCamera(const metrology::Target& /*target*/, const PoseGridSpec& spec) {
  // Looking down -z_B at the grid centre (the origin of B): camera x = x_B, y = -y_B,
  // z = -z_B, then tilted about x_B, then moved back along its optical axis.
  Eigen::Matrix3d down;
  down << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  Eigen::Isometry3d base_T_camera = Eigen::Isometry3d::Identity();
  base_T_camera.linear() = Eigen::AngleAxisd(spec.camera_tilt_deg * kRadiansPerDegree, Eigen::Vector3d::UnitX()) * down;
  base_T_camera.translation() = -spec.camera_distance_m * base_T_camera.linear().col(2);
  return base_T_camera;
}

std::vector<SimulatedPose> generatePoseGrid(const metrology::Target& target, const PoseGridSpec& spec) {
  if ((spec.counts.array() < 1).any()) throw std::invalid_argument("pose grid counts must be at least 1");
  if (spec.theta_deg.empty()) throw std::invalid_argument("pose grid needs at least one theta");
  const Eigen::Isometry3d camera_T_base = poseGridCamera(target, spec).inverse();
  // eTm: the board's centre on the effector, its printed face looking down (-z_E) at the
  // camera: target z (into the board) = -z_E, hence a half turn about x.
  Eigen::Isometry3d effector_T_target = Eigen::Isometry3d::Identity();
  effector_T_target.linear() = Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX()).toRotationMatrix();
  effector_T_target.translation() = -(effector_T_target.linear() * targetCentroid(target));
  std::vector<SimulatedPose> poses;
  const auto axis = [&](int i, int index) {
    const int count = spec.counts[i];
    return count == 1 ? 0.0 : spec.size_m[i] * (static_cast<double>(index) / (count - 1) - 0.5);
  };
  for (int iz = 0; iz < spec.counts.z(); ++iz)
    for (int iy = 0; iy < spec.counts.y(); ++iy)
      for (int ix = 0; ix < spec.counts.x(); ++ix)
        for (const double theta_deg : spec.theta_deg) {
          SimulatedPose pose;
          char id[16];
          std::snprintf(id, sizeof id, "p%03d", static_cast<int>(poses.size()) + 1);
          pose.id = id;
          pose.has_effector = true;
          pose.effector = Eigen::Vector4d(axis(0, ix), axis(1, iy), axis(2, iz), theta_deg * kRadiansPerDegree);
          Eigen::Isometry3d base_T_effector = Eigen::Isometry3d::Identity();
          base_T_effector.linear() = Eigen::AngleAxisd(pose.effector[3], Eigen::Vector3d::UnitZ()).toRotationMatrix();
          base_T_effector.translation() = pose.effector.head<3>();
          pose.camera_T_target = camera_T_base * base_T_effector * effector_T_target;
          poses.push_back(pose);
        }
  return poses;
}

}  // namespace mire::datasets
