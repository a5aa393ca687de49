// Leg observations (doc/legs.md): the mechanisms' leg segments, and the identification from leg
// lines simulated at the line level with a covariance of the shape a rod's two contours give
// (depth along the line of sight much less certain than across it).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/leg_identification.hpp"
#include "mire/mechanism/registry.hpp"

#include "sample_statistics.hpp"

namespace {

using namespace mire;
using namespace mire::mechanism;

// Representative leg-line errors for a rod of ~15 mm radius seen from ~1.3 m through ten images
// (doc/legs.md, "Precision"): across the line of sight 0.05 mm and 0.1 mrad, along it (the depth the
// apparent width gives) 1 mm and 2 mrad, in the line's tangent basis.
Eigen::Matrix4d legCovariance(const support::Line3d& line, double scale = 1.0) {
  const Eigen::Vector3d c = line.closestPointToOrigin();
  const Eigen::Vector3d depth = c.normalized(), across = line.direction.cross(depth);
  const auto [e1, e2] = support::lineTangentBasis(line.direction);
  Eigen::Matrix<double, 3, 2> E;
  E << e1, e2;
  const Eigen::Matrix3d angle = 4e-6 * depth * depth.transpose() + 1e-8 * across * across.transpose();
  const Eigen::Matrix3d shift = 1e-6 * depth * depth.transpose() + 2.5e-9 * across * across.transpose();
  Eigen::Matrix4d sigma = Eigen::Matrix4d::Zero();
  sigma.topLeftCorner<2, 2>() = E.transpose() * angle * E;
  sigma.bottomRightCorner<2, 2>() = E.transpose() * shift * E;
  return scale * scale * sigma;
}

// Lines drawn from `legCovariance` × noise_scale², stated with `legCovariance` (noise_scale 1: right).
std::vector<LegObservation> simulateLegs(const datasets::Campaign& c, unsigned seed, std::size_t count,
                                         double noise_scale = 1.0) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const Mechanism& m = *c.model.mechanism;
  const Eigen::Isometry3d cTb = c.bTc.inverse();
  std::vector<LegObservation> out;
  for (std::size_t j = 0; j < count; ++j) {
    const std::vector<LegSegment> segments = m.legSegments(c.truth.values(), c.bTe[j]);
    for (int i = 0; i < m.legCount(); ++i) {
      const LegSegment& s = segments[static_cast<std::size_t>(i)];
      const support::Line3d truth = support::Line3d::throughPoints(cTb * s.from, cTb * s.to);
      const Eigen::Matrix4d sigma = legCovariance(truth, noise_scale);
      const Eigen::Vector4d z(normal(rng), normal(rng), normal(rng), normal(rng));
      const support::Line3d measured = support::perturbLine(truth, Eigen::LLT<Eigen::Matrix4d>(sigma).matrixL() * z);
      out.push_back({c.poses[j].id, i, measured, legCovariance(measured)});
    }
  }
  return out;
}

TEST(LegSegments, HexapodLegsJoinTheJointsAtTheEncodersLength) {
  const datasets::Campaign c = datasets::simulateCampaign("gough-stewart", 1);
  const Mechanism& m = *c.model.mechanism;
  ASSERT_EQ(m.legCount(), 6);
  const Eigen::VectorXd g = c.truth.values();
  const std::vector<LegSegment> legs = m.legSegments(g, c.bTe[5]);
  ASSERT_EQ(legs.size(), 6u);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR((legs[i].to - legs[i].from).norm(), c.poses[5].joints[i] + g[36 + i], 1e-12);
    EXPECT_NEAR((legs[i].from - g.segment<3>(3 * i)).norm(), 0.0, 1e-15);
  }
}

