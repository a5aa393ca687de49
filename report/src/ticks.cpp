// Axis ticks (see ticks.hpp).
#include "mire/report/ticks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace mire::report {

std::string tickLabel(double value, double step) {
  const int decimals = std::clamp(static_cast<int>(-std::floor(std::log10(step) + 1e-9)), 0, 12);
  if (std::abs(value) < step * 1e-6) value = 0.0;
  char buffer[48];
  const double magnitude = std::max(std::abs(value), step);
  if (magnitude >= 1e6 || magnitude < 1e-4)
    std::snprintf(buffer, sizeof buffer, "%.3g", value);
  else
    std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

TickSet linearTicks(double low, double high, int max_count) {
  if (!std::isfinite(low) || !std::isfinite(high)) low = 0.0, high = 1.0;
  if (low > high) std::swap(low, high);
  if (high - low < 1e-300 + 1e-12 * std::max(std::abs(low), std::abs(high))) {
    const double pad = low == 0.0 ? 1.0 : std::abs(low) * 0.1;
    low -= pad;
    high += pad;
  }
  const double raw = (high - low) / std::max(1, max_count - 1);
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  double step = 10.0 * decade;
  for (const double m : {1.0, 2.0, 5.0})
    if (m * decade >= raw * (1.0 - 1e-9)) {
      step = m * decade;
      break;
    }
  TickSet set;
  const long first = static_cast<long>(std::floor(low / step + 1e-9));
  const long last = static_cast<long>(std::ceil(high / step - 1e-9));
  set.low = static_cast<double>(first) * step;
  set.high = static_cast<double>(last) * step;
  for (long k = first; k <= last; ++k) {
    const double value = static_cast<double>(k) * step;
    set.ticks.push_back({value, tickLabel(value, step), "", true});
  }
  return set;
}

namespace {

std::string exponentText(int k) {
  // U+2212 minus: the typographic sign of a superscript exponent.
  return k < 0 ? "\xE2\x88\x92" + std::to_string(-k) : std::to_string(k);
}

}  // namespace

TickSet logTicks(double low, double high) {
  if (!(low > 0.0) || !(high > 0.0) || !std::isfinite(low) || !std::isfinite(high))
    throw std::invalid_argument("a log axis needs a positive, finite range");
  if (low > high) std::swap(low, high);
  int first = static_cast<int>(std::floor(std::log10(low) + 1e-9));
  int last = static_cast<int>(std::ceil(std::log10(high) - 1e-9));
  if (last <= first) last = first + 1;
  const bool few = last - first < 2;
  TickSet set;
  set.low = std::pow(10.0, first);
  set.high = std::pow(10.0, last);
  for (int k = first; k <= last; ++k) {
    const double decade = std::pow(10.0, k);
    set.ticks.push_back({decade, "10", exponentText(k), true});
    if (k == last) break;
    for (int m = 2; m <= 9; ++m) {
      const double value = m * decade;
      const bool labelled = few && (m == 2 || m == 5);
      set.ticks.push_back({value, labelled ? tickLabel(value, decade) : "", "", labelled});
    }
  }
  return set;
}

}  // namespace mire::report
