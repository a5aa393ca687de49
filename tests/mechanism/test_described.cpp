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

TEST_P(DescribedExample, LegByLegJacobianMatchesCentralDifferences) {
  const Campaign c = simulate(GetParam(), 2);
  const IdentificationModel model = makeInitialModel(c.model.mechanism, c.truth, c.poses, c.model.external_form);
  const Mechanism& m = *model.mechanism;
  const int J = m.jointCount(), G = model.geometricCount(), E = model.external.size();
  double worst = 0.0;
  for (const std::size_t j : {std::size_t{4}, std::size_t{40}}) {
    const PoseObservation& p = c.poses[j];
    // A full whitening (a pose covariance's Cholesky factor is triangular and couples the legs).
    Eigen::MatrixXd W = Eigen::MatrixXd::Identity(J, J);
    W.triangularView<Eigen::StrictlyUpper>().setConstant(0.3);
    const auto cost = m.makeJointResidual(model.external, p.cTm, p.joints, W);
    Eigen::VectorXd g = model.geometricValues(), e = model.externalValues();
    const double* parameters[2] = {g.data(), e.data()};
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> Jg(J, G), Je(J, E);
    double* jacobians[2] = {Jg.data(), Je.data()};
    Eigen::VectorXd r(J);
    ASSERT_TRUE(cost->Evaluate(parameters, r.data(), jacobians));
    const auto residual = [&](const Eigen::VectorXd& gg, const Eigen::VectorXd& ee) {
      return Eigen::VectorXd(W * (p.joints - m.predictJoints(model.external, gg, ee, p.cTm).joints));
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
  std::printf("%s: leg-by-leg Jacobian - central differences: %.2e (relative, worst column)\n", GetParam().file, worst);
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

// ----- the file: parameters, round trip, syntax variants, bad input -----

// A 3-leg translation platform; tests replace some of its lines (1-based).
const std::vector<std::string> kSmall = {
    "name: small",                      // 1
    "platform: translation",            // 2
    "legs:",                            // 3
    "  - actuator: prismatic",          // 4
    "    base: [0, 0.2, 0]",            // 5
    "    axis: [0, 0, 1]",              // 6
    "    rod: 0.25",                    // 7
    "    platform: [0, 0.04, 0]",       // 8
    "  - actuator: prismatic",          // 9
    "    base: [-0.17, -0.1, 0]",       // 10
    "    axis: [0, 0, 1]",              // 11
    "    rod: 0.25",                    // 12
    "    platform: [-0.03, -0.02, 0]",  // 13
    "  - actuator: prismatic",          // 14
    "    base: [0.17, -0.1, 0]",        // 15
    "    axis: [0, 0, 1]",              // 16
    "    rod: 0.25",                    // 17
    "    platform: [0.03, -0.02, 0]",   // 18
};

// kSmall with lines replaced ("" deletes a line; a replacement may hold several lines).
std::string smallWith(const std::vector<std::pair<int, std::string>>& edits) {
  std::vector<std::string> lines = kSmall;
  for (const auto& [line, text] : edits) lines[static_cast<std::size_t>(line - 1)] = text;
  std::string out;
  for (const std::string& line : lines)
    if (!line.empty()) out += line + "\n";
  return out;
}

std::filesystem::path writeFile(const test::TempDir& dir, const std::string& name, const std::string& text) {
  const std::filesystem::path path = dir.path() / name;
  std::ofstream(path) << text;
  return path;
}

void expectSame(const MechanismDescription& a, const MechanismDescription& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.platform, b.platform);
  EXPECT_EQ(a.gains, b.gains);
  ASSERT_EQ(a.home.has_value(), b.home.has_value());
  if (a.home) {
    EXPECT_EQ(*a.home, *b.home);
  }
  ASSERT_EQ(a.legs.size(), b.legs.size());
  for (std::size_t i = 0; i < a.legs.size(); ++i) {
    const LegDescription &x = a.legs[i], &y = b.legs[i];
    EXPECT_EQ(x.actuator, y.actuator) << i;
    EXPECT_EQ(x.base, y.base) << i;
    EXPECT_LT((x.axis - y.axis).norm(), 1e-15) << i;  // normalised again on read
    EXPECT_EQ(x.arm, y.arm) << i;
    EXPECT_EQ(x.rod, y.rod) << i;
    EXPECT_EQ(x.platform, y.platform) << i;
    EXPECT_EQ(x.branch, y.branch) << i;
    EXPECT_EQ(x.offset, y.offset) << i;
    EXPECT_EQ(x.gain, y.gain) << i;
    EXPECT_EQ(x.stroke.has_value(), y.stroke.has_value()) << i;
    if (x.stroke && y.stroke) {
      EXPECT_EQ(*x.stroke, *y.stroke) << i;
    }
  }
}

TEST(DescribedFile, ParametersAreNamedPerLegWithTheirUnits) {
  const RegisteredModel model = makeDescribedModel(examplesDir() / "delta.yaml");
  const std::vector<std::string> leg1 = {"ax1",   "ay1", "az1", "ua1", "ub1", "armx1", "army1",
                                         "armz1", "l1",  "px1", "py1", "pz1", "q01"};
  const std::vector<std::string> names = model.nominal.names();
  ASSERT_EQ(names.size(), 39u);
  EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + 13), leg1);
  EXPECT_EQ(model.nominal.at("q01").unit, Unit::Radian);
  EXPECT_EQ(model.nominal.at("ua1").unit, Unit::Radian);
  EXPECT_EQ(model.nominal.at("armx1").unit, Unit::Metre);
  EXPECT_EQ(model.nominal.freeCount(), names.size());  // the gauge is the analysis's to find
  EXPECT_EQ(model.external_form, ExternalForm::Full);
  EXPECT_EQ(model.name, "delta-described");

  const RegisteredModel printer = makeDescribedModel(examplesDir() / "linear-delta.yaml");
  EXPECT_EQ(printer.nominal.at("q01").unit, Unit::Metre);
  EXPECT_EQ(printer.nominal.at("g3").unit, Unit::Dimensionless);
  EXPECT_EQ(printer.nominal.value("g3"), 1.0);
  EXPECT_EQ(printer.mechanism->jointColumnNames(), (std::vector<std::string>{"q1_m", "q2_m", "q3_m"}));
  const RegisteredModel hexapod = makeDescribedModel(examplesDir() / "gough-stewart.yaml");
  EXPECT_EQ(hexapod.nominal.at("rho06").unit, Unit::Metre);
  EXPECT_FALSE(hexapod.nominal.contains("l1"));
}

