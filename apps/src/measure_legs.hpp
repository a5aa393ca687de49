#pragma once
// `mire measure --legs legs.yaml --joints joints.csv` (doc/legs.md "Measuring a leg", doc/cli.md
// "measure"): every observable leg's axis at every pose with its 4×4 covariance, written to
// legs.csv (pipeline/leg_measurement.hpp).
#include <string>

namespace mire::app {

struct LegMeasureArguments {
  std::string camera, legs, joints, poses, output, save_contours;
  int threads = 0;
};

// Exit code (kPartialFailure when a pose or a leg was not measured); bad input throws.
int runLegMeasure(const LegMeasureArguments& args);

}  // namespace mire::app
