// `mire identify --observations legs|both` on a simulated hexapod campaign whose legs.csv holds the
// true leg axes perturbed by draws from their stated covariance (doc/legs.md).
#include <gtest/gtest.h>

#include <random>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/legs_csv.hpp"
#include "test_support.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;

std::vector<mechanism::LegObservation> legLines(const datasets::Campaign& c, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  const Eigen::Vector4d sigma(1e-4, 1e-4, 1e-4, 1e-4);  // rad, rad, m, m
  std::vector<mechanism::LegObservation> out;
  for (std::size_t j = 0; j < c.poses.size(); ++j) {
    const auto segments = c.model.mechanism->legSegments(c.truth.values(), c.bTe[j]);
    for (int i = 0; i < static_cast<int>(segments.size()); ++i) {
      const Eigen::Isometry3d cTb = c.bTc.inverse();
      const auto& s = segments[static_cast<std::size_t>(i)];
      const Eigen::Vector4d delta(sigma[0] * normal(rng), sigma[1] * normal(rng), sigma[2] * normal(rng),
                                  sigma[3] * normal(rng));
      const support::Line3d truth = support::Line3d::throughPoints(cTb * s.from, cTb * s.to);
      out.push_back({c.poses[j].id, i, support::perturbLine(truth, delta), sigma.cwiseAbs2().asDiagonal()});
    }
  }
  return out;
}

TEST(IdentifyLegsCli, HexapodFromLegsAloneAndFromBoth) {
  test::TempDir dir;
  const fs::path d = dir.path();
  const datasets::Campaign c =
      datasets::simulateCampaign("gough-stewart", 21, 0.2e-3, 0.03 * datasets::kCampaignDeg, 0, 30);
  datasets::writeCampaignFiles(c, d, 0, c.poses.size());
  mechanism::writeLegsCsv(d / "legs.csv", legLines(c, 5));
  const std::string files =
      " --model gough-stewart --joints " + (d / "joints.csv").string() + " --legs " + (d / "legs.csv").string();
  ASSERT_EQ(test::runMireIn(dir, "identify --observations legs" + files + " -o " + (d / "legs.yaml").string()), 0)
      << test::readText(d / "stderr.txt");
  std::string out = test::readText(d / "stdout.txt");
  EXPECT_NE(out.find("rank 36 of 36"), std::string::npos) << out;
  EXPECT_NE(test::readText(d / "legs.yaml").find("observations: \"legs\""), std::string::npos);
  ASSERT_EQ(test::runMireIn(dir, "identify --observations both --poses " + (d / "poses.csv").string() + files + " -o " +
                                     (d / "both.yaml").string()),
            0)
      << test::readText(d / "stderr.txt");
  out = test::readText(d / "stdout.txt");
  EXPECT_NE(out.find("observations both: 30 poses, 720 leg rows, 180 target rows"), std::string::npos) << out;
}

}  // namespace
}  // namespace mire::app