// One mechanism with all three leg kinds: the joint units are per leg, and the contract holds.
TEST(DescribedFile, LegKindsMixOnOnePlatform) {
  MechanismDescription d = readMechanismDescription(examplesDir() / "6-pus.yaml");
  const Eigen::Vector3d home = d.home->head<3>();
  const std::unique_ptr<Mechanism> pus = makeDescribedMechanism(d);
  const Eigen::VectorXd q_home =
      pus->inverseKinematics(pus->nominal().values(), pus->poseToTransform(pus->referencePose(pus->nominal().values()))).joints;
  for (int i : {4, 5}) {  // extensible legs from the carriage at home, reading 0.05 m there
    LegDescription& leg = d.legs[static_cast<std::size_t>(i)];
    const Eigen::Vector3d carriage = leg.base + q_home[i] * leg.axis;
    leg.actuator = LegActuator::Extensible;
    leg.offset = (home + leg.platform - carriage).norm() - 0.05;
    leg.base = carriage;
  }
  for (int i : {0, 1}) {  // revolute legs whose elbow at q = 0 is the carriage at home
    LegDescription& leg = d.legs[static_cast<std::size_t>(i)];
    const Eigen::Vector3d carriage = leg.base + q_home[i] * leg.axis;
    const Eigen::Vector3d radial = Eigen::Vector3d(carriage.x(), carriage.y(), 0).normalized();
    leg.actuator = LegActuator::Revolute;
    leg.arm = 0.10 * radial;
    leg.base = carriage - leg.arm;
    leg.axis = Eigen::Vector3d::UnitZ().cross(radial);
    leg.branch = 1;
    const IkmResult q = makeDescribedMechanism(d)->inverseKinematics(describedParameters(d).values(),
                                                                     transform(Eigen::Vector3d::Zero(), home));
    if (!(std::abs(q.joints[i]) < 1e-9)) leg.branch = -1;
  }
  const RegisteredModel model = makeDescribedModel(d);
  const Mechanism& m = *model.mechanism;
  EXPECT_EQ(m.jointColumnNames(), (std::vector<std::string>{"q1_rad", "q2_rad", "q3_m", "q4_m", "q5_m", "q6_m"}));
  const Eigen::VectorXd g = model.nominal.values();
  const IkmResult at_home = m.inverseKinematics(g, transform(Eigen::Vector3d::Zero(), home));
  EXPECT_NEAR(at_home.joints[0], 0.0, 1e-12);
  EXPECT_NEAR(at_home.joints[5], 0.05, 1e-12);
  const Example box{"", 0, 0.01, 2.0};
  double worst = 0.0;
  for (const Eigen::Isometry3d& pose : gridPoses(m, box)) {
    const IkmResult q = m.inverseKinematics(g, pose);
    ASSERT_TRUE(q.reachable());
    const FkmResult fkm = m.forwardKinematics(g, q.joints, m.referencePose(g));
    ASSERT_TRUE(fkm.converged) << fkm.message;
    worst = std::max(worst, (fkm.bTe.translation() - pose.translation()).norm());
  }
  EXPECT_LT(worst, 1e-10);
}

