// σ honesty of the FKM prediction (doc/mechanisms.md "fkm and ikm"): over exact-model
// campaigns, the predicted cTm of held-out poses (joints not used by the identification)
// against the noise-free truth, each position component's error divided by its predicted σ;
// std(error/σ) must be in [0.8, 1.25] (first-order propagation of the parameter covariance,
// with the mounting and, for the H4, the axis alignment's own uncertainty).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/prediction.hpp"

namespace mire::mechanism {
namespace {

struct Normalised {
  std::vector<double> position;  // error/σ per component
};

Normalised heldOutErrors(const std::string& name, int campaigns, int held_out) {
  Normalised out;
  for (int c = 0; c < campaigns; ++c) {
    const datasets::Campaign all = datasets::simulateCampaign(name, 300 + static_cast<unsigned>(c), 0.2e-3,
                                                              0.03 * datasets::kCampaignDeg, held_out);
    const std::vector<PoseObservation> train(all.poses.begin(), all.poses.end() - held_out);
    IdentificationModel model = makeInitialModel(all.model.mechanism, all.model.nominal, train, all.model.external_form);
    fixGauge(model, train);
    IdentificationResult result = identify(model, train);
    alignTranslatingTarget(*result.model.mechanism, result.model.external, result.model.parameters, train);
    const PredictionModel prediction = predictionModelFrom(name, result);
    for (std::size_t j = all.poses.size() - static_cast<std::size_t>(held_out); j < all.poses.size(); ++j) {
      const PosePrediction p = predictPose(prediction, all.poses[j].joints);
      EXPECT_TRUE(p.converged) << name << " pose " << j << ": " << p.message;
      if (!p.converged) continue;
      const Eigen::Isometry3d truth = all.bTc.inverse() * all.bTe[j] * all.mTe.inverse();
      for (int k = 0; k < 3; ++k)
        out.position.push_back((p.cTm[k] - truth.translation()[k]) / std::sqrt(p.cTm_covariance(k, k)));
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

INSTANTIATE_TEST_SUITE_P(Mechanisms, PredictionSigma, ::testing::Values("h4-12", "delta", "gough-stewart"),
                         [](const auto& info) {
                           std::string s = info.param;
                           for (char& ch : s) if (ch == '-') ch = '_';
                           return s;
                         });

}  // namespace
}  // namespace mire::mechanism
