// The ISO 9283 test of a robot from its measured cycles (accuracy.hpp).
#include "mire/pipeline/accuracy.hpp"

#include <map>
#include <stdexcept>

namespace mire::pipeline {
namespace mech = mire::mechanism;

namespace {

std::vector<mech::LineStraightness> straightnessOf(const mech::PredictionModel& model,
                                                   const std::vector<LinePose>& line_poses,
                                                   const mech::AccuracyOptions& options) {
  std::vector<std::string> order;
  std::map<std::string, std::pair<std::vector<Eigen::Vector3d>, std::vector<Eigen::Matrix3d>>> lines;
  bool all_covariances = true;
  for (const LinePose& p : line_poses) {
    const mech::AttainedPose a =
        mech::attainedPose(model.cTb(), model.eTm(), p.measured.observation.cTm, p.measured.observation.covariance);
    all_covariances = all_covariances && p.measured.observation.covariance.has_value();
    auto [it, inserted] = lines.try_emplace(p.line);
    if (inserted) order.push_back(p.line);
    it->second.first.push_back(a.bTe.translation());
    it->second.second.push_back(a.covariance.topLeftCorner<3, 3>());
  }
  std::vector<mech::LineStraightness> out;
  for (const std::string& id : order) {
    const auto& [points, covariances] = lines.at(id);
    out.push_back(
        mech::lineStraightness(id, points, all_covariances ? covariances : std::vector<Eigen::Matrix3d>{}, options));
  }
  return out;
}

}  // namespace

AccuracyResult evaluateAccuracy(const mech::PredictionModel& model, const std::vector<CommandedPose>& commanded,
                                const std::vector<mech::PoseRow>& measured, const std::string& poses_file,
                                const std::vector<LinePose>& line_poses, const mech::AccuracyOptions& options) {
  std::map<std::string, const CommandedPose*> by_id;
  for (const CommandedPose& c : commanded) by_id.emplace(c.id, &c);
  std::map<std::string, const mech::PoseRow*> measured_by_id;
  for (const mech::PoseRow& row : measured) {
    if (by_id.count(row.observation.id) == 0)
      throw std::runtime_error(poses_file + ":" + std::to_string(row.line) + ": measured pose '" + row.observation.id +
                               "' has no commanded pose of that pose_id");
    measured_by_id.emplace(row.observation.id, &row);
  }
  AccuracyResult result;
  std::vector<mech::AccuracySample> samples;
  for (const CommandedPose& c : commanded) {  // the commanded file's order: cycle j is the j-th row
    const auto it = measured_by_id.find(c.id);
    if (it == measured_by_id.end()) {
      result.unmeasured.push_back(c.id);
      continue;
    }
    const mech::PoseObservation& o = it->second->observation;
    const mech::AttainedPose a = mech::attainedPose(model.cTb(), model.eTm(), o.cTm, o.covariance);
    samples.push_back({c.id, c.position, c.bTe, a.bTe, a.covariance});
  }
  if (samples.empty()) throw std::runtime_error("no commanded pose was measured (no pose_id in common)");
  result.cycles_used = static_cast<int>(samples.size());
  result.positions = mech::poseAccuracy(samples, options);
  result.distances = mech::distanceAccuracy(samples, options);
  result.lines = straightnessOf(model, line_poses, options);
  return result;
}

}  // namespace mire::pipeline
