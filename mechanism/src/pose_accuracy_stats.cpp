// ISO 9283 statistics and the noise draws (pose_accuracy_stats.hpp).
#include "pose_accuracy_stats.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace mire::mechanism::detail {

MeanSpread meanSpread(const std::vector<double>& values) {
  MeanSpread out;
  const double n = static_cast<double>(values.size());
  out.mean = std::accumulate(values.begin(), values.end(), 0.0) / n;
  double sum_sq = 0.0;
  for (double v : values) sum_sq += (v - out.mean) * (v - out.mean);
  out.s = values.size() > 1 ? std::sqrt(sum_sq / (n - 1.0)) : 0.0;
  return out;
}

PoseStatistics poseStatistics(const std::vector<IsoPose>& deviations) {
  PoseStatistics out;
  IsoPose mean = IsoPose::Zero();
  for (const IsoPose& d : deviations) mean += d;
  mean /= static_cast<double>(deviations.size());
  out.ap_xyz = mean.head<3>();
  out.ap_p = out.ap_xyz.norm();  // §7.2.1: distance of the barycentre to the commanded position
  out.ap_abc = mean.tail<3>();
  std::vector<double> l;
  std::vector<std::vector<double>> angles(3);
  for (const IsoPose& d : deviations) {
    l.push_back((d.head<3>() - mean.head<3>()).norm());  // §7.2.2: l_j
    for (int k = 0; k < 3; ++k) angles[static_cast<std::size_t>(k)].push_back(d[3 + k]);
  }
  const MeanSpread ls = meanSpread(l);
  out.l_mean = ls.mean;
  out.s_l = ls.s;
  out.rp_l = ls.mean + 3.0 * ls.s;
  for (int k = 0; k < 3; ++k) out.s_abc[k] = meanSpread(angles[static_cast<std::size_t>(k)]).s;
  return out;
}

NoiseDraws::NoiseDraws(const std::vector<IsoPoseCovariance>& covariances, unsigned seed) : rng_(seed) {
  for (const IsoPoseCovariance& c : covariances) {
    const Eigen::SelfAdjointEigenSolver<IsoPoseCovariance> solver(0.5 * (c + c.transpose()));
    const Eigen::Matrix<double, 6, 1> root = solver.eigenvalues().cwiseMax(0.0).cwiseSqrt();
    roots_.push_back(solver.eigenvectors() * root.asDiagonal());
  }
}

std::vector<IsoPose> NoiseDraws::draw() {
  std::vector<IsoPose> out;
  out.reserve(roots_.size());
  for (const IsoPoseCovariance& a : roots_) {
    IsoPose z;
    for (int k = 0; k < 6; ++k) z[k] = normal_(rng_);
    out.push_back(a * z);
  }
  return out;
}

NoiseOnly summarize(std::vector<double> values) {
  NoiseOnly out;
  if (values.empty()) return out;
  out.mean = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  const auto index = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(values.size()))) - 1;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(index), values.end());
  out.p95 = values[index];
  return out;
}

}  // namespace mire::mechanism::detail
