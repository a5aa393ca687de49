// Axis ticks: 1-2-5 steps covering the data, labels with the step's decimals, whole decades.
#include "mire/report/ticks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace {

using namespace mire::report;

TEST(Ticks, LinearStepsAreNiceAndCoverTheData) {
  const TickSet set = linearTicks(0.013, 0.93, 6);
  EXPECT_DOUBLE_EQ(set.low, 0.0);
  EXPECT_NEAR(set.high, 1.0, 1e-12);
  ASSERT_EQ(set.ticks.size(), 6u);
  EXPECT_EQ(set.ticks[1].label, "0.2");
  EXPECT_EQ(set.ticks[5].label, "1.0");
  const TickSet residual = linearTicks(-0.0374, 0.0374, 7);  // symmetric about zero
  EXPECT_NEAR(residual.low, -residual.high, 1e-15);
  bool zero = false;
  for (const auto& t : residual.ticks) zero = zero || t.label == "0.00" || t.label == "0.000";
  EXPECT_TRUE(zero) << "a symmetric range has a labelled zero";
  for (const auto& t : residual.ticks) EXPECT_EQ(t.label.find("-0.00 "), std::string::npos);
}

TEST(Ticks, StepIsOneTwoOrFiveTimesAPowerOfTen) {
  for (const double span : {0.7, 3.3, 17.0, 420.0, 9e-5}) {
    const TickSet set = linearTicks(0.0, span, 6);
    const double step = set.ticks[1].value - set.ticks[0].value;
    const double mantissa = step / std::pow(10.0, std::floor(std::log10(step) + 1e-9));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-6 || std::abs(mantissa - 2) < 1e-6 || std::abs(mantissa - 5) < 1e-6)
        << span << ": step " << step;
    EXPECT_LE(set.ticks.size(), 7u);
    EXPECT_GE(set.high, span);
  }
}

TEST(Ticks, LogAxisHasWholeDecadesAndMinorTicks) {
  const TickSet set = logTicks(3e-4, 2.0);
  EXPECT_NEAR(set.low, 1e-4, 1e-18);
  EXPECT_NEAR(set.high, 10.0, 1e-12);
  int majors = 0;
  for (const auto& t : set.ticks)
    if (t.major) {
      ++majors;
      EXPECT_EQ(t.label, "10");
    }
  EXPECT_EQ(majors, 6);  // 10^-4 … 10^1
  EXPECT_EQ(set.ticks.front().exponent,
            "\xE2\x88\x92"
            "4");  // typographic minus
  EXPECT_EQ(set.ticks.size(), 6u + 5u * 8u);
  EXPECT_THROW(logTicks(0.0, 1.0), std::invalid_argument);
}

TEST(Ticks, NarrowLogAxisLabelsTwoAndFive) {
  const TickSet set = logTicks(0.012, 0.08);
  std::vector<std::string> labels;
  for (const auto& t : set.ticks)
    if (!t.label.empty() && t.exponent.empty()) labels.push_back(t.label);
  EXPECT_EQ(labels, (std::vector<std::string>{"0.02", "0.05"}));
}

}  // namespace
