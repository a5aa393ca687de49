// The ±1σ band of report.html's joint-residual figures (identify_report.hpp, jointResidualSigmas)
// against the spread it predicts: on simulated campaigns with known pose noise (0.2 mm / 0.03°,
// the covariance the poses carry), the residuals divided by their band σ have the spread of a
// fit's residuals, √(dof / residual count), within [0.8, 1.25].
#include <gtest/gtest.h>

#include "identify_report.hpp"
#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/pipeline/identify.hpp"

#include <cmath>
#include <cstdio>

namespace mire::app {
namespace {

void expectBandMatchesSpread(const std::string& mechanism, unsigned seed) {
  // 120 random poses (360 residuals for the Delta): the rms is then known to about ±4 % (one σ).
  const datasets::Campaign c = datasets::simulateCampaign(mechanism, seed, 0.2e-3, 0.03 * datasets::kCampaignDeg, 0, 120);
  const pipeline::Identification id = pipeline::identify(pipeline::chooseModel(mechanism, ""), c.poses, std::nullopt);
  const auto& result = id.result;
  ASSERT_TRUE(result.weighted);
  const auto sigmas = jointResidualSigmas(result);
  ASSERT_EQ(sigmas.size(), result.poses.size());
  double sum2 = 0.0;
  long count = 0;
  for (std::size_t k = 0; k < sigmas.size(); ++k)
    for (Eigen::Index j = 0; j < sigmas[k].size(); ++j) {
      ASSERT_GT(sigmas[k][j], 0.0);
      const double z = result.poses[k].residual[j] / sigmas[k][j];
      sum2 += z * z;
      ++count;
    }
  // Residuals of a fit lose one degree of freedom per free parameter.
  const double expected = std::sqrt(static_cast<double>(result.dof) / static_cast<double>(count));
  const double ratio = std::sqrt(sum2 / static_cast<double>(count)) / expected;
  std::printf("%s: %ld joint residuals, rms(residual / band sigma) %.3f, expected %.3f: ratio %.3f (chi2/dof %.3f)\n",
              mechanism.c_str(), count, std::sqrt(sum2 / static_cast<double>(count)), expected, ratio,
              result.chi2 / result.dof);
  EXPECT_GT(ratio, 0.8);
  EXPECT_LT(ratio, 1.25);
}

TEST(IdentifyReportSigma, DeltaBandMatchesTheResidualSpread) { expectBandMatchesSpread("delta", 41); }
TEST(IdentifyReportSigma, HexapodBandMatchesTheResidualSpread) { expectBandMatchesSpread("gough-stewart", 42); }

}  // namespace
}  // namespace mire::app
