#pragma once
// Checks of a simulation spec beyond the reader's (which checks one key at a time): the
// camera within the image limits of doc/limits.md, pose ids that are distinct folder names,
// finite poses with the target in front of the camera. Messages name the spec and the pose.
#include "mire/datasets/simulation.hpp"

namespace mire::app {

void checkSimulationSpec(const datasets::SimulationSpec& spec, bool poses);

}  // namespace mire::app
