#pragma once
// Small statistics of the end-to-end σ studies (doc/studies/, the chain studies:
// benchmarks/bench_chain.cpp): samples of error/σ per
// name gathered over chains, their spread, the Mahalanobis χ² of a whole error vector, and the
// process CPU time the studies report per stage.
#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <ctime>
#include <map>
#include <string>
#include <vector>

namespace mire::bench {

inline double processCpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

// Samples per name (a parameter, a camera parameter, a pose component).
using Samples = std::map<std::string, std::vector<double>>;

inline double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (const double x : v) s += x / static_cast<double>(v.size());
  return s;
}

inline double rms(const std::vector<double>& v) {
  double sq = 0.0;
  for (const double x : v) sq += x * x;
  return v.empty() ? 0.0 : std::sqrt(sq / static_cast<double>(v.size()));
}

// Sample standard deviation (n − 1); 0 below two samples.
inline double stddev(const std::vector<double>& v) {
  if (v.size() < 2) return 0.0;
  double mean = 0.0, sq = 0.0;
  for (const double x : v) mean += x / static_cast<double>(v.size());
  for (const double x : v) sq += (x - mean) * (x - mean);
  return std::sqrt(sq / static_cast<double>(v.size() - 1));
}

inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// xᵀ Σ⁻¹ x (a Mahalanobis χ²), through the pseudo-inverse-free LDLT of Σ.
inline double mahalanobis(const Eigen::VectorXd& x, const Eigen::MatrixXd& covariance) {
  return x.dot(covariance.ldlt().solve(x));
}

}  // namespace mire::bench
