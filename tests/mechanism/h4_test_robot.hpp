#pragma once
// A small simulated H4 for the mechanism tests: a "true" model-12 robot ≈1 mm / 0.5° from
// the nominal of doc/mechanisms.md, true camera and target transforms, the 81-pose
// protocol of doc/mechanisms.md and cTm noise of 0.2 mm / 0.03° per component (paper §5).
#include <Eigen/Geometry>

#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/support/constants.hpp"

namespace mire::mechanism::test {

using support::kPi;
constexpr double kDeg = kPi / 180.0;
constexpr double kSigmaT = 0.2e-3;       // m
constexpr double kSigmaR = 0.03 * kDeg;  // rad

struct TestRobot {
  H4Nominal nominal;
  ParameterSet truth;  // model-12 geometry
  std::shared_ptr<const Mechanism> mechanism = makeH4Mechanism(H4ModelKind::Model12);
  Eigen::Isometry3d bTc = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d mTe = Eigen::Isometry3d::Identity();

  TestRobot() {
    truth = h4Model12Parameters(nominal);
    truth.setValue("R", nominal.R + 1.0e-3);
    truth.setValue("L", nominal.L - 0.8e-3);
    truth.setValue("l", nominal.l + 1.2e-3);
    truth.setValue("h", nominal.h - 0.7e-3);
    const double dalpha[4] = {0.5, -0.4, 0.3, -0.5};
    const double dq0[4] = {0.5, -0.3, 0.4, -0.6};
    for (int i = 0; i < 4; ++i) {
      const std::string k = std::to_string(i + 1);
      truth.setValue("alpha" + k, truth.value("alpha" + k) + dalpha[i] * kDeg);
      truth.setValue("q0" + k, dq0[i] * kDeg);
    }
    // Camera under the workspace looking up, slightly tilted; target facing it.
    bTc.linear() = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.02, Eigen::Vector3d::UnitY()) *
                    Eigen::AngleAxisd(0.015, Eigen::Vector3d::UnitX()))
                       .toRotationMatrix();
    bTc.translation() << 0.03, -0.02, -1.25;
    mTe.linear() = (Eigen::AngleAxisd(kPi, Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) *
                    Eigen::AngleAxisd(0.004, Eigen::Vector3d::UnitY()))
                       .toRotationMatrix();
    mTe.translation() << 0.012, -0.008, 0.03;
  }

  // Paper §6: 27 positions (3×3×3 over 200×200×150 mm) × θ ∈ {−20°, 0°, 20°}.
  static std::vector<Eigen::Isometry3d> protocolPoses() {
    std::vector<Eigen::Isometry3d> poses;
    for (int ix = -1; ix <= 1; ++ix)
      for (int iy = -1; iy <= 1; ++iy)
        for (int iz = -1; iz <= 1; ++iz)
          for (int it = -1; it <= 1; ++it) {
            Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
            T.linear() = Eigen::AngleAxisd(20.0 * kDeg * it, Eigen::Vector3d::UnitZ()).toRotationMatrix();
            T.translation() << 0.1 * ix, 0.1 * iy, -0.62 + 0.075 * iz;
            poses.push_back(T);
          }
    return poses;
  }

  // Observations of the given effector poses; noise on cTm when rng is given.
  std::vector<PoseObservation> observe(const std::vector<Eigen::Isometry3d>& bTe, std::mt19937* rng) const {
    std::normal_distribution<double> normal;
    std::vector<PoseObservation> out;
    for (std::size_t j = 0; j < bTe.size(); ++j) {
      PoseObservation p;
      p.id = "p" + std::to_string(j + 1);
      p.joints = mechanism->inverseKinematics(truth.values(), bTe[j]).joints;
      p.cTm = toPoseVector(bTc.inverse() * bTe[j] * mTe.inverse());
      if (rng) {
        for (int k = 0; k < 3; ++k) p.cTm[k] += kSigmaT * normal(*rng);
        for (int k = 3; k < 6; ++k) p.cTm[k] += kSigmaR * normal(*rng);
      }
      PoseCovariance c = PoseCovariance::Zero();
      c.diagonal() << kSigmaT * kSigmaT, kSigmaT * kSigmaT, kSigmaT * kSigmaT, kSigmaR * kSigmaR, kSigmaR * kSigmaR,
          kSigmaR * kSigmaR;
      p.covariance = c;
      out.push_back(p);
    }
    return out;
  }

  // True values of the model's parameters (geometry + external projected on its form).
  Eigen::VectorXd trueValues(const IdentificationModel& model) const {
    Eigen::VectorXd v(model.parameters.size());
    v << truth.values(), model.external.valuesFrom(bTc, mTe);
    return v;
  }

  // z_ME of the truth in the axis-aligned target frame of an estimated alignment.
  double trueZME(const AxisAlignment& alignment) const {
    return (alignment.target.transpose() * mTe.translation()).z();
  }
};

}  // namespace mire::mechanism::test
