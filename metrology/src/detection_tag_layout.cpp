// Keeping the square markers (AprilTags, ArUco markers) that fit a target's layout, when the
// scene holds ids that are not on the target or repeats some (doc/targets.md, "Repeated and
// foreign ids").
#include "detection_internal.hpp"

#include <opencv2/calib3d.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace mire::metrology::detail {
namespace {

// Mean side length of an instance in the image (px).
double sidePx(const SquareInstance& instance) {
  double sum = 0.0;
  for (int j = 0; j < 4; ++j) sum += (instance.corners[j] - instance.corners[(j + 1) % 4]).norm();
  return 0.25 * sum;
}

double areaPx(const SquareInstance& instance) {
  double twice = 0.0;
  for (int j = 0; j < 4; ++j) {
    const Eigen::Vector2d& a = instance.corners[j];
    const Eigen::Vector2d& b = instance.corners[(j + 1) % 4];
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * std::abs(twice);
}

// Homography frame M -> image from every corner of the chosen instances (least squares).
cv::Matx33d fitHomography(const SquareLayout& layout, const std::vector<SquareInstance>& instances,
                          const std::vector<int>& chosen) {
  std::vector<cv::Point2d> model, image;
  for (const int i : chosen) {
    const auto& corners_m = layout.at(instances[i].id);
    for (int j = 0; j < 4; ++j) {
      model.emplace_back(corners_m[j].x(), corners_m[j].y());
      image.emplace_back(instances[i].corners[j].x(), instances[i].corners[j].y());
    }
  }
  const cv::Mat h = cv::findHomography(model, image, 0);
  return h.empty() ? cv::Matx33d::zeros() : cv::Matx33d(h);
}

// Largest corner distance (px) between an instance and the homography's prediction of it.
double misfitPx(const cv::Matx33d& h, const std::array<Eigen::Vector2d, 4>& corners_m, const SquareInstance& instance) {
  double worst = 0.0;
  for (int j = 0; j < 4; ++j) {
    const cv::Vec3d p = h * cv::Vec3d(corners_m[j].x(), corners_m[j].y(), 1.0);
    if (!(std::abs(p[2]) > 1e-12)) return std::numeric_limits<double>::infinity();
    worst = std::max(worst, std::hypot(p[0] / p[2] - instance.corners[j].x(), p[1] / p[2] - instance.corners[j].y()));
  }
  return worst;
}

struct Group {
  std::vector<int> members;  // instance indices, one per id
  double misfit_sum = 0.0;
  double area = 0.0;
};

// Grows a group from one seed instance: fit a homography on the group, add for every other id
// the available instance it predicts best if within one marker side (ids on a target are at
// least one side apart, so a wrong instance misses by more; lens distortion over the board
// stays well below it), refit, three rounds.
Group growGroup(const SquareLayout& layout, const std::vector<SquareInstance>& instances,
                const std::vector<bool>& available, int seed) {
  Group group;
  group.members = {seed};
  for (int round = 0; round < 3; ++round) {
    const cv::Matx33d h = fitHomography(layout, instances, group.members);
    std::map<int, std::pair<double, int>> best;  // id -> (misfit, instance)
    for (std::size_t i = 0; i < instances.size(); ++i) {
      if (!available[i] || static_cast<int>(i) == seed || instances[i].id == instances[seed].id) continue;
      const double misfit = misfitPx(h, layout.at(instances[i].id), instances[i]);
      if (misfit > sidePx(instances[i])) continue;
      auto [entry, inserted] = best.emplace(instances[i].id, std::make_pair(misfit, static_cast<int>(i)));
      if (!inserted && misfit < entry->second.first) entry->second = {misfit, static_cast<int>(i)};
    }
    std::vector<int> members = {seed};
    double misfit_sum = 0.0;
    for (const auto& [id, entry] : best) members.push_back(entry.second), misfit_sum += entry.first;
    const bool unchanged = members == group.members;
    group.members = members;
    group.misfit_sum = misfit_sum;
    if (unchanged) break;
  }
  for (const int i : group.members) group.area += areaPx(instances[i]);
  return group;
}

bool better(const Group& a, const Group& b) {
  if (a.members.size() != b.members.size()) return a.members.size() > b.members.size();
  if (a.area != b.area) return a.area > b.area;
  return a.misfit_sum < b.misfit_sum;
}

}  // namespace

std::vector<std::vector<int>> groupLayoutInstances(const SquareLayout& layout,
                                                   const std::vector<SquareInstance>& instances) {
  std::vector<bool> available(instances.size(), false);
  for (std::size_t i = 0; i < instances.size(); ++i) available[i] = layout.count(instances[i].id) > 0;
  std::vector<std::vector<int>> groups;
  while (std::find(available.begin(), available.end(), true) != available.end()) {
    Group best;
    for (std::size_t seed = 0; seed < instances.size(); ++seed) {
      if (!available[seed]) continue;
      Group group = growGroup(layout, instances, available, static_cast<int>(seed));
      if (best.members.empty() || better(group, best)) best = std::move(group);
    }
    for (const int i : best.members) available[i] = false;
    std::sort(best.members.begin(), best.members.end(), [&](int a, int b) { return instances[a].id < instances[b].id; });
    groups.push_back(best.members);
  }
  return groups;
}

std::vector<Detection> layoutDetections(const Target& target, const std::vector<SquareInstance>& instances,
                                        const DetectionOptions& options, const std::string& what) {
  const SquareLayout layout = squareLayout(target);
  const std::vector<std::vector<int>> groups = groupLayoutInstances(layout, instances);
  std::size_t on_target = 0;
  for (const SquareInstance& instance : instances) on_target += layout.count(instance.id);
  const std::size_t expected = layout.size();
  std::vector<Detection> candidates;
  for (const std::vector<int>& group : groups) {
    Detection detection;
    for (const int i : group) {
      const int k = target.tagIndex(instances[i].id);
      for (int j = 0; j < 4; ++j) {
        detection.ids.push_back(4 * k + j);
        detection.pixels.push_back(instances[i].corners[j]);
      }
    }
    detection.found = group.size() == expected || options.allow_partial;
    if (group.size() < expected)
      detection.reason = std::to_string(group.size()) + " of " + std::to_string(expected) + " " + what + " found";
    const std::size_t others = on_target - group.size();
    if (others > 0)
      detection.reason += (detection.reason.empty() ? "" : "; ") + std::to_string(others) +
                          " other instance(s) of the " + what + " ids, not fitting this group, left out";
    candidates.push_back(std::move(detection));
  }
  return candidates;
}

SquareLayout squareLayout(const Target& target) {
  SquareLayout layout;
  const auto& points = target.points();
  for (std::size_t k = 0; k < target.tagLayout().size(); ++k) {
    std::array<Eigen::Vector2d, 4> corners;
    for (int j = 0; j < 4; ++j) corners[j] = points[4 * k + j].head<2>();
    layout.emplace(target.tagLayout()[k].id, corners);
  }
  return layout;
}

}  // namespace mire::metrology::detail
