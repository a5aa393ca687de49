// The report charts: log y axis, ±σ error bars, title and y-axis label laid out apart (doc/plots.md).
#include "plot.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

namespace mire::app {
namespace {

const cv::Scalar kColour(180, 119, 31);

bool isColour(const cv::Vec3b& p, const cv::Scalar& c) { return p[0] == c[0] && p[1] == c[1] && p[2] == c[2]; }

// Tallest run of the colour in any column of [x0, x1) of the plot area (above the x axis, so not the legend).
int tallestColumn(const cv::Mat& image, int x0, int x1, const cv::Scalar& colour) {
  int best = 0;
  for (int x = x0; x < x1; ++x) {
    int count = 0;
    for (int y = 0; y <= image.rows - 80; ++y) count += isColour(image.at<cv::Vec3b>(y, x), colour) ? 1 : 0;
    best = std::max(best, count);
  }
  return best;
}

std::vector<int> barHeights(const cv::Mat& image, int bars) {
  std::vector<int> heights;
  const int left = 90, width = image.cols - 90 - 30;
  for (int b = 0; b < bars; ++b)
    heights.push_back(tallestColumn(image, left + b * width / bars, left + (b + 1) * width / bars, kColour));
  return heights;
}

TEST(PlotCharts, LogAxisGivesEqualStepsPerDecadeAndLinearStaysTheDefault) {
  const Series s{"values", {0.02, 0.2, 2.0}, kColour};
  const auto log_heights = barHeights(barChart("t", "y", {"a", "b", "c"}, {s}, 960, 540, YScale::log10), 3);
  ASSERT_GT(log_heights[0], 0);
  EXPECT_NEAR(log_heights[1] - log_heights[0], log_heights[2] - log_heights[1], 2);
  const auto linear = barHeights(barChart("t", "y", {"a", "b", "c"}, {s}), 3);  // default arguments: linear
  EXPECT_NEAR(static_cast<double>(linear[1]) / linear[2], 0.1, 0.01);
  EXPECT_NEAR(linear[0], 0.01 * 390 + 1, 1);  // 1 % of the 390 px plot height (inclusive rectangle)
}

TEST(PlotCharts, SigmaDrawsAnErrorBarOfTheRightLength) {
  Series plain{"v", {1.0, 1.0, 1.0}, kColour};
  Series with_sigma = plain;
  with_sigma.sigma = {0.0, 0.5, 0.0};
  const std::vector<double> x{0.0, 1.0, 2.0};
  const cv::Mat without = lineChart("t", "x", "y", x, {plain});
  const cv::Mat with = lineChart("t", "x", "y", x, {with_sigma});
  // y axis 0..2 (the nice maximum above 1.5) over 390 px: ±0.5 spans 195 px (+1 inclusive) at the middle point.
  const int middle = tallestColumn(with, 440, 540, kColour), plain_middle = tallestColumn(without, 440, 540, kColour);
  EXPECT_NEAR(middle, 196, 3);
  EXPECT_LT(plain_middle, 15);
}

// Rows holding dark ink in the header band (above the top tick label, which sits on the plot's top edge).
std::set<int> inkRows(const cv::Mat& image) {
  std::set<int> rows;
  for (int y = 0; y < 63; ++y)
    for (int x = 0; x < image.cols; ++x)
      if (image.at<cv::Vec3b>(y, x)[0] < 128) rows.insert(y);
  return rows;
}

TEST(PlotCharts, TitleAndYLabelNeverShareARowWhateverTheirLength) {
  const std::string long_text(200, 'W');
  const Series s{"v", {1.0}, kColour};
  const auto title_rows = inkRows(barChart(long_text + "|gy", "", {"a"}, {s}));
  const auto label_rows = inkRows(barChart("", long_text + "|gy (mm)", {"a"}, {s}, 960, 540, YScale::log10));
  ASSERT_FALSE(title_rows.empty());
  ASSERT_FALSE(label_rows.empty());
  for (const int row : title_rows) EXPECT_EQ(label_rows.count(row), 0u) << "row " << row;
}

}  // namespace
}  // namespace mire::app
