#pragma once
// Joint commands for desired effector poses with an identified model (`mire ikm`, `mire compensate
// --poses`; doc/mechanisms.md): joints.csv columns plus σ, unreachable or out-of-stroke poses named.
#include <Eigen/Core>

#include <string>
#include <vector>

#include "kinematics_files.hpp"
#include "mire/mechanism/prediction.hpp"

namespace mire::app {

struct JointCommandTable {
  std::string csv;  // pose_id, the joint columns, sigma_<joint column>
  std::size_t written = 0;
  std::vector<Eigen::VectorXd> sigmas;   // per written pose, the command's σ per joint (rad or m)
  std::vector<std::string> unreachable;  // "<poses>:<line>: pose 'id' is unreachable (joint(s) 1, 3)"
};
JointCommandTable jointCommandTable(const mechanism::PredictionModel& model, const std::vector<EffectorRow>& rows,
                                    const std::string& poses_name);

}  // namespace mire::app
