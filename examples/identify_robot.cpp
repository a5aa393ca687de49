// Identifies a parallel robot's geometry from measured target poses and encoder readings with the
// stage `mire identify` runs (mire/pipeline/identify.hpp): the nominal geometry, the external
// parameters (camera and target mounting) estimated from the data, the gauge found from the data,
// then the joint identification (Renaud et al. 2004, eq. 2/4) weighted by the measured pose
// covariances, with σ for every parameter (the camera calibration's shared error included when
// `mire measure` wrote poses_shared.csv).
//   identify_robot poses.csv joints.csv [model]      (model: h4-12 unless given; see mire identify --help)
#include "mire/mechanism/identification.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/pipeline/pose_set.hpp"

#include <cmath>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace mech = mire::mechanism;

// RMS of q̄ − f(cTm) over every joint of every pose the model reaches [rad].
double rmsJointResidual(const mech::IdentificationModel& model, const std::vector<mech::PoseObservation>& poses) {
  double sum = 0.0;
  int count = 0;
  for (const auto& pose : poses) {
    const auto predicted = model.predictJoints(pose.cTm);
    if (!predicted.reachable()) continue;
    sum += (pose.joints - predicted.joints).squaredNorm();
    count += static_cast<int>(pose.joints.size());
  }
  return count > 0 ? std::sqrt(sum / count) : NAN;
}

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: %s poses.csv joints.csv [model]\n", argv[0]);
    return 2;
  }
  try {
    const auto choice = mire::pipeline::chooseModel(argc == 4 ? argv[3] : "h4-12", "");
    // poses.csv with the side files `mire measure` writes beside it (covariances, shared term).
    const auto files = mire::pipeline::PoseSetFiles::beside(argv[1], argv[2]);
    const auto data = mire::pipeline::readPoseSet(files, choice.registered().mechanism->jointColumnNames());
    const auto& poses = data.observations.poses;
    const auto identification = mire::pipeline::identify(choice, poses, data.shared);
    const auto& initial = identification.initial.model;
    const auto& result = identification.result;

    std::printf("%s, %zu poses: joint residual rms %.3g rad (nominal) -> %.3g rad (identified), %s\n",
                choice.label().c_str(), poses.size(), rmsJointResidual(initial, poses), result.rms_joint_residual,
                result.converged ? "converged" : "NOT converged");
    for (const auto& name : result.free_names) {
      const auto& parameter = result.model.parameters.at(name);
      const std::string unit = mech::displayUnitName(parameter.unit);  // mm, deg
      std::printf("%-12s %12.5f %-3s  sigma %.5f\n", name.c_str(), mech::toDisplay(parameter.unit, parameter.value),
                  unit.c_str(), mech::toDisplay(parameter.unit, result.sigmaOf(name)));
    }
    return result.converged ? 0 : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "error: %s\n", error.what());
    return 1;
  }
}
