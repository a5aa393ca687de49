// Described mechanisms (doc/mechanisms.md, "Described mechanisms"): every example file of
// examples/mechanisms/ meets the mechanism contract (IKM and FKM inverse, autodiff Jacobians,
// a perturbed truth recovered with the gauge found from the data), the Delta and hexapod files
// reproduce the built-in models, and bad files are refused with the file, the line and the key.
#include <ceres/cost_function.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "mire/mechanism/delta.hpp"
#include "mire/mechanism/described.hpp"
#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/gough_stewart.hpp"
#include "mire/mechanism/identification.hpp"
#include "test_support.hpp"

namespace mire::mechanism {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

std::filesystem::path examplesDir() { return test::sourceDir() / "examples" / "mechanisms"; }

// An example file, the rank of its identification (geometric + full mounting, the gauge left
// out; doc/mechanisms.md, "Described mechanisms") and the box of poses around home it is used in.
struct Example {
  const char* file;
  int rank;
  double reach;     // half-size of the position box [m]
  double tilt_deg;  // largest rotation from home (full platforms)
};

const Example kExamples[] = {
    {"linear-delta.yaml", 21, 0.04, 0.0},   // 45 parameters: 3 × 10 + 3 gains + 12 mounting
    {"delta.yaml", 24, 0.10, 0.0},          // 51: 3 × 13 + 12, the rank of `delta-legs`
    {"6-rus.yaml", 66, 0.02, 5.0},          // 90: 6 × 13 + 12
    {"6-pus.yaml", 54, 0.03, 5.0},          // 72: 6 × 10 + 12
    {"gough-stewart.yaml", 42, 0.04, 6.0},  // 54: 6 × 7 + 12, the rank of `gough-stewart`
};

Eigen::Isometry3d transform(const Eigen::Vector3d& rotation_vector, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = fromRotationVector(rotation_vector);
  T.translation() = t;
  return T;
}

Eigen::Isometry3d homeOf(const Mechanism& m) { return m.poseToTransform(m.referencePose(m.nominal().values())); }

// A 3 × 3 × 3 grid of positions around home; on a full platform, × 3 tilts about an axis that
// changes from position to position (with a yaw), as the hexapod protocol.
std::vector<Eigen::Isometry3d> gridPoses(const Mechanism& m, const Example& e) {
  const Eigen::Isometry3d home = homeOf(m);
  const bool full = m.motionType() == MotionType::Spatial;
  std::vector<Eigen::Isometry3d> out;
  for (int ix = -1; ix <= 1; ++ix)
    for (int iy = -1; iy <= 1; ++iy)
      for (int iz = -1; iz <= 1; ++iz)
        for (int k = full ? -1 : 0; k <= (full ? 1 : 0); ++k) {
          const double a = 2.1 * (ix + 3 * iy + 9 * iz);
          const Eigen::Vector3d axis = Eigen::Vector3d(std::cos(a), std::sin(a), 0.5 * k).normalized();
          const Eigen::Vector3d r = e.tilt_deg * kDeg * k * axis;
          out.push_back(home * transform(r, e.reach * Eigen::Vector3d(ix, iy, iz)));
        }
  return out;
}

// Uniform positions in the box, rotations uniform in the ball of e.tilt_deg.
std::vector<Eigen::Isometry3d> randomPoses(const Mechanism& m, const Example& e, int count, unsigned seed) {
  const Eigen::Isometry3d home = homeOf(m);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Isometry3d> out;
  while (static_cast<int>(out.size()) < count) {
    const Eigen::Vector3d t(u(rng), u(rng), u(rng)), r(u(rng), u(rng), u(rng));
    if (r.norm() > 1.0) continue;
    out.push_back(home * transform(e.tilt_deg * kDeg * r, e.reach * t));
  }
  return out;
}

// 0.5 mm, 0.3° and 5·10⁻⁴ (a gain) on every geometric parameter, signs at random.
ParameterSet perturbed(const ParameterSet& nominal, unsigned seed) {
  ParameterSet truth = nominal;
  std::mt19937 rng(seed);
  std::bernoulli_distribution sign;
  for (const Parameter& p : nominal.parameters()) {
    const double step = p.unit == Unit::Metre ? 0.5e-3 : p.unit == Unit::Radian ? 0.3 * kDeg : 5e-4;
    truth.setValue(p.name, p.value + (sign(rng) ? step : -step));
  }
  return truth;
}

struct Campaign {
  RegisteredModel model;
  ParameterSet truth;
  std::vector<PoseObservation> poses;
};

// Noise-free joints of the truth and exact cTm through a camera 1.3 m from home.
// `pose_seed` draws other poses of the same robot (held-out checks).
Campaign simulate(const Example& e, unsigned seed, unsigned pose_seed = 0) {
  Campaign c;
  c.model = makeDescribedModel(examplesDir() / e.file);
  c.truth = perturbed(c.model.nominal, seed);
  const Mechanism& m = *c.model.mechanism;
  const Eigen::Vector3d home = homeOf(m).translation();
  const bool full = m.motionType() == MotionType::Spatial;
  const Eigen::Isometry3d bTc = transform(full ? Eigen::Vector3d(3.1, 0.1, 0.2) : Eigen::Vector3d(0.05, -0.04, 0.3),
                                          home + Eigen::Vector3d(0.03, -0.02, full ? 1.3 : -1.3));
  const Eigen::Isometry3d mTe = transform(full ? Eigen::Vector3d(0.02, -0.03, 0.4) : Eigen::Vector3d(3.1, 0.05, 0.0),
                                          Eigen::Vector3d(0.012, -0.008, 0.005));
  for (const Eigen::Isometry3d& bTe : randomPoses(m, e, 81, seed + 100 + pose_seed)) {
    const IkmResult ikm = m.inverseKinematics(c.truth.values(), bTe);
    if (!ikm.reachable()) throw std::logic_error(std::string(e.file) + ": a campaign pose is unreachable");
    PoseObservation p;
    p.id = std::to_string(c.poses.size() + 1);
    p.joints = ikm.joints;
    p.cTm = toPoseVector(bTc.inverse() * bTe * mTe.inverse());
    c.poses.push_back(p);
  }
  return c;
}

// What no gauge moves, leg by leg: rod lengths, gains, arm radii |a_⊥| and the extensible
// legs' offsets ρ0.
std::vector<double> legInvariants(const MechanismDescription& d) {
  std::vector<double> out;
  for (const LegDescription& leg : d.legs) {
    if (d.gains) out.push_back(leg.gain);
    if (leg.actuator == LegActuator::Extensible) {
      out.push_back(leg.offset);
      continue;
    }
    out.push_back(leg.rod);
    if (leg.actuator == LegActuator::Revolute) out.push_back((leg.arm - leg.arm.dot(leg.axis) * leg.axis).norm());
  }
  return out;
}

class DescribedExample : public ::testing::TestWithParam<Example> {};

INSTANTIATE_TEST_SUITE_P(Examples, DescribedExample, ::testing::ValuesIn(kExamples),
                         [](const ::testing::TestParamInfo<Example>& info) {
                           std::string name = info.param.file;
                           name = name.substr(0, name.find('.'));
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST_P(DescribedExample, IkmAndFkmAreInverseAroundHome) {
  const RegisteredModel model = makeDescribedModel(examplesDir() / GetParam().file);
  const Mechanism& m = *model.mechanism;
  const Eigen::VectorXd g = model.nominal.values();
  double worst_position = 0.0, worst_rotation = 0.0, worst_joint = 0.0;
  for (const Eigen::Isometry3d& pose : gridPoses(m, GetParam())) {
    const IkmResult q = m.inverseKinematics(g, pose);
    ASSERT_TRUE(q.reachable());
    const FkmResult fkm = m.forwardKinematics(g, q.joints, m.referencePose(g));
    ASSERT_TRUE(fkm.converged) << fkm.message;
    worst_position = std::max(worst_position, (fkm.bTe.translation() - pose.translation()).norm());
    worst_rotation = std::max(worst_rotation, Eigen::AngleAxisd(fkm.bTe.linear().transpose() * pose.linear()).angle());
    worst_joint = std::max(worst_joint, (m.inverseKinematics(g, fkm.bTe).joints - q.joints).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst_position, 1e-10);
  EXPECT_LT(worst_rotation, 1e-10);
  EXPECT_LT(worst_joint, 1e-10);
  std::printf("%s: FKM(IKM(X)) - X: %.2e m, %.2e rad; joints %.2e\n", GetParam().file, worst_position, worst_rotation,
              worst_joint);
}

// Well away from singularity over the box: ∂q/∂X keeps a moderate condition number (rotations
// as arcs at 0.1 m, a platform's radius, so that every column is per metre).
TEST_P(DescribedExample, HomeIsWellAwayFromSingularity) {
  const RegisteredModel model = makeDescribedModel(examplesDir() / GetParam().file);
  const Mechanism& m = *model.mechanism;
  const Eigen::VectorXd g = model.nominal.values();
  const int dof = m.poseDof();
  double worst = 0.0;
  for (const Eigen::Isometry3d& pose : gridPoses(m, GetParam())) {
    const Eigen::VectorXd x = m.transformToPose(pose);
    Eigen::MatrixXd J(m.jointCount(), dof);
    for (int k = 0; k < dof; ++k) {
      const double h = 1e-6, scale = k < 3 ? 1.0 : 10.0;  // per metre of arc at 0.1 m
      Eigen::VectorXd xp = x, xm = x;
      xp[k] += h;
      xm[k] -= h;
      J.col(k) =
          (m.inverseKinematics(g, m.poseToTransform(xp)).joints - m.inverseKinematics(g, m.poseToTransform(xm)).joints) /
          (2 * h) * scale;
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J);
    worst = std::max(worst, svd.singularValues()(0) / svd.singularValues()(dof - 1));
  }
  EXPECT_LT(worst, 30.0);
  std::printf("%s: worst condition number of dq/dX over the grid %.1f\n", GetParam().file, worst);
}

TEST_P(DescribedExample, AutodiffJacobianMatchesCentralDifferences) {
  const Campaign c = simulate(GetParam(), 2);
  const IdentificationModel model = makeInitialModel(c.model.mechanism, c.truth, c.poses, c.model.external_form);
  const Mechanism& m = *model.mechanism;
  const int J = m.jointCount(), G = model.geometricCount(), E = model.external.size();
  double worst = 0.0;
  for (const std::size_t j : {std::size_t{4}, std::size_t{40}}) {
    const PoseObservation& p = c.poses[j];
    const auto cost = m.makeJointResidual(model.external, p.cTm, p.joints, Eigen::MatrixXd::Identity(J, J));
    Eigen::VectorXd g = model.geometricValues(), e = model.externalValues();
    const double* parameters[2] = {g.data(), e.data()};
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> Jg(J, G), Je(J, E);
    double* jacobians[2] = {Jg.data(), Je.data()};
    Eigen::VectorXd r(J);
    ASSERT_TRUE(cost->Evaluate(parameters, r.data(), jacobians));
    const auto residual = [&](const Eigen::VectorXd& gg, const Eigen::VectorXd& ee) {
      return Eigen::VectorXd(p.joints - m.predictJoints(model.external, gg, ee, p.cTm).joints);
    };
    EXPECT_LT((r - residual(g, e)).norm(), 1e-12);
    const double h = 1e-6;
    for (int k = 0; k < G + E; ++k) {
      Eigen::VectorXd gp = g, gm = g, ep = e, em = e;
      if (k < G) {
        gp[k] += h;
        gm[k] -= h;
      } else {
        ep[k - G] += h;
        em[k - G] -= h;
      }
      const Eigen::VectorXd fd = (residual(gp, ep) - residual(gm, em)) / (2 * h);
      const Eigen::VectorXd ad = k < G ? Eigen::VectorXd(Jg.col(k)) : Eigen::VectorXd(Je.col(k - G));
      const double error = (fd - ad).cwiseAbs().maxCoeff() / std::max(1.0, ad.cwiseAbs().maxCoeff());
      EXPECT_LT(error, 1e-6) << "column " << k;
      worst = std::max(worst, error);
    }
    // ∂q/∂cTm against central differences too (the pose-covariance weighting uses it).
    const Eigen::MatrixXd dq = m.jointJacobianWrtPose(model.external, g, e, p.cTm);
    for (int k = 0; k < 6; ++k) {
      PoseVector plus = p.cTm, minus = p.cTm;
      plus[k] += h;
      minus[k] -= h;
      const Eigen::VectorXd fd =
          (m.predictJoints(model.external, g, e, plus).joints - m.predictJoints(model.external, g, e, minus).joints) /
          (2 * h);
      EXPECT_LT((fd - dq.col(k)).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, fd.cwiseAbs().maxCoeff())) << k;
    }
  }
  std::printf("%s: autodiff - central differences: %.2e (relative, worst column)\n", GetParam().file, worst);
}

TEST_P(DescribedExample, IdentificationRecoversPerturbedTruthWithTheGaugeFromTheData) {
  const Campaign c = simulate(GetParam(), 3);
  IdentificationModel model = makeInitialModel(c.model.mechanism, c.model.nominal, c.poses, c.model.external_form);
  const GaugeAnalysis gauge = fixGauge(model, c.poses);
  EXPECT_EQ(gauge.report.rank, GetParam().rank) << gauge.text();
  EXPECT_EQ(gauge.report.rank, static_cast<int>(model.parameters.freeCount())) << gauge.text();
  IdentificationOptions options;
  options.compute_identifiability = true;
  const IdentificationResult result = identify(model, c.poses, options);
  EXPECT_LT(result.rms_joint_residual, 1e-9) << gauge.text();
  EXPECT_TRUE(result.identifiability.fullRank()) << result.identifiability.text();
  // Parameters in no unidentifiable combination are the truth's, whatever the gauge, to first
  // order: a gauge that turns an arm about its axis (with q0) moves its other components by
  // |a|·ε²/2 (0.35 m × (7 mrad)²/2 ≈ 9 µm on the Delta's arms). The per-leg quantities no gauge
  // moves (rod lengths, gains, arm radii, extensible offsets) are the truth's exactly.
  double worst = 0.0;
  int checked = 0;
  for (const std::string& name : gauge.identified) {
    if (!c.truth.contains(name)) continue;
    const double error = std::abs(result.model.parameters.value(name) - c.truth.value(name));
    EXPECT_LT(error, 2e-5) << name;
    ++checked;
  }
  EXPECT_GT(checked, 0) << gauge.text();
  const MechanismDescription description = readMechanismDescription(examplesDir() / GetParam().file);
  const std::vector<double> truth = legInvariants(describedWithParameters(description, c.truth));
  const std::vector<double> found = legInvariants(describedWithParameters(description, result.model.parameters));
  for (std::size_t k = 0; k < truth.size(); ++k) {
    EXPECT_NEAR(found[k], truth[k], 1e-9) << k;
    worst = std::max(worst, std::abs(found[k] - truth[k]));
  }
  // Whatever the gauge, the identified model predicts the truth's joints at held-out poses.
  double worst_joint = 0.0;
  for (const PoseObservation& p : simulate(GetParam(), 3, 1).poses) {
    const IkmResult q = result.model.predictJoints(p.cTm);
    ASSERT_TRUE(q.reachable()) << p.id;
    worst_joint = std::max(worst_joint, (q.joints - p.joints).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst_joint, 1e-9);
  std::printf(
      "%s: rank %d of %zu, rms residual %.2e, %d identified parameters, leg invariants within %.2e of the truth, "
      "held-out joints within %.2e\n",
      GetParam().file, gauge.report.rank, gauge.report.parameter_names.size(), result.rms_joint_residual, checked,
      worst, worst_joint);
}

// ----- the built-in models as descriptions -----

TEST(DescribedBuiltIn, DeltaFileIsTheBuiltInDelta) {
  const RegisteredModel described = makeDescribedModel(examplesDir() / "delta.yaml");
  const std::unique_ptr<Mechanism> builtin = makeDeltaMechanism(DeltaModelKind::Simple);
  const Eigen::VectorXd gd = described.nominal.values(), gb = builtin->nominal().values();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst_joint = 0.0, worst_position = 0.0;
  for (int k = 0; k < 50; ++k) {
    const Eigen::Vector3d t(0.15 * u(rng), 0.15 * u(rng), -0.65 + 0.075 * u(rng));
    const Eigen::Isometry3d bTe = transform(Eigen::Vector3d::Zero(), t);
    const IkmResult qd = described.mechanism->inverseKinematics(gd, bTe);
    const IkmResult qb = builtin->inverseKinematics(gb, bTe);
    ASSERT_TRUE(qd.reachable() && qb.reachable());
    worst_joint = std::max(worst_joint, (qd.joints - qb.joints).cwiseAbs().maxCoeff());
    const FkmResult fd = described.mechanism->forwardKinematics(gd, qb.joints, described.mechanism->referencePose(gd));
    const FkmResult fb = builtin->forwardKinematics(gb, qb.joints, builtin->referencePose(gb));
    ASSERT_TRUE(fd.converged && fb.converged) << fd.message << fb.message;
    worst_position = std::max(worst_position, (fd.bTe.translation() - fb.bTe.translation()).norm());
  }
  EXPECT_LT(worst_joint, 1e-9);
  EXPECT_LT(worst_position, 1e-9);
  EXPECT_EQ(described.mechanism->jointUnits(), builtin->jointUnits());
  EXPECT_EQ(described.mechanism->motionType(), builtin->motionType());
  std::printf("delta.yaml vs delta: joints %.2e rad, FKM positions %.2e m\n", worst_joint, worst_position);
}

TEST(DescribedBuiltIn, GoughStewartFileIsTheBuiltInHexapod) {
  const RegisteredModel described = makeDescribedModel(examplesDir() / "gough-stewart.yaml");
  const std::unique_ptr<Mechanism> builtin = makeGoughStewartMechanism();
  const Eigen::VectorXd gd = described.nominal.values(), gb = builtin->nominal().values();
  const Example box{"gough-stewart.yaml", 0, 0.04, 6.0};
  double worst_joint = 0.0, worst_position = 0.0, worst_rotation = 0.0;
  for (const Eigen::Isometry3d& bTe : randomPoses(*builtin, box, 50, 11)) {
    const IkmResult qd = described.mechanism->inverseKinematics(gd, bTe);
    const IkmResult qb = builtin->inverseKinematics(gb, bTe);
    worst_joint = std::max(worst_joint, (qd.joints - qb.joints).cwiseAbs().maxCoeff());
    const FkmResult fd = described.mechanism->forwardKinematics(gd, qb.joints, described.mechanism->referencePose(gd));
    const FkmResult fb = builtin->forwardKinematics(gb, qb.joints, builtin->referencePose(gb));
    ASSERT_TRUE(fd.converged && fb.converged) << fd.message << fb.message;
    worst_position = std::max(worst_position, (fd.bTe.translation() - fb.bTe.translation()).norm());
    worst_rotation = std::max(worst_rotation, Eigen::AngleAxisd(fd.bTe.linear().transpose() * fb.bTe.linear()).angle());
  }
  EXPECT_LT(worst_joint, 1e-9);
  EXPECT_LT(worst_position, 1e-9);
  EXPECT_LT(worst_rotation, 1e-9);
  EXPECT_EQ(described.mechanism->jointUnits(), builtin->jointUnits());
  EXPECT_EQ(described.mechanism->poseComponentNames(), builtin->poseComponentNames());
  std::printf("gough-stewart.yaml vs gough-stewart: joints %.2e m, FKM positions %.2e m, rotations %.2e rad\n",
              worst_joint, worst_position, worst_rotation);
}

}  // namespace
}  // namespace mire::mechanism
