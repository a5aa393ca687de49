#pragma once
// Files of `mire fkm` / `mire ikm` (doc/mechanisms.md): effector poses in the base frame
// (one column per pose component, `<name>_<unit>`, σ columns in mm/deg), the camera-frame
// prediction in poses.csv's format with its covariance side file.
#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

#include "mire/mechanism/io.hpp"
#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/prediction.hpp"

namespace mire::app {

// "x_m", "theta_rad", ... for the mechanism's pose components.
std::vector<std::string> poseColumnNames(const mechanism::Mechanism& mechanism);

struct EffectorRow {
  std::string id;
  Eigen::VectorXd pose;
  int line = 0;
  std::string group;  // the `group_column` cell, when one is asked for
};
// Reads effector.csv (pose_id + poseColumnNames(), + `group_column` when not empty: accuracy's
// `position`); errors name file:line. Rotations beyond 2π rad (degrees typed in a _rad column)
// and lengths beyond 100 m (millimetres in a _m column) are refused with the file, the line and
// the likely unit.
std::vector<EffectorRow> readEffectorCsv(const std::filesystem::path& path, const mechanism::Mechanism& mechanism,
                                         const std::string& group_column = {});

// The same unit check on joint readings (joints.csv of fkm): q<i>_rad beyond 2π, q<i>_m beyond
// 100 m.
void checkJointUnits(const std::vector<mechanism::JointRow>& rows, const mechanism::Mechanism& mechanism,
                     const std::string& file);

}  // namespace mire::app
