#pragma once
// `mire identify --robot-poses`: hand-eye calibration of a robot that reports its own pose
// (doc/cli.md, "identify"; the solver is mechanism/hand_eye.hpp). Reads robot_poses.csv and
// poses.csv (with its covariance side file), writes the two transforms with σ and their
// covariance side file, prints the report.
#include <string>

namespace mire::app {

struct HandEyeIdentifyArguments {
  std::string robot_poses, poses, covariances, mounting, robot_sigma, output;
};

// Exit code; bad input throws (UsageError for the command line, std::runtime_error naming the
// file and line for a file).
int runHandEyeIdentify(const HandEyeIdentifyArguments& args);

}  // namespace mire::app