// The symmetric layout's legs at its nominal are the 42-parameter hexapod's at its nominal (the
// same joints), and their lengths are what its IKM reads plus rho0.
TEST(LegSegments, SymmetricHexapodLegsAreTheNominalHexapods) {
  const RegisteredModel symmetric = makeRegisteredModel("gough-stewart-symmetric");
  const RegisteredModel full = makeRegisteredModel("gough-stewart");
  const Eigen::VectorXd g = symmetric.nominal.values();
  Eigen::Isometry3d bTe = Eigen::Isometry3d::Identity();
  bTe.translation() = Eigen::Vector3d(0.01, -0.02, 0.41);
  bTe.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const std::vector<LegSegment> a = symmetric.mechanism->legSegments(g, bTe);
  const std::vector<LegSegment> b = full.mechanism->legSegments(full.nominal.values(), bTe);
  ASSERT_EQ(a.size(), 6u);
  ASSERT_EQ(b.size(), 6u);
  const IkmResult ikm = symmetric.mechanism->inverseKinematics(g, bTe);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_LT((a[i].from - b[i].from).norm(), 1e-12) << i;
    EXPECT_LT((a[i].to - b[i].to).norm(), 1e-12) << i;
    EXPECT_NEAR((a[i].to - a[i].from).norm(), ikm.joints[static_cast<Eigen::Index>(i)] + g[4], 1e-12) << i;
  }
}

TEST(LegSegments, DeltaForearmsHaveTheForearmLengthAndStartAtTheElbows) {
  const datasets::Campaign c = datasets::simulateCampaign("delta", 1);
  const Mechanism& m = *c.model.mechanism;
  ASSERT_EQ(m.legCount(), 3);
  const ParameterSet& p = c.truth;
  const std::vector<LegSegment> legs = m.legSegments(p.values(), c.bTe[7]);
  ASSERT_EQ(legs.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    const double a = p.value("alpha" + std::to_string(i + 1));
    const Eigen::Vector3d pivot = p.value("R") * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
    EXPECT_NEAR((legs[i].to - legs[i].from).norm(), p.value("l"), 1e-9);
    EXPECT_NEAR((legs[i].from - pivot).norm(), p.value("L"), 1e-12);
  }
}

// One legs-only hexapod campaign: base joints in the camera frame against the truth, in σ.
struct BaseJointErrors {
  std::vector<double> normalised;
  double largest_mm = 0.0, median_sigma_mm = 0.0;
};

void legsOnlyCampaign(unsigned seed, BaseJointErrors& out, std::vector<double>& sigmas) {
  constexpr std::size_t kPoses = 30;
  const datasets::Campaign c = datasets::simulateCampaign(makeRegisteredModel("gough-stewart"), seed, 0.2e-3,
                                                          0.03 * datasets::kCampaignDeg, 0, kPoses);
  const std::vector<LegObservation> legs = simulateLegs(c, seed + 77, kPoses);
  const std::vector<PoseObservation> poses(c.poses.begin(), c.poses.end());
  IdentificationModel model = makeLegsInitialModel(c.model.mechanism, c.model.nominal, legs);
  LegIdentificationOptions options;
  options.observations = Observations::Legs;
  options.fix = legsOnlyGauge(model);
  const LegIdentificationResult r = identifyWithLegs(model, poses, legs, options);
  ASSERT_TRUE(r.converged) << "campaign " << seed;
  EXPECT_TRUE(r.identifiability.fullRank()) << "campaign " << seed << ": " << r.identifiability.text();
  EXPECT_LT(r.chi2 / r.dof, 1.5) << "campaign " << seed;
  const Eigen::Isometry3d cTb = r.model.external.baseFromCamera(r.model.externalValues()).inverse();
  const Eigen::Isometry3d cTb_true = c.bTc.inverse();
  for (int i = 0; i < 6; ++i) {
    const std::string n = std::to_string(i + 1);
    const Eigen::Vector3d b(r.model.parameters.value("bx" + n), r.model.parameters.value("by" + n),
                            r.model.parameters.value("bz" + n));
    const Eigen::Vector3d truth(c.truth.value("bx" + n), c.truth.value("by" + n), c.truth.value("bz" + n));
    Eigen::Matrix3d cov;
    const auto at = [&](const std::string& name) {
      return static_cast<Eigen::Index>(std::find(r.free_names.begin(), r.free_names.end(), name) - r.free_names.begin());
    };
    const Eigen::Index k[3] = {at("bx" + n), at("by" + n), at("bz" + n)};
    for (int u = 0; u < 3; ++u)
      for (int v = 0; v < 3; ++v) cov(u, v) = r.covariance(k[u], k[v]);
    const Eigen::Matrix3d cov_c = cTb.linear() * cov * cTb.linear().transpose();
    const Eigen::Vector3d error = cTb * b - cTb_true * truth;
    for (int u = 0; u < 3; ++u) {
      out.normalised.push_back(error[u] / std::sqrt(cov_c(u, u)));
      sigmas.push_back(1e3 * std::sqrt(cov_c(u, u)));
    }
    out.largest_mm = std::max(out.largest_mm, 1e3 * error.norm());
  }
}

