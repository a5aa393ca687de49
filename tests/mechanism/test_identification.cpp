// Identification of the simulated H4 (paper §6 protocol, doc/mechanisms.md): recovery within the predicted σ,
// Monte-Carlo coverage of σ, external initialisation, rank and named combinations (eq. 24),
// variants A–H (Table 2), outliers, priors.
#include <gtest/gtest.h>

#include <ctime>
#include <iostream>
#include <map>
#include <random>

#include "h4_test_robot.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/identification_covariance.hpp"
#include "mire/mechanism/variants.hpp"

namespace mire::mechanism {
namespace {

using test::kDeg;

// Model 12 + the 7 external parameters, initialised from the data, z_ME at its true value.
IdentificationModel initialModel12(const test::TestRobot& robot, const std::vector<PoseObservation>& poses) {
  IdentificationModel model =
      makeInitialModel(robot.mechanism, h4Model12Parameters(robot.nominal), poses, ExternalForm::AxisAligned);
  model.parameters.setValue("z_ME", robot.trueZME(model.external.alignment()));
  return model;
}

// One Monte-Carlo draw: noisy observations of the protocol poses, model 12 fitted without the
// identifiability report.
IdentificationResult fitNoisyDraw(const test::TestRobot& robot, std::mt19937& rng, std::vector<PoseObservation>& poses) {
  poses = robot.observe(test::TestRobot::protocolPoses(), &rng);
  IdentificationOptions options;
  options.compute_identifiability = false;
  return identify(initialModel12(robot, poses), poses, options);
}

TEST(Identification, ExternalInitialisationIsExactOnExactData) {
  const test::TestRobot robot;
  const auto poses = robot.observe(test::TestRobot::protocolPoses(), nullptr);
  ExternalParameterization form(ExternalForm::AxisAligned);
  // With the true geometry the FKM poses are exact: the closed form must return the truth.
  const ParameterSet ext =
      estimateExternal(*robot.mechanism, robot.truth.values(), poses, ExternalForm::AxisAligned, form, /*z_ME=*/0.0);
  const Eigen::Isometry3d bTc = form.baseFromCamera(ext.values());
  const Eigen::Isometry3d mTe = form.targetFromEffector(ext.values());
  // z_BC + z_ME is all the data fix: compare with the z part moved into bTc.
  const Eigen::Vector3d axis_in_base = Eigen::Vector3d::UnitZ();
  const double z_shift = (robot.mTe.translation() - mTe.translation()).dot(mTe.linear() * Eigen::Vector3d::UnitZ());
  EXPECT_LT((bTc.linear() - robot.bTc.linear()).norm(), 1e-9);
  EXPECT_LT((mTe.linear() - robot.mTe.linear()).norm(), 1e-9);
  EXPECT_LT((bTc.translation() - z_shift * axis_in_base - robot.bTc.translation()).norm(), 1e-9);
  EXPECT_LT((mTe.translation() + z_shift * (mTe.linear() * Eigen::Vector3d::UnitZ()) - robot.mTe.translation()).norm(),
            1e-9);
}

TEST(Identification, Model12RecoversTruthWithinPredictedSigma) {
  const test::TestRobot robot;
  std::mt19937 rng(7);
  const auto poses = robot.observe(test::TestRobot::protocolPoses(), &rng);
  const IdentificationModel model = initialModel12(robot, poses);
  EXPECT_EQ(model.parameters.freeCount(), 19u);
  const std::clock_t cpu_start = std::clock();
  IdentificationResult r = identify(model, poses);
  for (int repeat = 0; repeat < 4; ++repeat) r = identify(model, poses);
  std::cout << "identify: " << 1e3 * double(std::clock() - cpu_start) / CLOCKS_PER_SEC / 5
            << " ms CPU per run (timing only, see bench_identify)\n";
  ASSERT_TRUE(r.converged) << r.solver_report;
  EXPECT_TRUE(r.weighted);
  EXPECT_TRUE(r.identifiability.fullRank());
  EXPECT_EQ(r.identifiability.rank, 19);
  EXPECT_TRUE(r.outliers.empty());
  EXPECT_NEAR(r.residual_scale, 1.0, 0.2);  // χ²/dof with the true pose covariances
  const Eigen::VectorXd truth = robot.trueValues(r.model);
  std::cout << "model 12 + 7 external: cond " << r.identifiability.condition_number
            << " (unit-norm columns), rms joint residual " << r.rms_joint_residual << " rad, solve "
            << r.solve_seconds * 1e3 << " ms, " << r.iterations << " iterations\n";
  for (const std::string& name : r.free_names) {
    const std::size_t i = r.model.parameters.index(name);
    const double error = r.model.parameters[i].value - truth[static_cast<Eigen::Index>(i)];
    const double sigma = r.sigmaOf(name);
    std::cout << "  " << name << ": error " << error << ", sigma " << sigma << ", error/sigma " << error / sigma << "\n";
    EXPECT_LT(std::abs(error), 3.0 * sigma) << name;
  }
}

TEST(Identification, MonteCarloSpreadMatchesPredictedSigma) {
  const test::TestRobot robot;
  const auto exact = robot.observe(test::TestRobot::protocolPoses(), nullptr);
  const int draws = 200;
  std::mt19937 rng(2026);
  std::vector<Eigen::VectorXd> errors;
  Eigen::VectorXd predicted;
  std::vector<std::string> names;
  std::vector<PoseObservation> poses;
  for (int draw = 0; draw < draws; ++draw) {
    const IdentificationResult r = fitNoisyDraw(robot, rng, poses);
    ASSERT_TRUE(r.converged);
    const Eigen::VectorXd truth = robot.trueValues(r.model);
    Eigen::VectorXd e(static_cast<Eigen::Index>(r.free_names.size()));
    Eigen::VectorXd s(e.size());
    for (std::size_t k = 0; k < r.free_names.size(); ++k) {
      const std::size_t i = r.model.parameters.index(r.free_names[k]);
      e[static_cast<Eigen::Index>(k)] = r.model.parameters[i].value - truth[static_cast<Eigen::Index>(i)];
      s[static_cast<Eigen::Index>(k)] = r.sigma[static_cast<Eigen::Index>(i)];
    }
    errors.push_back(e);
    predicted = draw == 0 ? s : Eigen::VectorXd(predicted + s);
    names = r.free_names;
  }
  predicted /= draws;
  std::cout << "Monte Carlo (" << draws << " draws): spread / predicted sigma\n";
  for (std::size_t k = 0; k < names.size(); ++k) {
    double mean = 0.0, sq = 0.0;
    for (const auto& e : errors) mean += e[static_cast<Eigen::Index>(k)] / draws;
    for (const auto& e : errors) sq += std::pow(e[static_cast<Eigen::Index>(k)] - mean, 2);
    const double spread = std::sqrt(sq / (draws - 1));
    const double ratio = spread / predicted[static_cast<Eigen::Index>(k)];
    std::cout << "  " << names[k] << ": " << ratio << " (bias " << mean / predicted[static_cast<Eigen::Index>(k)]
              << " sigma)\n";
    EXPECT_GT(ratio, 0.8) << names[k];
    EXPECT_LT(ratio, 1.25) << names[k];
    EXPECT_LT(std::abs(mean), 0.5 * predicted[static_cast<Eigen::Index>(k)]) << names[k] << " biased";
  }
}

// The residual sandwich (sandwichCovariance) with its CR2 leverage adjustment is unbiased when the
// weights are right: its mean over draws equals (AᵀA)⁻¹ for every parameter (0.97–1.03 here).
// Without the adjustment it averages as little as 0.85 of that, by a factor that differs from
// parameter to parameter (the leverage of the poses fixing each), which the uniform
// m/(m − p) = 1.31 it replaced could not follow.
TEST(Identification, ResidualSandwichIsUnbiasedWithRightWeights) {
  const test::TestRobot robot;
  const int draws = 100;
  std::mt19937 rng(28);
  Eigen::VectorXd ratio_sum;
  std::vector<std::string> names;
  std::vector<PoseObservation> poses;
  for (int draw = 0; draw < draws; ++draw) {
    const IdentificationResult r = fitNoisyDraw(robot, rng, poses);
    ASSERT_TRUE(r.converged);
    const Eigen::VectorXd ratio = sandwichCovariance(r, poses).diagonal().cwiseQuotient(r.information_inverse.diagonal());
    ratio_sum = draw == 0 ? ratio : Eigen::VectorXd(ratio_sum + ratio);
    names = r.free_names;
  }
  for (std::size_t k = 0; k < names.size(); ++k) {
    const double mean = ratio_sum[static_cast<Eigen::Index>(k)] / draws;
    std::cout << "  " << names[k] << ": mean sandwich / (AᵀA)⁻¹ " << mean << "\n";
    EXPECT_NEAR(mean, 1.0, 0.06) << names[k];
  }
}

// A robot whose joint offsets are 5° from nominal: at the nominal geometry no pose reproduces
// some encoder readings exactly (the FKM stops a few mrad away); the initial external values
// start from those least-squares poses, and the identification still recovers the truth.
TEST(Identification, InitialisesWhereTheNominalFkmHasNoExactSolution) {
  test::TestRobot robot;
  const double dq0[4] = {5.0, -4.5, 5.0, -5.0};
  for (int i = 0; i < 4; ++i) robot.truth.setValue("q0" + std::to_string(i + 1), dq0[i] * kDeg);
  std::mt19937 rng(5);
  const auto poses = robot.observe(test::TestRobot::protocolPoses(), &rng);
  const Eigen::VectorXd nominal = h4Model12Parameters(robot.nominal).values();
  int inexact = 0;
  for (const PoseObservation& p : poses)
    inexact += !robot.mechanism->forwardKinematics(nominal, p.joints, robot.mechanism->referencePose(nominal)).converged;
  ASSERT_GT(inexact, 0) << "the case this test is for: the nominal FKM reproduces every pose";
  const IdentificationResult r = identify(initialModel12(robot, poses), poses);
  ASSERT_TRUE(r.converged) << r.solver_report;
  const Eigen::VectorXd truth = robot.trueValues(r.model);
  for (const std::string& name : r.free_names) {
    const std::size_t i = r.model.parameters.index(name);
    EXPECT_LT(std::abs(r.model.parameters[i].value - truth[static_cast<Eigen::Index>(i)]), 4.0 * r.sigmaOf(name)) << name;
  }
}

TEST(Identification, FreeingZmeLosesOneRankAndNamesEq24) {
  const test::TestRobot robot;
  const auto poses = robot.observe(test::TestRobot::protocolPoses(), nullptr);
  IdentificationModel model = initialModel12(robot, poses);
  model.parameters.setValues(robot.trueValues(model));
  model.parameters.setFixed("z_ME", false);
  const IdentifiabilityReport report = analyzeIdentifiability(model, poses);
  std::cout << report.text();
  EXPECT_EQ(report.rank, 19);
  ASSERT_EQ(report.combinations.size(), 1u);
  const UnidentifiableCombination& c = report.combinations[0];
  // δz_BC = −δz_ME (axis-aligned form: the rotation axis is z_B, r33 = 1).
  std::map<std::string, double> direction(c.direction.begin(), c.direction.end());
  ASSERT_EQ(direction.size(), 2u) << c.text();
  ASSERT_TRUE(direction.count("z_ME") && direction.count("z_BC")) << c.text();
  EXPECT_NEAR(direction["z_BC"] / direction["z_ME"], -1.0, 1e-6);
}

TEST(Identification, FullExternalFormNamesEq24Combination) {
  const test::TestRobot robot;
  const auto poses = robot.observe(test::TestRobot::protocolPoses(), nullptr);
  ExternalParameterization full(ExternalForm::Full);
  ParameterSet ext = full.parameters();
  ext.setValues(full.valuesFrom(robot.bTc, robot.mTe));
  const IdentificationModel model = makeIdentificationModel(robot.mechanism, robot.truth, full, ext);
  const IdentifiabilityReport report = analyzeIdentifiability(model, poses);
  std::cout << report.text();
  EXPECT_EQ(report.parameter_names.size(), 24u);
  // eq. 24: c t_B,l + cR_B,l3 · e t_M,3 only as sums, plus the invisible effector tilt (2).
  EXPECT_EQ(report.rank, 21);
  const Eigen::Matrix3d cRb = robot.bTc.linear().transpose();
  bool found = false;
  for (const UnidentifiableCombination& c : report.combinations) {
    std::map<std::string, double> d(c.direction.begin(), c.direction.end());
    if (!d.count("tz_EM") || !d.count("tx_CB")) continue;
    found = true;
    // Direction: δt_CB = −cR_B(:,3)·δtz_EM (relative to tz_EM's coefficient).
    const double unit = d["tz_EM"];
    EXPECT_NEAR(d["tx_CB"] / unit, -cRb(0, 2), 1e-6) << c.text();
    EXPECT_NEAR(d["ty_CB"] / unit, -cRb(1, 2), 1e-6) << c.text();
    EXPECT_NEAR(d["tz_CB"] / unit, -cRb(2, 2), 1e-6) << c.text();
  }
  EXPECT_TRUE(found) << report.text();
}

TEST(Identification, Model31CameraFrameHas36IdentifiableParameters) {
  const test::TestRobot robot;
  const auto poses = robot.observe(test::TestRobot::protocolPoses(), nullptr);
  const IdentificationModel model = makeH4VariantModel('H', robot.nominal, poses);
  EXPECT_EQ(model.parameters.freeCount(), 36u);
  const IdentifiabilityReport report = analyzeIdentifiability(model, poses);
  std::cout << "model 31 camera frame: rank " << report.rank << ", cond " << report.condition_number << "\n";
  EXPECT_EQ(report.rank, 36);

  // Model 31 in the base frame with the 7 external parameters: 38 unknowns, d couples with y_BC.
  Eigen::Vector3d shift;
  const ParameterSet p31 = model31FromModel12(robot.truth, &shift);
  ExternalParameterization aligned(ExternalForm::AxisAligned);
  ParameterSet ext = aligned.parameters();
  Eigen::Isometry3d b31Tc = robot.bTc;
  b31Tc.translation() -= shift;
  ext.setValues(aligned.valuesFrom(b31Tc, robot.mTe));
  const IdentificationModel base31 = makeIdentificationModel(makeH4Mechanism(H4ModelKind::Model31), p31, aligned, ext);
  EXPECT_EQ(base31.parameters.freeCount(), 38u);
  const IdentifiabilityReport r31 = analyzeIdentifiability(base31, poses);
  std::cout << r31.text();
  EXPECT_LT(r31.rank, 38);
  bool d_named = false;
  for (const auto& c : r31.combinations)
    for (const auto& term : c.direction) d_named = d_named || term.first == "d";
  EXPECT_TRUE(d_named);
}

TEST(Identification, VariantsMatchTable2Counts) {
  const test::TestRobot robot;
  std::mt19937 rng(11);
  const auto poses = robot.observe(test::TestRobot::protocolPoses(), &rng);
  for (const H4Variant& v : h4Variants()) {
    const IdentificationModel model = makeH4VariantModel(v.letter, robot.nominal, poses);
    int geometric = 0, external = 0;
    for (std::size_t i : model.parameters.freeIndices())
      (static_cast<int>(i) < model.geometricCount() ? geometric : external)++;
    EXPECT_EQ(geometric, v.geometric_count) << v.letter;
    EXPECT_EQ(external, v.external_count) << v.letter;
    const IdentificationResult r = identify(model, poses);
    EXPECT_TRUE(r.converged) << v.letter;
    // A, B, E, F hold h at its nominal value, 0.7 mm from the truth: the misfit must show.
    const bool h_fixed = v.letter == 'A' || v.letter == 'B' || v.letter == 'E' || v.letter == 'F';
    if (h_fixed)
      EXPECT_GT(r.residual_scale, 1.3) << v.letter;
    else
      EXPECT_NEAR(r.residual_scale, 1.0, 0.35) << v.letter;
    std::cout << "variant " << v.letter << ": " << geometric << "+" << external << " parameters, cond "
              << r.identifiability.condition_number << ", rms " << r.rms_joint_residual << " rad\n";
    if (v.letter == 'E') {
      EXPECT_DOUBLE_EQ(r.model.parameters.value("L1"), r.model.parameters.value("L4"));
      EXPECT_DOUBLE_EQ(r.model.parameters.value("l2"), robot.nominal.l);
    }
  }
  EXPECT_THROW(h4Variant('Z'), std::invalid_argument);
}

TEST(Identification, RobustLossReportsOutlierPose) {
  const test::TestRobot robot;
  std::mt19937 rng(5);
  auto poses = robot.observe(test::TestRobot::protocolPoses(), &rng);
  poses[40].joints[2] += 0.02;  // a gross encoder error on one pose
  IdentificationOptions options;
  options.loss = RobustLoss::Huber;
  const IdentificationResult r = identify(initialModel12(robot, poses), poses, options);
  ASSERT_EQ(r.outliers.size(), 1u);
  EXPECT_EQ(r.outliers[0], poses[40].id);
  const Eigen::VectorXd truth = robot.trueValues(r.model);
  for (const std::string& name : r.free_names) {
    const std::size_t i = r.model.parameters.index(name);
    EXPECT_LT(std::abs(r.model.parameters[i].value - truth[static_cast<Eigen::Index>(i)]), 4.0 * r.sigmaOf(name)) << name;
  }
}

TEST(Identification, UnweightedPriorsAndBadOptions) {
  const test::TestRobot robot;
  std::mt19937 rng(9);
  auto poses = robot.observe(test::TestRobot::protocolPoses(), &rng);
  for (auto& p : poses) p.covariance.reset();
  IdentificationOptions options;
  options.priors.push_back({"l", 0.7005, 1e-7});
  const IdentificationResult r = identify(initialModel12(robot, poses), poses, options);
  EXPECT_FALSE(r.weighted);
  EXPECT_NEAR(r.model.parameters.value("l"), 0.7005, 1e-6);
  EXPECT_LT(r.sigmaOf("l"), 2e-7);
  EXPECT_GT(r.residual_scale, 0.0);

  IdentificationOptions bad;
  bad.fix = {"not_a_parameter"};
  EXPECT_THROW(identify(initialModel12(robot, poses), poses, bad), std::invalid_argument);
  IdentificationOptions bad_prior;
  bad_prior.priors.push_back({"R", 0.22, -1.0});
  EXPECT_THROW(identify(initialModel12(robot, poses), poses, bad_prior), std::invalid_argument);

  // An unreachable pose at the initial values is named.
  IdentificationModel model = initialModel12(robot, poses);
  auto far = poses;
  far[3].cTm[2] += 5.0;
  try {
    identify(model, far);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(far[3].id), std::string::npos) << e.what();
  }
}

TEST(Identification, ConditionNumbersOnRandomPoses) {
  // Paper Table 1 uses 100 random poses in the workspace: report ours (unit-norm columns).
  const test::TestRobot robot;
  std::mt19937 rng(100);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Eigen::Isometry3d> random;
  for (int i = 0; i < 100; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(20.0 * kDeg * u(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() << 0.1 * u(rng), 0.1 * u(rng), -0.62 + 0.075 * u(rng);
    random.push_back(T);
  }
  const auto poses = robot.observe(random, nullptr);
  IdentificationModel m12 = initialModel12(robot, poses);
  m12.parameters.setValues(robot.trueValues(m12));
  const IdentifiabilityReport r12 = analyzeIdentifiability(m12, poses);
  IdentificationModel geometric_only = m12;
  for (const std::string& n : m12.external.parameters().names()) geometric_only.parameters.setFixed(n);
  const IdentifiabilityReport g12 = analyzeIdentifiability(geometric_only, poses);
  const IdentificationModel h = makeH4VariantModel('H', robot.nominal, poses);
  const IdentifiabilityReport r31c = analyzeIdentifiability(h, poses);
  // Model 31 (base frame), geometric parameters only, without and with d (paper Table 1).
  Eigen::Vector3d shift;
  const ParameterSet p31 = model31FromModel12(robot.truth, &shift);
  ExternalParameterization aligned(ExternalForm::AxisAligned, m12.external.alignment());
  ParameterSet ext = aligned.parameters();
  Eigen::Isometry3d b31Tc = robot.bTc;
  b31Tc.translation() -= shift;
  ext.setValues(aligned.valuesFrom(b31Tc, robot.mTe));
  IdentificationModel m31 = makeIdentificationModel(makeH4Mechanism(H4ModelKind::Model31), p31, aligned, ext);
  for (const std::string& n : aligned.parameters().names()) m31.parameters.setFixed(n);
  const IdentifiabilityReport with_d = analyzeIdentifiability(m31, poses);
  m31.parameters.setFixed("d");
  const IdentifiabilityReport without_d = analyzeIdentifiability(m31, poses);
  EXPECT_EQ(with_d.rank, 31);
  EXPECT_EQ(without_d.rank, 30);
  EXPECT_GT(with_d.condition_number, without_d.condition_number);
  std::cout << "cond (100 random poses, unit-norm columns): model 31 geometric without d " << without_d.condition_number
            << ", with d " << with_d.condition_number << "\n";
  std::cout << "cond (100 random poses, unit-norm columns): model 12 geometric " << g12.condition_number
            << ", model 12 + 7 external " << r12.condition_number << ", model 31 camera frame (36) "
            << r31c.condition_number << "\n";
  EXPECT_TRUE(r12.fullRank());
  EXPECT_TRUE(r31c.fullRank());
}

}  // namespace
}  // namespace mire::mechanism
