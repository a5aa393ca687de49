// σ honesty of the FKM prediction (doc/mechanisms.md "`mire fkm` and `mire ikm`"): over exact-model
// campaigns, the predicted cTm of held-out poses (joints not used by the identification)
// against the noise-free truth, each component's error divided by its predicted σ;
// std(error/σ) must be in [0.8, 1.25] (first-order propagation of the parameter covariance,
// with the mounting and, for the H4, the axis alignment's own uncertainty) for every
// component the model moves. The Delta's plate never turns: its predicted orientation is the
// mean measured one for every joint reading, with that mean's σ (alignTranslatingTarget).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/mechanism/translating_target.hpp"

namespace mire::mechanism {
namespace {

constexpr double kNoiseR = 0.03 * datasets::kCampaignDeg;

struct Normalised {
  std::vector<double> position;          // error/σ per component
  std::vector<double> rotation;          // rotation-vector error/σ per component
  double largest_rotation_change = 0.0;  // over the held-out poses of a campaign [rad]
  std::vector<double> rotation_sigma;    // predicted σ of each rotation-vector component [rad]
};

// The truth's rotation vector taken nearest the prediction's (same rotation).
PoseVector nearestTruth(const Eigen::Isometry3d& truth, const PoseVector& predicted) {
  PoseVector tv = toPoseVector(truth);
  if ((tv.tail<3>() - predicted.tail<3>()).norm() > 1.0 && tv.tail<3>().norm() > 1.0)
    tv.tail<3>() *= 1.0 - 2.0 * 3.14159265358979323846 / tv.tail<3>().norm();
  return tv;
}

Normalised heldOutErrors(const std::string& name, int campaigns, int held_out) {
  Normalised out;
  for (int c = 0; c < campaigns; ++c) {
    const datasets::Campaign all =
        datasets::simulateCampaign(name, 300 + static_cast<unsigned>(c), 0.2e-3, kNoiseR, held_out);
    const std::vector<PoseObservation> train(all.poses.begin(), all.poses.end() - held_out);
    IdentificationModel model = makeInitialModel(all.model.mechanism, all.model.nominal, train, all.model.external_form);
    fixGauge(model, train);
    IdentificationResult result = identify(model, train);
    const auto mean_orientation_covariance = alignTranslatingTarget(result, train);
    const PredictionModel prediction = predictionModelFrom(name, result, mean_orientation_covariance);
    PoseVector first = PoseVector::Zero();
    for (std::size_t j = all.poses.size() - static_cast<std::size_t>(held_out); j < all.poses.size(); ++j) {
      const PosePrediction p = predictPose(prediction, all.poses[j].joints);
      EXPECT_TRUE(p.converged) << name << " pose " << j << ": " << p.message;
      if (!p.converged) continue;
      if (first.isZero()) first = p.cTm;
      out.largest_rotation_change = std::max(out.largest_rotation_change, (p.cTm.tail<3>() - first.tail<3>()).norm());
      const PoseVector truth = nearestTruth(all.bTc.inverse() * all.bTe[j] * all.mTe.inverse(), p.cTm);
      for (int k = 0; k < 6; ++k) {
        const double sigma = std::sqrt(p.cTm_covariance(k, k));
        (k < 3 ? out.position : out.rotation).push_back((p.cTm[k] - truth[k]) / sigma);
        if (k >= 3) out.rotation_sigma.push_back(sigma);
      }
    }
  }
  return out;
}

double rms(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}

class PredictionSigma : public ::testing::TestWithParam<std::string> {};

TEST_P(PredictionSigma, HeldOutPositionErrorsMatchPredictedSigma) {
  const Normalised n = heldOutErrors(GetParam(), 12, 20);
  ASSERT_GT(n.position.size(), 600u);
  const double ratio = rms(n.position);
  std::printf("%s: held-out position std(error/sigma) %.3f over %zu components\n", GetParam().c_str(), ratio,
              n.position.size());
  EXPECT_GT(ratio, 0.8) << GetParam();
  EXPECT_LT(ratio, 1.25) << GetParam();
}

// The H4 turns about one axis and the hexapod in 3 DoF: the rotation is a function of the
// joints and its σ comes from the parameters' covariance.
TEST_P(PredictionSigma, HeldOutRotationErrorsMatchPredictedSigma) {
  if (GetParam() == "delta") GTEST_SKIP() << "the Delta's plate does not turn: see DeltaOrientation below";
  const Normalised n = heldOutErrors(GetParam(), 12, 20);
  const double ratio = rms(n.rotation);
  std::printf("%s: held-out rotation-vector std(error/sigma) %.3f over %zu components\n", GetParam().c_str(), ratio,
              n.rotation.size());
  EXPECT_GT(ratio, 0.8) << GetParam();
  EXPECT_LT(ratio, 1.25) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Mechanisms, PredictionSigma,
                         ::testing::Values("h4-12", "delta", "gough-stewart", "gough-stewart-gains"),
                         [](const auto& info) {
                           std::string s = info.param;
                           for (char& ch : s)
                             if (ch == '-') ch = '_';
                           return s;
                         });

// The Delta cannot move its plate's orientation: the predicted cRm is the same for every joint
// reading (the mean measured orientation), its σ is that mean's, σ_r/√N per rotation-vector
// component (N = 27 identification poses), not the camera rotation's σ (12× larger before);
// and the error against the truth matches it (40 campaigns: one independent error per
// campaign and component).
TEST(PredictionSigmaDelta, DeltaOrientationIsTheMeanMeasuredOneWithItsSigma) {
  const Normalised n = heldOutErrors("delta", 40, 5);
  EXPECT_LT(n.largest_rotation_change, 1e-12);
  const double expected = kNoiseR / std::sqrt(27.0);
  for (double sigma : n.rotation_sigma) EXPECT_NEAR(sigma / expected, 1.0, 0.05);
  const double ratio = rms(n.rotation);
  std::printf("delta: rotation-vector std(error/sigma) %.3f over %zu components (sigma %.5f deg)\n", ratio,
              n.rotation.size(), n.rotation_sigma.front() / datasets::kCampaignDeg);
  EXPECT_GT(ratio, 0.8);
  EXPECT_LT(ratio, 1.25);
}

}  // namespace
}  // namespace mire::mechanism