// The acceptance's first item at the line level: 20 hexapod campaigns, legs only.
TEST(LegIdentification, HexapodLegsOnlyBaseJointsWithinTheirSigma) {
  BaseJointErrors errors;
  std::vector<double> sigmas;
  for (unsigned seed = 0; seed < 20; ++seed) legsOnlyCampaign(500 + seed, errors, sigmas);
  std::sort(sigmas.begin(), sigmas.end());
  const double sd = test::sampleStandardDeviation(errors.normalised);
  const auto outside =
      std::count_if(errors.normalised.begin(), errors.normalised.end(), [](double e) { return std::abs(e) > 3.0; });
  RecordProperty("std_error_over_sigma", std::to_string(sd));
  std::printf(
      "legs-only hexapod: %zu base-joint coordinates, std(error/sigma) %.3f, %ld beyond 3 sigma, "
      "largest error %.3f mm, median sigma %.3f mm\n",
      errors.normalised.size(), sd, static_cast<long>(outside), errors.largest_mm, sigmas[sigmas.size() / 2]);
  EXPECT_GE(sd, 0.8);
  EXPECT_LE(sd, 1.25);
  EXPECT_LE(outside, 2);  // 360 values: 1 expected beyond 3σ
}

// Lines whose errors are 4 times what their covariances say: the χ² test rejects the fit and the
// covariance is scaled by χ²/dof (about 16), as identify() does for target poses (doc/legs.md).
TEST(LegIdentification, MisfitScalesTheCovarianceByTheResiduals) {
  constexpr std::size_t kPoses = 30;
  const datasets::Campaign c = datasets::simulateCampaign(makeRegisteredModel("gough-stewart"), 600, 0.2e-3,
                                                          0.03 * datasets::kCampaignDeg, 0, kPoses);
  const std::vector<PoseObservation> poses(c.poses.begin(), c.poses.end());
  const auto fit = [&](double noise_scale, bool scale_on_misfit) {
    const std::vector<LegObservation> legs = simulateLegs(c, 677, kPoses, noise_scale);
    const IdentificationModel model = makeLegsInitialModel(c.model.mechanism, c.model.nominal, legs);
    LegIdentificationOptions options;
    options.observations = Observations::Legs;
    options.fix = legsOnlyGauge(model);
    options.scale_on_misfit = scale_on_misfit;
    return identifyWithLegs(model, poses, legs, options);
  };
  EXPECT_EQ(fit(1.0, true).covariance_scale2, 1.0);
  const LegIdentificationResult scaled = fit(4.0, true), unscaled = fit(4.0, false);
  EXPECT_NEAR(scaled.covariance_scale2, scaled.chi2 / scaled.dof, 1e-12);
  EXPECT_GT(scaled.covariance_scale2, 16.0 * 0.8);
  EXPECT_LT(scaled.covariance_scale2, 16.0 * 1.25);
  EXPECT_EQ(unscaled.covariance_scale2, 1.0);
  for (Eigen::Index f = 0; f < scaled.covariance.rows(); ++f)
    EXPECT_NEAR(scaled.covariance(f, f) / unscaled.covariance(f, f), scaled.covariance_scale2, 1e-6 * scaled.covariance_scale2)
        << scaled.free_names[static_cast<std::size_t>(f)];
}

// Both observations against the target alone on the same poses: the free parameters' σ and the
// target's position predicted from the joints at held-out poses (doc/legs.md, "Both"). The σ ratio
// compares parameters free in both fits; where the legs release part of the target-only gauge (the
// Delta's camera position) the two fits hold different gauges, so the held-out error, which no gauge
// changes, is the ratio that counts.
struct Ratios {
  std::vector<double> sigma_vs_bundle, sigma_vs_identify, held_out_both, held_out_target;
};

