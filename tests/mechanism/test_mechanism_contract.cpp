// The same contract for every registered mechanism (doc/mechanisms.md): IKM and FKM are
// inverse, the autodiff cost Jacobian matches finite differences, identification recovers
// a perturbed truth from an exact-model campaign, and the identifiability analysis finds the
// expected rank and names what the camera cannot see.
#include <ceres/cost_function.h>
#include <gtest/gtest.h>

#include <algorithm>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/identification.hpp"

namespace mire::mechanism {
namespace {

using datasets::Campaign;
using datasets::simulateCampaign;

struct H4Model12 {
  static std::string name() { return "h4-12"; }
  static constexpr int kRank = 19;
};
struct H4Model31 {
  static std::string name() { return "h4-31"; }
  static constexpr int kRank = -1;
};
struct Delta {
  static std::string name() { return "delta"; }
  static constexpr int kRank = 14;
};
struct DeltaLegs {
  static std::string name() { return "delta-legs"; }
  static constexpr int kRank = 24;
};
struct GoughStewart {
  static std::string name() { return "gough-stewart"; }
  static constexpr int kRank = 42;
};
struct GoughStewartSymmetric {
  static std::string name() { return "gough-stewart-symmetric"; }
  static constexpr int kRank = 17;
};
struct GoughStewartGains {
  static std::string name() { return "gough-stewart-gains"; }
  static constexpr int kRank = 48;
};

template <class M>
class MechanismContract : public ::testing::Test {};
using Models =
    ::testing::Types<H4Model12, H4Model31, Delta, DeltaLegs, GoughStewartSymmetric, GoughStewart, GoughStewartGains>;
TYPED_TEST_SUITE(MechanismContract, Models);

TYPED_TEST(MechanismContract, IkmAndFkmAreInverse) {
  const Campaign c = simulateCampaign(TypeParam::name(), 1, 0.0, 0.0);
  const Mechanism& m = *c.model.mechanism;
  const Eigen::VectorXd g = c.truth.values();
  for (const PoseObservation& p : c.poses) {
    const FkmResult fkm = m.forwardKinematics(g, p.joints, m.referencePose(g));
    ASSERT_TRUE(fkm.converged) << p.id << ": " << fkm.message;
    const Eigen::Isometry3d truth = c.bTe[std::stoul(p.id) - 1];
    EXPECT_LT((fkm.bTe.translation() - truth.translation()).norm(), 1e-10) << p.id;
    EXPECT_LT(Eigen::AngleAxisd(fkm.bTe.linear().transpose() * truth.linear()).angle(), 1e-10) << p.id;
    const IkmResult ikm = m.inverseKinematics(g, fkm.bTe);
    ASSERT_TRUE(ikm.reachable());
    EXPECT_LT((ikm.joints - p.joints).cwiseAbs().maxCoeff(), 1e-10) << p.id;
  }
  EXPECT_EQ(static_cast<int>(m.jointColumnNames().size()), m.jointCount());
}

TYPED_TEST(MechanismContract, AutodiffJacobianMatchesFiniteDifferences) {
  const Campaign c = simulateCampaign(TypeParam::name(), 2);
  const IdentificationModel model = makeInitialModel(c.model.mechanism, c.truth, c.poses, c.model.external_form);
  const Mechanism& m = *model.mechanism;
  const int J = m.jointCount(), G = model.geometricCount(), E = model.external.size();
  const PoseObservation& p = c.poses[4];
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
    EXPECT_LT((fd - ad).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, ad.cwiseAbs().maxCoeff())) << "column " << k;
  }
}

