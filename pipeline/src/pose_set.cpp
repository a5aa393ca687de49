// A measured campaign as identification reads it (pose_set.hpp).
#include "mire/pipeline/pose_set.hpp"

#include "mire/support/side_files.hpp"

namespace mire::pipeline {
namespace fs = std::filesystem;

PoseSetFiles PoseSetFiles::beside(const fs::path& poses, const fs::path& joints) {
  PoseSetFiles files;
  files.poses = poses;
  files.joints = joints;
  if (const fs::path covariances = support::covarianceSidePath(poses); fs::exists(covariances))
    files.covariances = covariances;
  if (const fs::path shared = support::sharedTermSidePath(poses); fs::exists(shared)) files.shared = shared;
  return files;
}

std::vector<std::vector<Eigen::VectorXd>> PoseSet::lineJoints() const {
  std::vector<std::vector<Eigen::VectorXd>> joints;
  for (const auto& line : lines) joints.push_back(line.joints);
  return joints;
}

PoseSet readPoseSet(const PoseSetFiles& files, const std::vector<std::string>& joint_columns) {
  PoseSet set;
  set.observations = mechanism::readObservations(files.poses, files.joints, files.covariances, joint_columns);
  if (files.shared) set.shared = mechanism::readSharedTermCsv(*files.shared);
  if (files.lines) set.lines = mechanism::readLinesCsv(*files.lines, joint_columns);
  return set;
}

}  // namespace mire::pipeline
