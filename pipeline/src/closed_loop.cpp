// The ISO 9283 test before and after compensation (closed_loop.hpp).
#include "mire/pipeline/closed_loop.hpp"

#include <stdexcept>

#include "mire/metrology/feature_averaging.hpp"
#include "mire/metrology/pose_estimation.hpp"

namespace mire::pipeline {
namespace mech = mire::mechanism;

namespace {

AccuracyResult accuracyOf(const mech::PredictionModel& identified, const Eigen::VectorXd& controller,
                          const datasets::TrueRobotReach& reach, const Eigen::Isometry3d& bTc,
                          const Eigen::Isometry3d& mTe, const datasets::Iso9283Spec& spec,
                          const datasets::CameraReading& camera) {
  const mech::Mechanism& m = *identified.mechanism;
  const datasets::Iso9283Test test = datasets::simulateIso9283Test(m, controller, reach, bTc, mTe, spec, camera);
  std::vector<CommandedPose> commanded;
  std::vector<mech::PoseRow> measured;
  for (std::size_t i = 0; i < test.ids.size(); ++i) {
    commanded.push_back({test.ids[i], test.positions[i], m.poseToTransform(test.commanded[i])});
    measured.push_back({test.measured[i], static_cast<int>(i) + 2});  // the line of poses.csv
  }
  return evaluateAccuracy(identified, commanded, measured, "poses.csv", {});
}

}  // namespace

datasets::CameraReading calibratedCameraReading(const calibration::Camera& truth, const calibration::Camera& calibrated,
                                                const metrology::Target& target) {
  const std::vector<Eigen::Vector3d> points = target.points();
  return [truth, calibrated, points](const Eigen::Isometry3d& cTm) {
    metrology::AveragedFeatures features;
    for (std::size_t k = 0; k < points.size(); ++k) {
      Eigen::Vector2d pixel;
      if (!truth.project(cTm * points[k], &pixel)) continue;
      features.ids.push_back(static_cast<int>(k));
      features.pixels.push_back(pixel);
      features.covariance.push_back(Eigen::Matrix2d::Identity() * 1e-4);  // weights only: no noise here
      features.observations.push_back(1);
    }
    features.images_used = features.images_total = 1;
    const metrology::PoseEstimate estimate = metrology::estimatePose(calibrated, points, features);
    if (!estimate.valid)
      throw std::runtime_error("closed loop: the calibrated camera sees no pose: " + estimate.reason);
    return mech::toPoseVector(estimate.cTm);
  };
}

ClosedLoopTest closedLoopTest(const mech::PredictionModel& identified, const Eigen::VectorXd& nominal,
                              const datasets::TrueRobotReach& reach, const Eigen::Isometry3d& bTc,
                              const Eigen::Isometry3d& mTe, const datasets::Iso9283Spec& spec,
                              const datasets::CameraReading& camera) {
  ClosedLoopTest out;
  out.spec = spec;
  out.before = accuracyOf(identified, nominal, reach, bTc, mTe, spec, camera);
  datasets::Iso9283Spec after = spec;
  ++after.seed;  // new cycles: the robot's scatter and the camera's noise are not the same twice
  out.after = accuracyOf(identified, identified.geometric.values(), reach, bTc, mTe, after, camera);
  return out;
}

}  // namespace mire::pipeline