double heldOutRms(const IdentificationModel& model, const datasets::Campaign& c, std::size_t first) {
  const Mechanism& m = *model.mechanism;
  const Eigen::VectorXd g = model.geometricValues(), e = model.externalValues();
  double sum = 0.0;
  int n = 0;
  for (std::size_t j = first; j < c.poses.size(); ++j) {
    const FkmResult fkm = m.forwardKinematics(g, c.poses[j].joints, m.referencePose(g));
    EXPECT_TRUE(fkm.converged) << fkm.message;
    const Eigen::Vector3d predicted = model.external.targetInCamera(e, fkm.bTe).translation();
    const Eigen::Vector3d truth = (c.bTc.inverse() * c.bTe[j] * c.mTe.inverse()).translation();
    sum += (predicted - truth).squaredNorm();
    ++n;
  }
  return std::sqrt(sum / n);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

void bothVersusTarget(const std::string& name, unsigned seed, Ratios& out) {
  constexpr int kTrain = 30, kHeldOut = 20;
  const datasets::Campaign c = datasets::simulateCampaign(makeRegisteredModel(name), seed, 0.2e-3,
                                                          0.03 * datasets::kCampaignDeg, kHeldOut, kTrain);
  const std::vector<PoseObservation> train(c.poses.begin(), c.poses.begin() + kTrain);
  const std::vector<LegObservation> legs = simulateLegs(c, seed + 91, kTrain);
  IdentificationModel model = makeInitialModel(c.model.mechanism, c.model.nominal, train, c.model.external_form);
  const GaugeAnalysis gauge = fixGauge(model, train);
  IdentificationResult target = identify(model, train);
  alignTranslatingTarget(*target.model.mechanism, target.model.external, target.model.parameters, train);
  LegIdentificationOptions options;
  options.observations = Observations::Target;
  const LegIdentificationResult bundle = identifyWithLegs(target.model, train, {}, options);
  // The legs see the base frame: the target-only gauge is released, and the gauge of both chosen by
  // the analysis of a first fit.
  options.observations = Observations::Both;
  options.release = gauge.gauge;
  LegIdentificationResult both = identifyWithLegs(target.model, train, legs, options);
  if (!both.identifiability.fullRank()) {
    options.fix = both.identifiability.unidentifiable;
    both = identifyWithLegs(target.model, train, legs, options);
  }
  ASSERT_TRUE(bundle.converged && both.converged) << name << " campaign " << seed;
  EXPECT_LT(both.chi2 / both.dof, 1.5) << name << " campaign " << seed;
  for (const std::string& n : target.free_names)
    if (static_cast<int>(both.model.parameters.index(n)) < both.model.geometricCount() && both.sigmaOf(n) > 0) {
      out.sigma_vs_bundle.push_back(both.sigmaOf(n) / bundle.sigmaOf(n));
      out.sigma_vs_identify.push_back(both.sigmaOf(n) / target.sigmaOf(n));
    }
  out.held_out_target.push_back(heldOutRms(target.model, c, kTrain));
  out.held_out_both.push_back(heldOutRms(both.model, c, kTrain));
}

class BothObservations : public ::testing::TestWithParam<std::string> {};

TEST_P(BothObservations, ReduceTheSigmaAndTheHeldOutErrorAgainstTheTargetAlone) {
  Ratios r;
  for (unsigned seed = 0; seed < 5; ++seed) bothVersusTarget(GetParam(), 700 + seed, r);
  double both = 0.0, target = 0.0;
  for (std::size_t k = 0; k < r.held_out_both.size(); ++k) {
    both += r.held_out_both[k] * r.held_out_both[k];
    target += r.held_out_target[k] * r.held_out_target[k];
  }
  const double held_out_ratio = std::sqrt(both / target);
  std::printf(
      "%s, 5 campaigns of 30 poses: median sigma ratio both/target %.3f (against identify(): %.3f), "
      "held-out target position RMS both %.3f mm, target only %.3f mm (ratio %.3f)\n",
      GetParam().c_str(), median(r.sigma_vs_bundle), median(r.sigma_vs_identify),
      1e3 * std::sqrt(both / r.held_out_both.size()), 1e3 * std::sqrt(target / r.held_out_target.size()), held_out_ratio);
  EXPECT_LT(median(r.sigma_vs_bundle), 1.0);
  EXPECT_LT(median(r.sigma_vs_identify), 1.0);
  EXPECT_LT(held_out_ratio, 1.0);
}

INSTANTIATE_TEST_SUITE_P(Legs, BothObservations, ::testing::Values("gough-stewart", "delta"));

}  // namespace
