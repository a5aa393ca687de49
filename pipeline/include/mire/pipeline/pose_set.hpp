#pragma once
// A measured campaign as identification reads it (doc/file-formats.md): poses.csv with its
// covariance side file, joints.csv, the calibration's shared term (`<stem>_shared.csv`,
// doc/uncertainty.md) and the straight-line records of criterion V3.
#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mire/mechanism/identification_covariance.hpp"
#include "mire/mechanism/io.hpp"

namespace mire::pipeline {

struct PoseSetFiles {
  std::filesystem::path poses, joints;
  std::optional<std::filesystem::path> covariances;  // none: the σ columns of poses.csv
  std::optional<std::filesystem::path> shared;       // none: the poses' errors are independent
  std::optional<std::filesystem::path> lines;
  // poses.csv's side files where they exist, as `mire measure` writes them.
  static PoseSetFiles beside(const std::filesystem::path& poses, const std::filesystem::path& joints);
};

struct PoseSet {
  mechanism::ObservationSet observations;
  std::optional<mechanism::SharedPoseTerm> shared;
  std::vector<mechanism::LineRecord> lines;
  std::vector<std::vector<Eigen::VectorXd>> lineJoints() const;  // the records' joints, per line
};

// Reads every file named; throws std::runtime_error naming the file and line at fault.
PoseSet readPoseSet(const PoseSetFiles& files, const std::vector<std::string>& joint_columns);

}  // namespace mire::pipeline
