// analyzeJacobian on matrices with known structure.
#include <gtest/gtest.h>

#include <random>

#include "mire/mechanism/identifiability.hpp"

namespace mire::mechanism {
namespace {

TEST(Identifiability, NamesAnExactCombination) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n;
  Eigen::MatrixXd J(40, 4);
  for (Eigen::Index i = 0; i < J.size(); ++i) J.data()[i] = n(rng);
  J.col(3) = 2.0 * J.col(0) - 0.5 * J.col(2);  // c = 2a − 0.5b: δ(a, b, c) = (2, −0.5, −1) is null
  const IdentifiabilityReport r = analyzeJacobian(J, {"a", "b", "c", "d"});
  EXPECT_EQ(r.rank, 3);
  EXPECT_FALSE(r.fullRank());
  ASSERT_EQ(r.combinations.size(), 1u);
  std::map<std::string, double> d(r.combinations[0].direction.begin(), r.combinations[0].direction.end());
  EXPECT_EQ(d.count("b"), 0u);
  // Null direction ∝ (2, 0, −0.5, −1) on (a, b, c, d).
  EXPECT_NEAR(d["a"] / d["d"], -2.0, 1e-9);
  EXPECT_NEAR(d["c"] / d["d"], 0.5, 1e-9);
  EXPECT_GT(r.condition_number, 1e12);
  EXPECT_GT(r.condition_number_identifiable, 1.0);
  EXPECT_FALSE(r.text().empty());
}

// Two equivalent parameters (the same column up to scale): the priority names which one is held.
TEST(Identifiability, PivotPriorityChoosesWhichEquivalentParameterIsHeld) {
  std::mt19937 rng(5);
  std::normal_distribution<double> n;
  Eigen::MatrixXd J(30, 3);
  for (Eigen::Index i = 0; i < J.size(); ++i) J.data()[i] = n(rng);
  J.col(2) = -3.0 * J.col(0);  // "mount" ≡ "geo"
  IdentifiabilityOptions options;
  options.pivot_priority = {1.0, 1.0, 0.5};
  EXPECT_EQ(analyzeJacobian(J, {"geo", "other", "mount"}, options).unidentifiable, std::vector<std::string>{"mount"});
  options.pivot_priority = {0.5, 1.0, 1.0};
  EXPECT_EQ(analyzeJacobian(J, {"geo", "other", "mount"}, options).unidentifiable, std::vector<std::string>{"geo"});
}

// Two equivalent parameters whose columns differ by rounding only (an arm turned about its axis
// and the joint offset): the later one in parameter order is held, whichever way the noise goes.
TEST(Identifiability, RoundingDoesNotChooseWhichEquivalentParameterIsHeld) {
  std::mt19937 rng(6);
  std::normal_distribution<double> n;
  Eigen::MatrixXd J(30, 3);
  for (Eigen::Index i = 0; i < J.size(); ++i) J.data()[i] = n(rng);
  for (const double sign : {1.0, -1.0})
    for (int draw = 0; draw < 5; ++draw) {
      Eigen::MatrixXd K = J;
      for (Eigen::Index i = 0; i < K.rows(); ++i) K(i, 2) = K(i, 0) * (1.0 + sign * 1e-13 * std::abs(n(rng)));
      EXPECT_EQ(analyzeJacobian(K, {"a", "b", "c"}).unidentifiable, std::vector<std::string>{"c"}) << sign << draw;
      K.col(0).swap(K.col(2));
      EXPECT_EQ(analyzeJacobian(K, {"a", "b", "c"}).unidentifiable, std::vector<std::string>{"c"}) << sign << draw;
    }
}

TEST(Identifiability, ScalingMakesUnitsIrrelevant) {
  std::mt19937 rng(4);
  std::normal_distribution<double> n;
  Eigen::MatrixXd J(30, 3);
  for (Eigen::Index i = 0; i < J.size(); ++i) J.data()[i] = n(rng);
  Eigen::MatrixXd K = J;
  K.col(1) *= 1e4;  // same parameter in other units
  const auto a = analyzeJacobian(J, {"x", "y", "z"});
  const auto b = analyzeJacobian(K, {"x", "y", "z"});
  EXPECT_NEAR(a.condition_number, b.condition_number, 1e-9 * a.condition_number);
  EXPECT_GT(b.condition_number_unscaled, 100.0 * a.condition_number_unscaled);
  EXPECT_TRUE(a.fullRank());
}

// Column scaling makes every unit direction's singular value 1 unless columns mix: two
// correlated columns (a, b) and an independent one (c) weighted 10x give the directions a+b
// (largest), c, then a-b; each named by its dominant parameter.
TEST(Identifiability, EachSingularValueIsNamedByItsDominantParameter) {
  Eigen::MatrixXd J(4, 3);
  J << 1.0, 0.9, 0.0, 0.0, 0.1, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 10.0;
  const auto report = analyzeJacobian(J, {"a", "b", "c"});
  ASSERT_EQ(report.dominant_parameters.size(), 3u);
  EXPECT_EQ(report.dominant_parameters[1], "c");
  EXPECT_NE(report.dominant_parameters[0], "c");
  EXPECT_NE(report.dominant_parameters[2], "c");
}

TEST(Identifiability, BadInput) {
  Eigen::MatrixXd J = Eigen::MatrixXd::Identity(3, 3);
  EXPECT_THROW(analyzeJacobian(J, {"a", "b"}), std::invalid_argument);
  J(1, 1) = std::nan("");
  EXPECT_THROW(analyzeJacobian(J, {"a", "b", "c"}), std::invalid_argument);
}

}  // namespace
}  // namespace mire::mechanism
