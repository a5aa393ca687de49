#pragma once
// The sample standard deviation of the tests and studies (one copy; MATLAB's std()).
#include <cmath>
#include <vector>

namespace mire::test {

// √(Σ (x − mean)² / (n − 1)), the mean as Σx / n; needs at least two values.
inline double sampleStandardDeviation(const std::vector<double>& values) {
  double mean = 0.0;
  for (const double v : values) mean += v;
  mean /= static_cast<double>(values.size());
  double sum = 0.0;
  for (const double v : values) sum += (v - mean) * (v - mean);
  return std::sqrt(sum / static_cast<double>(values.size() - 1));
}

}  // namespace mire::test
