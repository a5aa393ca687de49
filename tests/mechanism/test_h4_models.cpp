// H4 models: IKM/FKM round trip, model 31 ≡ model 12 at ψ = α + π, β = π/2, the camera-frame
// form, unreachable poses and bad input.
#include <gtest/gtest.h>

#include <random>

#include "h4_test_robot.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/parameter_set.hpp"

namespace mire::mechanism {
namespace {

using test::kDeg;
using test::kPi;

std::vector<Eigen::VectorXd> randomPoses(int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::VectorXd> out;
  for (int i = 0; i < count; ++i) {
    Eigen::VectorXd x(4);
    x << 0.1 * u(rng), 0.1 * u(rng), -0.62 + 0.075 * u(rng), 20.0 * kDeg * u(rng);
    out.push_back(x);
  }
  return out;
}

TEST(H4Models, IkmFkmRoundTripModel12) {
  const test::TestRobot robot;
  const auto& m = *robot.mechanism;
  const Eigen::VectorXd g = robot.truth.values();
  for (const Eigen::VectorXd& x : randomPoses(20, 1)) {
    const IkmResult ikm = m.inverseKinematics(g, m.poseToTransform(x));
    ASSERT_TRUE(ikm.reachable());
    const FkmResult fkm = m.forwardKinematics(g, ikm.joints, m.referencePose(g));
    ASSERT_TRUE(fkm.converged) << fkm.message;
    EXPECT_LT((fkm.pose - x).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(H4Models, FkmReportsNonConvergence) {
  const test::TestRobot robot;
  const auto& m = *robot.mechanism;
  const Eigen::VectorXd g = robot.truth.values();
  // Joints no pose can produce: arms folded up far beyond the forearm reach.
  const Eigen::Vector4d q(-1.4, 1.4, -1.4, 1.4);
  const FkmResult fkm = m.forwardKinematics(g, q, m.referencePose(g));
  EXPECT_FALSE(fkm.converged);
  EXPECT_FALSE(fkm.message.empty());
}

TEST(H4Models, Model31ReproducesModel12AtSpecialValues) {
  const test::TestRobot robot;
  Eigen::Vector3d shift;
  const ParameterSet p31 = model31FromModel12(robot.truth, &shift);
  EXPECT_EQ(p31.size(), 31u);
  EXPECT_NEAR(p31.value("psi1"),
              robot.truth.value("alpha1") + kPi - 2 * kPi * (robot.truth.value("alpha1") > 0 ? 1 : 0), 1e-12);
  EXPECT_NEAR(p31.value("beta3"), kPi / 2, 1e-15);
  const auto m31 = makeH4Mechanism(H4ModelKind::Model31);
  const auto& m12 = *robot.mechanism;
  double worst = 0.0;
  for (const Eigen::VectorXd& x : randomPoses(50, 2)) {
    const Eigen::Isometry3d T12 = m12.poseToTransform(x);
    Eigen::Isometry3d T31 = T12;
    T31.translation() -= shift;
    const IkmResult q12 = m12.inverseKinematics(robot.truth.values(), T12);
    const IkmResult q31 = m31->inverseKinematics(p31.values(), T31);
    ASSERT_TRUE(q12.reachable() && q31.reachable());
    worst = std::max(worst, (q12.joints - q31.joints).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-12);
}

TEST(H4Models, CameraFrameModel31ReproducesModel31) {
  const test::TestRobot robot;
  Eigen::Vector3d shift;
  const ParameterSet p31 = model31FromModel12(robot.truth, &shift);
  // An arbitrary frame B' (rotation about z and tilt, translation): B' <- B31.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() << 0.2, -0.1, 0.9;
  const ParameterSet pc = model31CameraFromModel31(p31, T);
  EXPECT_EQ(pc.size(), 33u);
  const auto m31 = makeH4Mechanism(H4ModelKind::Model31);
  const auto mc = makeH4Mechanism(H4ModelKind::Model31Camera);
  double worst = 0.0;
  for (const Eigen::VectorXd& x : randomPoses(50, 3)) {
    Eigen::Isometry3d T31 = m31->poseToTransform(x);
    T31.translation() -= shift;
    const IkmResult a = m31->inverseKinematics(p31.values(), T31);
    const IkmResult b = mc->inverseKinematics(pc.values(), T * T31);
    ASSERT_TRUE(a.reachable() && b.reachable());
    worst = std::max(worst, (a.joints - b.joints).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-12);
  // FKM in the camera frame.
  const IkmResult q = mc->inverseKinematics(pc.values(), T * m31->poseToTransform(randomPoses(1, 4)[0]));
  const FkmResult fkm = mc->forwardKinematics(pc.values(), q.joints, mc->referencePose(pc.values()));
  EXPECT_TRUE(fkm.converged) << fkm.message;
}

TEST(H4Models, UnreachablePoseIsReportedNotNaN) {
  const test::TestRobot robot;
  Eigen::VectorXd x(4);
  x << 0.0, 0.0, -1.5, 0.0;  // below the reach of the forearms
  const IkmResult ikm = robot.mechanism->inverseKinematics(robot.truth.values(), robot.mechanism->poseToTransform(x));
  EXPECT_FALSE(ikm.reachable());
  EXPECT_EQ(ikm.unreachable_joints.size(), 4u);
}

TEST(H4Models, BadInputErrors) {
  ParameterSet p = h4Model12Parameters({});
  EXPECT_THROW(p.value("nope"), std::invalid_argument);
  try {
    p.fix({"R", "bogus"});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bogus"), std::string::npos);
  }
  EXPECT_FALSE(p.at("R").fixed);  // nothing changed on error
  EXPECT_THROW(p.setValue("R", std::nan("")), std::invalid_argument);
  EXPECT_THROW(p.setValue("L", std::numeric_limits<double>::infinity()), std::invalid_argument);
  EXPECT_THROW(p.add({"R", 1.0, Unit::Metre, false, ""}), std::invalid_argument);
  const auto m = makeH4Mechanism(H4ModelKind::Model12);
  Eigen::VectorXd g = p.values();
  g[0] = std::nan("");
  EXPECT_THROW(m->inverseKinematics(g, Eigen::Isometry3d::Identity()), std::invalid_argument);
  EXPECT_THROW(m->inverseKinematics(Eigen::VectorXd::Zero(3), Eigen::Isometry3d::Identity()), std::invalid_argument);
  H4Nominal amplified;
  amplified.amplification = 2.0;
  EXPECT_THROW(makeH4Mechanism(H4ModelKind::Model31Camera, amplified), std::invalid_argument);

  std::vector<PoseObservation> poses(1);
  poses[0].id = "pose7";
  poses[0].joints = Eigen::Vector4d::Zero();
  poses[0].cTm[2] = std::nan("");
  try {
    validatePoses(poses, 4);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pose7"), std::string::npos);
  }
}

TEST(H4Models, TiesShareOneValue) {
  ParameterSet p = makeH4Mechanism(H4ModelKind::Model31Camera)->nominal();
  p.setValue("L2", 0.31);
  p.tie({"L1", "L2", "L3", "L4"});
  EXPECT_DOUBLE_EQ(p.value("L4"), p.value("L1"));
  p.setValue("L3", 0.305);
  EXPECT_DOUBLE_EQ(p.value("L1"), 0.305);
  EXPECT_EQ(p.freeCount(), 33u - 3u);
  p.setFixed("L2");
  EXPECT_EQ(p.freeCount(), 29u);
}

}  // namespace
}  // namespace mire::mechanism
