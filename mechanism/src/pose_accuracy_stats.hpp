#pragma once
// The ISO 9283 statistics on deviations from the commanded pose (doc/accuracy.md), shared by the
// figures and their noise-only draws (pose_accuracy.cpp), and the noise draws themselves.
#include <Eigen/Core>

#include <random>
#include <vector>

#include "mire/mechanism/pose_accuracy.hpp"

namespace mire::mechanism::detail {

// §7.2.1 and §7.2.2 on the deviations attained − commanded of one position's cycles.
struct PoseStatistics {
  Eigen::Vector3d ap_xyz = Eigen::Vector3d::Zero();
  double ap_p = 0.0;
  Eigen::Vector3d ap_abc = Eigen::Vector3d::Zero();
  double l_mean = 0.0, s_l = 0.0, rp_l = 0.0;
  Eigen::Vector3d s_abc = Eigen::Vector3d::Zero();
};
PoseStatistics poseStatistics(const std::vector<IsoPose>& deviations);

// Mean and sample standard deviation (n − 1), n ≥ 2.
struct MeanSpread {
  double mean = 0.0, s = 0.0;
};
MeanSpread meanSpread(const std::vector<double>& values);

// Draws of N(0, Σ) for a fixed list of covariances (positive semi-definite; a zero one draws 0).
class NoiseDraws {
 public:
  NoiseDraws(const std::vector<IsoPoseCovariance>& covariances, unsigned seed);
  std::vector<IsoPose> draw();  // one deviation per covariance

 private:
  std::vector<IsoPoseCovariance> roots_;  // Σ = A·Aᵀ
  std::mt19937 rng_;
  std::normal_distribution<double> normal_;
};

// Mean and 95th percentile of sampled values.
NoiseOnly summarize(std::vector<double> values);

}  // namespace mire::mechanism::detail
