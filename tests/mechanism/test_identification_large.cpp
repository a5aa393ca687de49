// Large identification problems (doc/mechanisms.md "Large problems"): above
// 20 000 residual rows identify() never stores the N×P Jacobian at the solution; it streams it
// into row compressions (RᵀR = AᵀA). Here the streamed covariance and identifiability are
// checked against the direct formulas on the whole matrices, built in the test from the public
// identificationJacobian() and the result's weights: 6 250 H4 poses = 25 000 rows.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/variants.hpp"

namespace mm = mire::mechanism;

namespace {

double relativeDifference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// (AᵀA)⁻¹ by the SVD of the whole A, as the direct path computes it.
Eigen::MatrixXd directInformationInverse(const Eigen::MatrixXd& A) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeThinV);
  const Eigen::VectorXd inv_s2 = svd.singularValues().array().square().inverse().matrix();
  return svd.matrixV() * inv_s2.asDiagonal() * svd.matrixV().transpose();
}

// (AᵀA)⁻¹, σ and the identifiability report of a large (streamed) identification against
// the direct formulas on the whole matrices: A = the used poses' W·J rows, then the priors'.
void checkAgainstDirectFormulas(const mm::IdentificationResult& result, const std::vector<mm::PoseObservation>& poses,
                                const std::vector<mm::GaussianPrior>& priors) {
  ASSERT_TRUE(result.converged);
  ASSERT_TRUE(result.weighted);
  const int n = static_cast<int>(poses.size());
  const Eigen::MatrixXd J = mm::identificationJacobian(result.model, poses);
  ASSERT_EQ(J.rows(), 4 * n);
  ASSERT_GT(J.rows(), 20000);  // the large-problem path
  const std::vector<std::string> names = result.model.parameters.freeNames();
  std::vector<Eigen::Index> used;
  for (int j = 0; j < n; ++j)
    if (result.poses[static_cast<std::size_t>(j)].used) used.push_back(j);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(
      4 * static_cast<Eigen::Index>(used.size()) + static_cast<Eigen::Index>(priors.size()), J.cols());
  for (std::size_t k = 0; k < used.size(); ++k)
    A.middleRows(4 * static_cast<Eigen::Index>(k), 4) =
        result.whitening[static_cast<std::size_t>(used[k])] * J.middleRows(4 * used[k], 4);
  for (std::size_t k = 0; k < priors.size(); ++k) {
    const auto column = std::find(names.begin(), names.end(), priors[k].name) - names.begin();
    A(4 * static_cast<Eigen::Index>(used.size()) + static_cast<Eigen::Index>(k), column) = 1.0 / priors[k].sigma;
  }

  const Eigen::MatrixXd information_inverse = directInformationInverse(A);
  EXPECT_LT(relativeDifference(result.information_inverse, information_inverse), 1e-9);
  // σ² = (AᵀA)⁻¹·scale² + the alignment term, per free parameter.
  const Eigen::MatrixXd covariance =
      information_inverse * result.covarianceScale2() + result.termCovariance(mm::CovarianceTerm::kAlignment);
  ASSERT_EQ(static_cast<Eigen::Index>(names.size()), covariance.rows());
  for (std::size_t k = 0; k < names.size(); ++k) {
    const double expected = std::sqrt(covariance(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(k)));
    EXPECT_NEAR(result.sigmaOf(names[k]), expected, 1e-9 * expected) << names[k];
  }
  // The alignment term is there (variant D estimates the axis alignment).
  EXPECT_GT(result.termCovariance(mm::CovarianceTerm::kAlignment).diagonal().maxCoeff(), 0.0);

  // Identifiability (every pose): column norms and singular values of the column-scaled J.
  const Eigen::VectorXd norms = J.colwise().norm().transpose();
  EXPECT_LT(relativeDifference(result.identifiability.column_norms, norms), 1e-9);
  const Eigen::JacobiSVD<Eigen::MatrixXd> scaled(J * norms.cwiseInverse().asDiagonal());
  EXPECT_LT(relativeDifference(result.identifiability.singular_values, scaled.singularValues()), 1e-9);
  EXPECT_EQ(result.identifiability.rank, static_cast<int>(names.size()));
}

}  // namespace

TEST(IdentificationLarge, StreamedCovarianceAndIdentifiabilityMatchTheDirectFormulas) {
  constexpr int kPoses = 6250;  // 25 000 residual rows: the large-problem path
  const mire::datasets::Campaign c =
      mire::datasets::simulateCampaign("h4-12", 9, 0.2e-3, 0.03 * mire::datasets::kCampaignDeg, 0, kPoses);
  const std::vector<mm::PoseObservation>& poses = c.poses;
  ASSERT_EQ(poses.size(), static_cast<std::size_t>(kPoses));
  const mm::IdentificationModel initial = mm::makeH4VariantModel('D', mm::H4Nominal{}, poses, {});
  const mm::IdentificationResult result = mm::identify(initial, poses);
  // Without a robust loss the flagged outliers (~p·N by chance) stay in the covariance.
  for (const mm::PoseResidual& pose : result.poses) ASSERT_TRUE(pose.used) << pose.id;
  checkAgainstDirectFormulas(result, poses, {});

  // The solve (poses in compressed chunks, pose_chunk_cost.hpp) reached the minimum of the
  // per-pose cost: the Gauss–Newton step left, (AᵀA)⁻¹·Aᵀr, is below 10⁻² σ for every parameter
  // (not 0: the weights were propagated once more after the last solve, identification.cpp
  // solveWeighted). The per-pose blocks leave the same step, 1.3·10⁻³ σ at most here.
  const Eigen::MatrixXd J = mm::identificationJacobian(result.model, poses);
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(J.cols());
  for (std::size_t j = 0; j < poses.size(); ++j) {
    const Eigen::MatrixXd& W = result.whitening[j];
    gradient += (W * J.middleRows(4 * static_cast<Eigen::Index>(j), 4)).transpose() * (W * result.poses[j].residual);
  }
  const Eigen::VectorXd step = result.information_inverse * gradient;
  const std::vector<std::string> names = result.model.parameters.freeNames();
  for (std::size_t k = 0; k < names.size(); ++k)
    EXPECT_LT(std::abs(step[static_cast<Eigen::Index>(k)]), 1e-2 * result.sigmaOf(names[k])) << names[k];
}

// The kept system under a robust loss (the outliers' rows left out) with a prior row below.
TEST(IdentificationLarge, StreamedKeptSystemWithOutliersAndAPriorMatchesTheDirectFormulas) {
  constexpr int kPoses = 6250;
  const mire::datasets::Campaign c =
      mire::datasets::simulateCampaign("h4-12", 9, 0.2e-3, 0.03 * mire::datasets::kCampaignDeg, 0, kPoses);
  const std::vector<mm::PoseObservation>& poses = c.poses;
  const mm::IdentificationModel initial = mm::makeH4VariantModel('D', mm::H4Nominal{}, poses, {});
  mm::IdentificationOptions options;
  options.loss = mm::RobustLoss::Huber;
  const std::string name = initial.parameters.freeNames().front();
  options.priors.push_back({name, initial.parameters.value(name), 1e-4});
  const mm::IdentificationResult result = mm::identify(initial, poses, options);
  ASSERT_FALSE(result.outliers.empty());  // ~p·N by chance: some rows are left out
  checkAgainstDirectFormulas(result, poses, options.priors);
}
