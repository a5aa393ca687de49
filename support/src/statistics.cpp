#include "mire/support/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace mire::support {

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  if (values.size() % 2 == 1) return *middle;
  const double upper = *middle;
  const double lower = *std::max_element(values.begin(), middle);
  return 0.5 * (lower + upper);
}

double upperMedian(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), middle, values.end());
  return *middle;
}

double madSigma(const std::vector<double>& values) {
  const double centre = median(values);
  std::vector<double> deviations;
  deviations.reserve(values.size());
  for (const double v : values) deviations.push_back(std::abs(v - centre));
  return kMadToSigma * median(deviations);
}

namespace {

// Upper quantile of the standard normal distribution, by bisection on erfc.
double normalUpperQuantile(double p) {
  double lo = -10.0, hi = 10.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (0.5 * std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

}  // namespace

double chi2Quantile(int k, double p, bool lower) {
  const double z = normalUpperQuantile(p) * (lower ? -1.0 : 1.0);
  const double a = 2.0 / (9.0 * std::max(1, k));
  return std::max(0.0, k * std::pow(1.0 - a + z * std::sqrt(a), 3.0));
}

}  // namespace mire::support
