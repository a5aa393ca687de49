// One H4 identification: model 12 + 7 external parameters (19 unknowns), 81 poses of the
// 81-pose protocol (doc/mechanisms.md, "Evaluation criteria") with 0.2 mm / 0.03° noise on cTm and the pose
// covariances as weights. Target: < 5 ms per identification. Prints the median time of repeated runs.
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>
#include <vector>

#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/identification.hpp"

using namespace mire::mechanism;

int main() {
  constexpr double kDeg = 3.14159265358979323846 / 180.0;
  const H4Nominal nominal;
  std::shared_ptr<const Mechanism> mechanism = makeH4Mechanism(H4ModelKind::Model12, nominal);
  ParameterSet truth = h4Model12Parameters(nominal);
  truth.setValue("R", nominal.R + 1e-3);
  truth.setValue("l", nominal.l + 1.2e-3);
  truth.setValue("q01", 0.5 * kDeg);
  truth.setValue("alpha2", truth.value("alpha2") - 0.4 * kDeg);
  Eigen::Isometry3d bTc = Eigen::Isometry3d::Identity(), mTe = Eigen::Isometry3d::Identity();
  bTc.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  bTc.translation() << 0.03, -0.02, -1.25;
  mTe.linear() = Eigen::AngleAxisd(3.14159265358979323846, Eigen::Vector3d::UnitX()).toRotationMatrix();
  mTe.translation() << 0.012, -0.008, 0.0;

  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  std::vector<PoseObservation> poses;
  for (int ix = -1; ix <= 1; ++ix)
    for (int iy = -1; iy <= 1; ++iy)
      for (int iz = -1; iz <= 1; ++iz)
        for (int it = -1; it <= 1; ++it) {
          Eigen::Isometry3d bTe = Eigen::Isometry3d::Identity();
          bTe.linear() = Eigen::AngleAxisd(20 * kDeg * it, Eigen::Vector3d::UnitZ()).toRotationMatrix();
          bTe.translation() << 0.1 * ix, 0.1 * iy, -0.62 + 0.075 * iz;
          PoseObservation p;
          p.id = std::to_string(poses.size() + 1);
          p.joints = mechanism->inverseKinematics(truth.values(), bTe).joints;
          p.cTm = toPoseVector(bTc.inverse() * bTe * mTe.inverse());
          for (int k = 0; k < 3; ++k) p.cTm[k] += 0.2e-3 * normal(rng);
          for (int k = 3; k < 6; ++k) p.cTm[k] += 0.03 * kDeg * normal(rng);
          PoseCovariance c = PoseCovariance::Zero();
          c.diagonal() << 4e-8, 4e-8, 4e-8, std::pow(0.03 * kDeg, 2), std::pow(0.03 * kDeg, 2), std::pow(0.03 * kDeg, 2);
          p.covariance = c;
          poses.push_back(p);
        }

  // CPU time (std::clock), median of 21 runs: stable on a shared machine.
  const auto time = [](auto&& f) {
    std::vector<double> ms;
    for (int i = 0; i < 21; ++i) {
      const std::clock_t t0 = std::clock();
      f();
      ms.push_back(1e3 * double(std::clock() - t0) / CLOCKS_PER_SEC);
    }
    std::nth_element(ms.begin(), ms.begin() + 10, ms.end());
    return ms[10];
  };
  IdentificationModel model = makeInitialModel(mechanism, truth, poses, ExternalForm::AxisAligned);
  model.parameters.setValues(
      makeInitialModel(mechanism, h4Model12Parameters(nominal), poses, ExternalForm::AxisAligned).parameters.values());
  IdentificationResult result;
  const double init_ms =
      time([&] { makeInitialModel(mechanism, h4Model12Parameters(nominal), poses, ExternalForm::AxisAligned); });
  const double weighted_ms = time([&] { result = identify(model, poses); });
  std::printf(
      "identify (81 poses, 19 parameters, weighted by pose covariances): %.2f ms CPU median "
      "(%d iterations; target < 5 ms: %s)\n",
      weighted_ms, result.iterations, weighted_ms < 5.0 ? "met" : "NOT met");
  IdentificationOptions fast;
  fast.use_pose_covariances = false;
  fast.compute_identifiability = false;
  const double unweighted_ms = time([&] { result = identify(model, poses, fast); });
  std::printf("identify (unweighted, no identifiability report): %.2f ms CPU median (%d iterations)\n", unweighted_ms,
              result.iterations);
  std::printf("initial external parameters from the data (axis alignment + 81 FKM): %.2f ms CPU median\n", init_ms);
  return 0;
}
