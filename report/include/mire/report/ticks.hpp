#pragma once
// Axis ticks: "nice" linear steps (1, 2, 5 × 10^k) and whole decades on a log axis.
#include <string>
#include <vector>

namespace mire::report {

struct Tick {
  double value = 0.0;
  std::string label;     // linear: "0.25"; log: the exponent's base "10" (see exponent)
  std::string exponent;  // log axes: "−3" for 10⁻³, empty on linear axes
  bool major = true;     // log axes: false for the unlabelled 2…9 between decades
};

struct TickSet {
  double low = 0.0, high = 1.0;  // the axis range, widened to the outer ticks
  std::vector<Tick> ticks;
};

// At most about `max_count` labelled ticks at a 1-2-5 step covering [low, high]; the range is
// widened to the first and last tick. low == high gets a range around the value.
TickSet linearTicks(double low, double high, int max_count = 6);
// Decades covering [low, high] (both > 0; throws std::invalid_argument otherwise), minor ticks
// at 2…9; with fewer than two decades, 2 and 5 are labelled as well (as plain numbers).
TickSet logTicks(double low, double high);
// The value with the decimals the step needs ("0.05" for step 0.05, "-0" never).
std::string tickLabel(double value, double step);

}  // namespace mire::report
