#pragma once
// Order statistics and distribution quantiles shared by the modules (one home instead of a
// copy per file).
#include <vector>

namespace mire::support {

// Median: the middle value, or the mean of the two middle values for an even count; 0 for
// no values.
double median(std::vector<double> values);

// The upper median: the value of rank n/2 (0-based) in sorted order, the middle one for an
// odd count, the upper of the two middle ones for an even count; 0 for no values.
double upperMedian(std::vector<double> values);

// Scale from the median absolute deviation to σ for a normal distribution.
constexpr double kMadToSigma = 1.4826;

// Robust σ: kMadToSigma × the median absolute deviation from the median.
double madSigma(const std::vector<double>& values);

// The χ² quantile with k degrees of freedom exceeded with probability p (the quantile of the
// lower tail with `lower`), by the Wilson–Hilferty approximation:
// k·(1 − 2/(9k) + z_p·√(2/(9k)))³, z_p the standard normal upper quantile.
double chi2Quantile(int k, double p, bool lower = false);

}  // namespace mire::support
