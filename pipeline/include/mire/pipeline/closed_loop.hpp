#pragma once
// The demos' last stage (doc/accuracy.md, "Closing the loop"): the paper's "modify the control law
// accordingly", checked the ISO 9283 way on the simulated true robot. The same test (5 positions,
// 30 cycles, datasets/iso9283_test.hpp) twice: before, the controller runs the nominal geometry;
// after, it sends the identified model's joint commands (`mire compensate --poses`). The commanded
// poses are in the identified base frame (the frame the camera's measurements define) and both
// tests are read through the identified mounting, as `mire accuracy` reads them.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mire/calibration/camera_model.hpp"
#include "mire/datasets/iso9283_test.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/metrology/target.hpp"
#include "mire/pipeline/accuracy.hpp"

namespace mire::pipeline {

struct ClosedLoopTest {
  datasets::Iso9283Spec spec;
  AccuracyResult before, after;
};

// The pose the calibrated camera reports for a true one (noise-free): the target's features
// projected by the true camera, the pose estimated with the calibrated one. The identification
// saw every pose through that camera: its mounting and geometry absorbed the calibration's error
// (about 0.2 mm at the demos' 1.9 m), and the test is read through them.
datasets::CameraReading calibratedCameraReading(const calibration::Camera& truth, const calibration::Camera& calibrated,
                                                const metrology::Target& target);

// `nominal`: the geometry the uncompensated controller runs (the identified model's parameter
// order); `reach`, bTc, mTe: the true robot and the true mountings (simulation only); `camera`:
// calibratedCameraReading(). Throws std::runtime_error when a position is out of reach.
ClosedLoopTest closedLoopTest(const mechanism::PredictionModel& identified, const Eigen::VectorXd& nominal,
                              const datasets::TrueRobotReach& reach, const Eigen::Isometry3d& bTc,
                              const Eigen::Isometry3d& mTe, const datasets::Iso9283Spec& spec,
                              const datasets::CameraReading& camera);

}  // namespace mire::pipeline
