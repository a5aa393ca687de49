#pragma once
// Inputs of `mire plan` and `mire select` (doc/plan-and-select.md): the nominal geometry of a
// registered model, the workspace YAML and the mounting guess YAML. Errors name the file, the
// line and the key.
#include <filesystem>
#include <string>

#include "mire/mechanism/experiment_design.hpp"

namespace mire::app {

// The registry entry `name` with its nominal geometry from `nominal_yaml` (empty: built-in), read
// as `mire identify --nominal` reads it (pipeline::applyNominalFile).
mechanism::DesignModel readDesignModel(const std::string& name, const std::filesystem::path& nominal_yaml);

// workspace.yaml: x_m, y_m, z_m: [min, max] (base frame, m); theta_deg (H4) or rx_deg, ry_deg,
// rz_deg (6 DoF) as [min, max]; none for the Delta; optional shape: box|cylinder,
// joint_margin_deg (revolute joints) or joint_margin_m (prismatic). Unknown keys are errors.
mechanism::Workspace readWorkspaceYaml(const std::filesystem::path& path, const mechanism::Mechanism& mechanism);

// mounting.yaml: the full-form mounting tx_CB ty_CB tz_CB rx_CB ry_CB rz_CB (cTb) and
// tx_EM ty_EM tz_EM rx_EM ry_EM rz_EM (eTm), SI, rotation vectors — the names `mire identify`
// writes for the Delta and the Gough–Stewart platform. With the camera on the effector, the
// names `mire identify --mounting camera-on-effector` writes: tx_EC..rz_EC (eTc) and
// tx_BM..rz_BM (bTm). All twelve are required.
mechanism::MountingGuess readMountingYaml(const std::filesystem::path& path, bool camera_on_effector = false);

// The design model with the camera on the effector when `camera_on_effector` (the
// camera-on-effector external form, as `mire identify --mounting camera-on-effector`); a model
// whose mounting form assumes the camera fixed (the H4's axis-aligned and camera-frame forms,
// paper §4) is refused by name: UsageError "--mounting camera-on-effector: <what> <model> (...)".
mechanism::DesignModel withMounting(mechanism::DesignModel model, bool camera_on_effector, const std::string& what);

}  // namespace mire::app
