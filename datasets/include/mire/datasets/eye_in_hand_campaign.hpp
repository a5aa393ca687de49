#pragma once
// Simulated campaigns with the camera on the effector (doc/mechanisms.md, "Mounting"): the same
// robots, poses and noise as mechanism_campaign.hpp, the camera riding on the effector and the
// target fixed in the workspace, cTm = cTe · eTb(X) · bTm.
#include <Eigen/Geometry>

#include <random>
#include <utility>

#include "mire/datasets/mechanism_campaign.hpp"

namespace mire::datasets {

// The true eTc and bTm: a hexapod's camera looking up at a target 0.5 m above the platform's home,
// the others' looking down at a target 0.45 m below it; generic rotations, so that no parameter is
// accidentally aligned with an axis.
inline std::pair<Eigen::Isometry3d, Eigen::Isometry3d> eyeInHandMountings(const Mechanism& m,
                                                                          const Eigen::VectorXd& reference_pose) {
  const bool up = m.motionType() == MotionType::Spatial;
  const double side = up ? 1.0 : -1.0;
  const Eigen::Isometry3d eTc = makeTransform(up ? Eigen::Vector3d(0.05, -0.04, 0.3) : Eigen::Vector3d(3.05, 0.08, -0.2),
                                              Eigen::Vector3d(0.031, -0.022, 0.015 * side));
  const Eigen::Isometry3d bTm =
      makeTransform(up ? Eigen::Vector3d(-0.03, 0.06, 1.1) : Eigen::Vector3d(3.08, -0.06, 0.7),
                    Eigen::Vector3d(0.021, -0.017, reference_pose[2] + side * (up ? 0.5 : 0.45)));
  return {eTc, bTm};
}

struct EyeInHandCampaign {
  Campaign base;  // robot, truth, true bTe and joints; base.poses holds the eye-in-hand cTm
  Eigen::Isometry3d eTc, bTm;
  Eigen::Isometry3d cTm(std::size_t j) const { return eTc.inverse() * base.bTe[j].inverse() * bTm; }
};

// simulateCampaign()'s robot and poses seen by a camera on the effector, with the same noise
// (independent draws) and covariance on each measured cTm.
inline EyeInHandCampaign simulateEyeInHandCampaign(const RegisteredModel& model, const ParameterSet& truth,
                                                   unsigned seed, double noise_t = 0.2e-3,
                                                   double noise_r = 0.03 * kCampaignDeg, int extra = 0, int count = 0) {
  EyeInHandCampaign c;
  c.base = simulateCampaign(model, truth, seed, noise_t, noise_r, extra, count);
  const Mechanism& m = *c.base.model.mechanism;
  std::tie(c.eTc, c.bTm) = eyeInHandMountings(m, m.referencePose(truth.values()));
  std::mt19937 rng(seed + 3000);
  std::normal_distribution<double> normal;
  for (std::size_t j = 0; j < c.base.poses.size(); ++j) {
    PoseVector& v = c.base.poses[j].cTm;
    v = toPoseVector(c.cTm(j));
    for (int k = 0; k < 3; ++k) v[k] += noise_t * normal(rng);
    for (int k = 3; k < 6; ++k) v[k] += noise_r * normal(rng);
  }
  return c;
}

}  // namespace mire::datasets
