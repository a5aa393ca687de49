#pragma once
// Kalibr's target files read as mire targets (doc/targets.md, "Kalibr aprilgrid").
#include "mire/metrology/target.hpp"
#include "mire/support/yaml.hpp"

namespace mire::metrology::detail {

// True when the file is Kalibr's (its `target_type` key) rather than mire's (`type`).
bool isKalibrTarget(const support::YamlNode& root);

// Kalibr's aprilgrid (target_type, tagCols, tagRows, tagSize, tagSpacing) as a mire AprilTag
// layout; any other Kalibr target_type is refused by name. Errors name the file, line and key.
TargetSpec kalibrTargetSpec(const support::YamlNode& root);

}  // namespace mire::metrology::detail
