// σ honesty of the controller fit's expected residual (controller_fit.hpp, doc/accuracy.md
// "Controller model"): over simulated campaigns of a Delta whose legs differ, identified with the
// per-leg model, the `delta` controller fitted to the identified robot is run on the TRUE robot;
// its frame-free RMS position error against the expected one, in units of the stated σ, must
// spread as a standard normal: std in [0.8, 1.25].
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <vector>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/controller_fit.hpp"
#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/mechanism/translating_target.hpp"

namespace mire::mechanism {
namespace {

std::vector<Eigen::VectorXd> workspaceGrid(const datasets::Campaign& c, const Eigen::Vector3d& half_box) {
  const Eigen::VectorXd ref = c.model.mechanism->referencePose(c.truth.values());
  std::vector<Eigen::VectorXd> grid;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 3; ++k) {
        Eigen::VectorXd pose = ref;
        pose.head<3>() += half_box.cwiseProduct(Eigen::Vector3d(i / 2.0 - 1.0, j / 2.0 - 1.0, k - 1.0));
        grid.push_back(pose);
      }
  return grid;
}

// The TRUE robot driven by the fitted controller over the grid: frame-free RMS position error.
double trueResidual(const datasets::Campaign& c, const Mechanism& controller, const ControllerFit& fit,
                    const std::vector<Eigen::VectorXd>& grid) {
  Eigen::Matrix3Xd attained(3, static_cast<Eigen::Index>(grid.size())), wanted(3, attained.cols());
  for (std::size_t j = 0; j < grid.size(); ++j) {
    const Eigen::Isometry3d T = controller.poseToTransform(grid[j]);
    const IkmResult q = controller.inverseKinematics(
        fit.parameters.values(), controller.poseToTransform(controllerCommand(controller, fit.frame, T)));
    EXPECT_TRUE(q.reachable());
    const FkmResult f = c.model.mechanism->forwardKinematics(c.truth.values(), q.joints, grid[j]);
    EXPECT_TRUE(f.converged);
    attained.col(static_cast<Eigen::Index>(j)) = f.bTe.translation();
    wanted.col(static_cast<Eigen::Index>(j)) = T.translation();
  }
  const Eigen::Isometry3d align(Eigen::umeyama(attained, wanted, false));
  return std::sqrt(((align * attained) - wanted).colwise().squaredNorm().mean());
}

TEST(ControllerResidualSigma, DeltaControllerOfAPerLegIdentification) {
  const RegisteredModel controller = makeRegisteredModel("delta");
  std::vector<double> z;
  double sum_expected = 0.0, sum_sigma = 0.0;
  constexpr int kCampaigns = 30;
  for (int s = 0; s < kCampaigns; ++s) {
    const datasets::Campaign c = datasets::simulateCampaign("delta-legs", 700 + static_cast<unsigned>(s), 0.2e-3,
                                                            0.03 * datasets::kCampaignDeg, 54);
    IdentificationModel model = makeInitialModel(c.model.mechanism, c.model.nominal, c.poses, c.model.external_form);
    fixGauge(model, c.poses);
    IdentificationResult result = identify(model, c.poses);
    const auto orientation = alignTranslatingTarget(result, c.poses);
    const PredictionModel identified = predictionModelFrom("delta-legs", result, orientation);
    const std::vector<Eigen::VectorXd> grid = workspaceGrid(c, Eigen::Vector3d(0.1, 0.1, 0.05));
    const ControllerFit fit = fitControllerModel(identified, controller, grid);
    ASSERT_TRUE(fit.converged);
    ASSERT_GT(fit.draws, 90);
    const double truth = trueResidual(c, *controller.mechanism, fit, grid);
    z.push_back((truth - fit.expected_rms_position_error) / fit.sigma_rms_position_error);
    sum_expected += fit.expected_rms_position_error;
    sum_sigma += fit.sigma_rms_position_error;
  }
  const Eigen::Map<const Eigen::VectorXd> v(z.data(), static_cast<Eigen::Index>(z.size()));
  const double mean = v.mean();
  const double spread = std::sqrt((v.array() - mean).square().sum() / static_cast<double>(v.size() - 1));
  std::printf(
      "delta controller of delta-legs, %d campaigns of 81 poses: mean expected RMS %.4f mm, mean sigma %.4f mm; "
      "(true - expected)/sigma: mean %.3f, std %.3f\n",
      kCampaigns, 1e3 * sum_expected / kCampaigns, 1e3 * sum_sigma / kCampaigns, mean, spread);
  EXPECT_GT(spread, 0.8);
  EXPECT_LT(spread, 1.25);
  EXPECT_LT(std::abs(mean), 3.0 / std::sqrt(static_cast<double>(kCampaigns)) + 0.2);
}

}  // namespace
}  // namespace mire::mechanism
