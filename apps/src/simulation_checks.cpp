#include "simulation_checks.hpp"

#include "validate.hpp"

#include <set>
#include <stdexcept>

namespace mire::app {

void checkSimulationSpec(const datasets::SimulationSpec& spec, bool poses) {
  const std::string where = spec.file.string();
  checkCamera(spec.camera, spec.file);
  checkTargetSize(spec.target, spec.file);
  if (!poses) return;
  std::set<std::string> ids;
  for (const datasets::SimulatedPose& pose : spec.poses) {
    const std::string name = "pose '" + pose.id + "'";
    if (pose.id == "." || pose.id == ".." || pose.id.find_first_of("/\\,\"") != std::string::npos || pose.id.empty() ||
        pose.id[0] == '.')
      throw std::runtime_error(where + ": " + name +
                               ": an id must be a plain folder name (no '/', ',', '\"', no leading '.')");
    if (!ids.insert(pose.id).second)
      throw std::runtime_error(where + ": " + name + " appears twice (ids must be distinct)");
    if (!pose.camera_T_target.matrix().allFinite())
      throw std::runtime_error(where + ": " + name + ": non-finite t or r");
    // The target's features must lie in front of the camera (z > 0 in the camera frame).
    for (const Eigen::Vector3d& point : spec.target.points())
      if (!((pose.camera_T_target * point).z() > 0.0))
        throw std::runtime_error(where + ": " + name + ": the target is (partly) behind the camera (z <= 0)");
  }
}

}  // namespace mire::app
