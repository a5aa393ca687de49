#pragma once
// The ISO 9283 test of a robot (doc/accuracy.md): commanded effector poses grouped by position,
// the measured target poses of the cycles, turned into attained effector poses through the
// identified mounting (cTb, eTm), then pose accuracy and repeatability, distance accuracy and the
// straightness of measured straight-line motions (mechanism/pose_accuracy.hpp).
#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "mire/mechanism/io.hpp"
#include "mire/mechanism/pose_accuracy.hpp"
#include "mire/mechanism/prediction.hpp"

namespace mire::pipeline {

struct CommandedPose {
  std::string id, position;
  Eigen::Isometry3d bTe = Eigen::Isometry3d::Identity();
};

// A measured pose along a straight-line motion.
struct LinePose {
  std::string line;
  mechanism::PoseRow measured;
};

struct AccuracyResult {
  std::vector<mechanism::PositionAccuracy> positions;
  std::vector<mechanism::DistanceAccuracy> distances;
  std::vector<mechanism::LineStraightness> lines;
  std::vector<std::string> unmeasured;  // commanded ids without a measured pose
  int cycles_used = 0;
};

// Pairs commanded and measured poses by id (measured poses without a command are an error naming
// the poses file's line; commands without a measurement are listed in `unmeasured`). Throws
// std::runtime_error when no command was measured, std::invalid_argument from the ISO figures
// (a position with one cycle).
AccuracyResult evaluateAccuracy(const mechanism::PredictionModel& model, const std::vector<CommandedPose>& commanded,
                                const std::vector<mechanism::PoseRow>& measured, const std::string& poses_file,
                                const std::vector<LinePose>& line_poses, const mechanism::AccuracyOptions& options = {});

}  // namespace mire::pipeline