TEST(DescribedFile, WrittenDescriptionsReadBackTheSame) {
  const test::TempDir dir;
  for (const Example& e : kExamples) {
    const MechanismDescription d = readMechanismDescription(examplesDir() / e.file);
    const MechanismDescription again = readMechanismDescription(writeFile(dir, e.file, d.yamlString()));
    SCOPED_TRACE(e.file);
    expectSame(d, again);
    EXPECT_EQ(describedParameters(again).values(), describedParameters(d).values());
    expectSame(describedWithParameters(d, describedParameters(d)), d);
  }
}

// An identified geometry written as a description is the identified model: the axis tilts folded
// into the axes give the same IKM.
TEST(DescribedFile, IdentifiedValuesWrittenAsADescriptionGiveTheSameModel) {
  for (const Example& e : kExamples) {
    SCOPED_TRACE(e.file);
    const MechanismDescription d = readMechanismDescription(examplesDir() / e.file);
    const std::unique_ptr<Mechanism> original = makeDescribedMechanism(d);
    const ParameterSet values = perturbed(original->nominal(), 5);
    const MechanismDescription identified =
        parseMechanismDescription(describedWithParameters(d, values).yamlString(), "identified.yaml");
    const std::unique_ptr<Mechanism> rewritten = makeDescribedMechanism(identified);
    double worst = 0.0;
    for (const Eigen::Isometry3d& pose : gridPoses(*original, e)) {
      const IkmResult a = original->inverseKinematics(values.values(), pose);
      const IkmResult b = rewritten->inverseKinematics(rewritten->nominal().values(), pose);
      ASSERT_TRUE(a.reachable() && b.reachable());
      worst = std::max(worst, (a.joints - b.joints).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(worst, 1e-12);
  }
}

TEST(DescribedFile, YamlAsPeopleWriteIt) {
  const std::string flow =
      "%YAML 1.2\n---\n"
      "{name: small, platform: translation, legs: [\n"
      "  {actuator: prismatic, base: [0, 0.2, 0], axis: [0, 0, 2], rod: 0.25, platform: [0, 0.04, 0], branch: +1},\n"
      "  {actuator: prismatic, base: [-0.17, -0.1, 0], axis: [0, 0, 1], rod: 0.25, platform: [-0.03, -0.02, 0]},\n"
      "  {actuator: prismatic, base: [0.17, -0.1, 0], axis: [0, 0, 1.0], rod: 0.25, platform: [0.03, -0.02, 0],\n"
      "   branch: 1}]}\n";
  const std::string block =
      smallWith({{5, "    base:\n      - 0\n      - 0.2\n      - 0"}, {7, "    rod: 0.25   # m\n    branch: 1"}});
  const MechanismDescription reference = parseMechanismDescription(smallWith({}), "small.yaml");
  expectSame(parseMechanismDescription(flow, "flow.yaml"), reference);
  expectSame(parseMechanismDescription(block, "block.yaml"), reference);
  const MechanismDescription minus = parseMechanismDescription(smallWith({{7, "    rod: 0.25\n    branch: -1"}}), "m");
  EXPECT_EQ(minus.legs[0].branch, -1);
  const MechanismDescription homed =
      parseMechanismDescription(smallWith({{3, "home: {t: [0, 0, 0.1]}\nlegs:"}}), "home.yaml");
  EXPECT_EQ(homed.home->head<3>(), Eigen::Vector3d(0, 0, 0.1));
}

struct BadFile {
  std::vector<std::pair<int, std::string>> edits;
  int line;
  std::string key;
  std::string what;
};

TEST(DescribedFile, BadInputNamesTheFileTheLineAndTheKey) {
  const std::vector<BadFile> cases = {
      {{{7, ""}}, 4, "legs[0].rod", "missing key"},
      {{{9, "  - actuator: linear"}}, 9, "legs[1].actuator", "prismatic, revolute or extensible"},
      {{{10, "    base: [-0.17, -0.1]"}}, 10, "legs[1].base", "expected 3 numbers"},
      {{{16, "    axis: [0, 0, 0]"}}, 16, "legs[2].axis", "the axis is zero"},
      {{{14, "  - actuator: extensible"}, {16, "    offset: 0.3"}}, 17, "legs[2].rod", "has no 'rod'"},
      {{{14, "  - actuator: extensible"}}, 16, "legs[2].axis", "has no 'axis'"},
      {{{8, "    platform: [0, 0.04, 0]\n    branch: 2"}}, 9, "legs[0].branch", "not +1 or -1"},
      {{{8, "    platform: [0, 0.04, 0]\n    branch: 0"}}, 9, "legs[0].branch", "not +1 or -1"},
      {{{13, "    platform: [-0.03, .nan, 0]"}}, 13, "legs[1].platform[1]", "finite"},
      {{{15, "    base: [0.17, .inf, 0]"}}, 15, "legs[2].base[1]", "finite"},
      {{{7, "    rod: -0.25"}}, 7, "legs[0].rod", "out of range"},
      {{{7, "    rood: 0.25"}}, 7, "legs[0].rood", "did you mean 'rod'"},
      {{{14, ""}, {15, ""}, {16, ""}, {17, ""}, {18, ""}}, 3, "legs", "exactly 3 legs, not 2"},
      {{{2, "platform: full"}}, 3, "legs", "exactly 6 legs, not 3"},
      {{{2, "platform: planar"}}, 2, "platform", "translation or full"},
      {{{1, ""}}, 1, "name", "missing key"},
      {{{4, "  - actuator: revolute"}, {6, "    axis: [0, 0, 1]\n    arm: [0, 0, 0.1]"}},
       7,
       "legs[0].arm",
       "along the axis"},
      {{{4, "  - actuator: revolute"}}, 4, "legs[0].arm", "missing key"},
      {{{8, "    platform: [0, 0.04, 0]\n    gain: 1.01"}}, 9, "legs[0].gain", "gains: true"},
      {{{3, "home: {t: [0, 0, 0.1], r: [0, 0, 0.1]}\nlegs:"}}, 3, "home.r", "no rotation"},
      {{{3, "home: [0, 0]\nlegs:"}}, 3, "home", "expected 3 numbers"},
      {{{3, "gains: maybe\nlegs:"}}, 3, "gains", ""},
      {{{8, "    platform: [0, 0.04, 0]\n    stroke: [0.3, 0.1]"}}, 9, "legs[0].stroke", "is not below its maximum"},
      {{{8, "    platform: [0, 0.04, 0]\n    stroke: [0.1]"}}, 9, "legs[0].stroke", "expected 2 numbers"},
      {{{8, "    platform: [0, 0.04, 0]\n    stroke: 0.3"}}, 9, "legs[0].stroke", "expected 2 numbers"},
      {{{8, "    platform: [0, 0.04, 0]\n    stroke: [0.1, .inf]"}}, 9, "legs[0].stroke[1]", "finite"},
  };
  const test::TempDir dir;
  for (const BadFile& bad : cases) {
    const std::filesystem::path file = writeFile(dir, "robot.yaml", smallWith(bad.edits));
    try {
      readMechanismDescription(file);
      ADD_FAILURE() << "accepted: " << bad.key << " (" << bad.what << ")";
    } catch (const std::invalid_argument& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("robot.yaml:" + std::to_string(bad.line) + ":"), std::string::npos) << message;
      EXPECT_NE(message.find("'" + bad.key + "'"), std::string::npos) << message;
      EXPECT_NE(message.find(bad.what), std::string::npos) << message;
    }
  }
  EXPECT_THROW(readMechanismDescription(dir.path() / "absent.yaml"), std::invalid_argument);
}

// A leg's declared stroke (doc/mechanisms.md, "Described mechanisms"): read, written back, and
// the IKM names the legs whose reading falls outside it (the pose is still reachable); a
// revolute reading counts in the turn nearest the stroke.
TEST(DescribedFile, StrokesAreReadWrittenAndNamedByTheIkm) {
  const MechanismDescription d =
      parseMechanismDescription(smallWith({{8, "    platform: [0, 0.04, 0]\n    stroke: [0.2, 0.35]"}}), "s.yaml");
  ASSERT_TRUE(d.legs[0].stroke.has_value());
  EXPECT_EQ(*d.legs[0].stroke, Eigen::Vector2d(0.2, 0.35));
  EXPECT_FALSE(d.legs[1].stroke.has_value());
  expectSame(parseMechanismDescription(d.yamlString(), "again.yaml"), d);
  expectSame(describedWithParameters(d, describedParameters(d)), d);  // an identified file keeps it

  const std::unique_ptr<Mechanism> m = makeDescribedMechanism(d);
  const Eigen::VectorXd g = m->nominal().values();
  // Leg 1 (rail at y = 0.20, joint at y = 0.04): its carriage sits z + √(0.25² − 0.16²) = z + 0.1921 m up.
  const auto at = [&](double z) { return m->inverseKinematics(g, transform(Eigen::Vector3d::Zero(), {0, 0, z})); };
  const IkmResult inside = at(0.10), below = at(0.0), above = at(0.17);
  EXPECT_NEAR(inside.joints[0], 0.10 + std::sqrt(0.25 * 0.25 - 0.16 * 0.16), 1e-12);
  EXPECT_TRUE(inside.reachable() && inside.withinStroke());
  EXPECT_TRUE(below.reachable());
  EXPECT_EQ(below.out_of_stroke_joints, std::vector<int>{0});
  EXPECT_EQ(above.out_of_stroke_joints, std::vector<int>{0});

  MechanismDescription rus = readMechanismDescription(examplesDir() / "6-rus.yaml");
  const std::unique_ptr<Mechanism> plain = makeDescribedMechanism(rus);
  const Eigen::Isometry3d home = homeOf(*plain);
  const double q = plain->inverseKinematics(plain->nominal().values(), home).joints[3];
  rus.legs[3].stroke = Eigen::Vector2d(q + 2 * 3.14159265358979323846 - 0.1, q + 2 * 3.14159265358979323846 + 0.1);
  EXPECT_TRUE(makeDescribedMechanism(rus)->inverseKinematics(plain->nominal().values(), home).withinStroke());
  rus.legs[3].stroke = Eigen::Vector2d(q + 0.05, q + 0.5);
  EXPECT_EQ(makeDescribedMechanism(rus)->inverseKinematics(plain->nominal().values(), home).out_of_stroke_joints,
            std::vector<int>{3});
  rus.legs[3].stroke = Eigen::Vector2d(0.5, 0.5);
  EXPECT_THROW(makeDescribedModel(rus), std::invalid_argument);
}

TEST(DescribedFile, DescriptionsBuiltInCodeAreChecked) {
  MechanismDescription d = readMechanismDescription(examplesDir() / "6-pus.yaml");
  d.legs[2].branch = 0;
  EXPECT_THROW(makeDescribedModel(d), std::invalid_argument);
  d.legs[2].branch = 1;
  d.legs[2].axis = Eigen::Vector3d(0, 0, 2);
  EXPECT_THROW(makeDescribedModel(d), std::invalid_argument);
  d.legs[2].axis = Eigen::Vector3d::UnitZ();
  d.legs.pop_back();
  EXPECT_THROW(makeDescribedModel(d), std::invalid_argument);
}

}  // namespace
}  // namespace mire::mechanism
