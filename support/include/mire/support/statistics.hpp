#pragma once
// Order statistics shared by the modules (one home instead of a copy per file).
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

}  // namespace mire::support