TYPED_TEST(MechanismContract, IdentificationRecoversPerturbedTruth) {
  const Campaign c = simulateCampaign(TypeParam::name(), 3, 0.0, 0.0);
  IdentificationModel model = makeInitialModel(c.model.mechanism, c.model.nominal, c.poses, c.model.external_form);
  const GaugeAnalysis gauge = fixGauge(model, c.poses);
  if (TypeParam::kRank > 0) {
    EXPECT_EQ(gauge.report.rank, TypeParam::kRank) << gauge.text();
  }
  EXPECT_EQ(gauge.report.rank, static_cast<int>(model.parameters.freeCount())) << gauge.text();
  IdentificationOptions options;
  options.compute_identifiability = true;
  const IdentificationResult result = identify(model, c.poses, options);
  EXPECT_LT(result.rms_joint_residual, 1e-9) << gauge.text();
  EXPECT_TRUE(result.identifiability.fullRank()) << result.identifiability.text();
  // Parameters in no unidentifiable combination are the truth's, whatever the gauge.
  int checked = 0;
  for (const std::string& name : gauge.identified) {
    if (!c.truth.contains(name)) continue;
    EXPECT_NEAR(result.model.parameters.value(name), c.truth.value(name), 1e-6) << name;  // h4-31: cond ~ 2000
    ++checked;
  }
  if (c.model.mechanism->motionType() != MotionType::Schoenflies) {
    EXPECT_GT(checked, 0) << gauge.text();
  }
}

// The Delta's base offsets and its legs' base positions are equivalent (a translating target):
// the gauge holds the mounting, whatever the rounding. Before the pivot priority, rounding freed
// tx_CB and ty_CB on 4 of 120 rendered chains, where identify then returned a base turned by up
// to 9° (17–58σ; doc/studies/2026-11-25-delta-gauge-120-chains.md), and here on seeds
// 3 and 6 (of 60 tried with the priority: none).
TEST(MechanismContractNames, TheDeltaGaugeHoldsTheBaseOffsetsNotTheLegs) {
  for (unsigned seed = 1; seed <= 12; ++seed) {
    const Campaign c = simulateCampaign("delta-legs", seed);
    IdentificationModel model = makeInitialModel(c.model.mechanism, c.model.nominal, c.poses, c.model.external_form);
    const GaugeAnalysis gauge = fixGauge(model, c.poses);
    for (const char* name : {"tx_CB", "ty_CB"})
      EXPECT_TRUE(model.parameters.at(name).fixed) << "seed " << seed << ": " << name << " free\n" << gauge.text();
  }
}

TEST(MechanismContractNames, IdentifiabilityNamesWhatTheCameraCannotSee) {
  // Delta: the plate never turns, so eTm's rotation has no influence and the target offset
  // merges with the camera position (3 + 3 gauge directions).
  const Campaign delta = simulateCampaign("delta", 4);
  IdentificationModel model =
      makeInitialModel(delta.model.mechanism, delta.model.nominal, delta.poses, ExternalForm::Full);
  const GaugeAnalysis a = analyzeGauge(model, delta.poses);
  EXPECT_EQ(a.gauge.size(), 6u) << a.text();
  EXPECT_EQ(a.no_influence.size(), 3u) << a.text();
  for (const std::string& name : a.gauge)
    EXPECT_TRUE(name.find("_EM") != std::string::npos || name.find("_CB") != std::string::npos) << name;
  // Gough–Stewart: 12 frame gauge directions, rho0 identified.
  const Campaign gs = simulateCampaign("gough-stewart", 5);
  IdentificationModel gsm = makeInitialModel(gs.model.mechanism, gs.model.nominal, gs.poses, ExternalForm::Full);
  const GaugeAnalysis b = analyzeGauge(gsm, gs.poses);
  EXPECT_EQ(b.gauge.size(), 12u) << b.text();
  for (int i = 1; i <= 6; ++i)
    EXPECT_NE(std::find(b.identified.begin(), b.identified.end(), "rho0" + std::to_string(i)), b.identified.end())
        << b.text();
}

TEST(MechanismContractNames, RegistryRejectsUnknownNames) {
  try {
    makeRegisteredModel("delta3");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("gough-stewart"), std::string::npos);
  }
  EXPECT_EQ(makeRegisteredModel("gough-stewart").mechanism->jointColumnNames()[5], "q6_m");
  EXPECT_EQ(makeRegisteredModel("delta").mechanism->jointColumnNames()[0], "q1_rad");
}

}  // namespace
}  // namespace mire::mechanism
