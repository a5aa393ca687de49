#include "plot.hpp"

#include "mire/support/atomic_file.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace mire::app {
namespace {

constexpr int kLeft = 90, kRight = 30, kTop = 50, kBottom = 80;
const cv::Scalar kInk(40, 40, 40);
const cv::Scalar kGrid(220, 220, 220);

std::string tickLabel(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

double niceMaximum(const std::vector<Series>& series) {
  double maximum = 0.0;
  for (const auto& s : series)
    for (const double v : s.values)
      if (std::isfinite(v)) maximum = std::max(maximum, v);
  if (maximum <= 0.0) return 1.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(maximum)));
  for (const double step : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (step * magnitude >= maximum) return step * magnitude;
  return 10.0 * magnitude;
}

// Canvas with title, y grid and labels; returns the y → pixel mapping's maximum.
cv::Mat canvas(const std::string& title, const std::string& y_label, double y_max, int width, int height) {
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  cv::putText(image, title, {kLeft, 30}, cv::FONT_HERSHEY_SIMPLEX, 0.65, kInk, 1, cv::LINE_AA);
  const int plot_height = height - kTop - kBottom;
  for (int tick = 0; tick <= 5; ++tick) {
    const int y = kTop + plot_height - tick * plot_height / 5;
    cv::line(image, {kLeft, y}, {width - kRight, y}, kGrid, 1);
    cv::putText(image, tickLabel(y_max * tick / 5.0), {8, y + 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, kInk, 1, cv::LINE_AA);
  }
  cv::putText(image, y_label, {8, kTop - 12}, cv::FONT_HERSHEY_SIMPLEX, 0.45, kInk, 1, cv::LINE_AA);
  cv::line(image, {kLeft, kTop}, {kLeft, height - kBottom}, kInk, 1);
  cv::line(image, {kLeft, height - kBottom}, {width - kRight, height - kBottom}, kInk, 1);
  return image;
}

void legend(cv::Mat& image, const std::vector<Series>& series) {
  int x = kLeft;
  const int y = image.rows - 20;
  for (const auto& s : series) {
    cv::rectangle(image, {x, y - 10}, {x + 14, y + 2}, s.colour, cv::FILLED);
    cv::putText(image, s.label, {x + 20, y}, cv::FONT_HERSHEY_SIMPLEX, 0.45, kInk, 1, cv::LINE_AA);
    x += 30 + static_cast<int>(s.label.size()) * 9;
  }
}

}  // namespace

cv::Scalar seriesColour(int index) {
  static const cv::Scalar kColours[] = {{180, 119, 31}, {14, 127, 255}, {44, 160, 44},
                                        {40, 39, 214},  {189, 103, 148}, {75, 86, 140}};
  return kColours[index % 6];
}

cv::Mat barChart(const std::string& title, const std::string& y_label, const std::vector<std::string>& categories,
                 const std::vector<Series>& series, int width, int height) {
  const double y_max = niceMaximum(series);
  cv::Mat image = canvas(title, y_label, y_max, width, height);
  const int plot_width = width - kLeft - kRight;
  const int plot_height = height - kTop - kBottom;
  const int groups = std::max<int>(1, static_cast<int>(categories.size()));
  const double group_width = static_cast<double>(plot_width) / groups;
  const double bar_width = 0.8 * group_width / std::max<std::size_t>(1, series.size());
  for (int g = 0; g < groups; ++g) {
    const double group_left = kLeft + g * group_width + 0.1 * group_width;
    for (std::size_t s = 0; s < series.size(); ++s) {
      if (static_cast<std::size_t>(g) >= series[s].values.size() || !std::isfinite(series[s].values[g])) continue;
      const int bar_height = static_cast<int>(std::lround(series[s].values[g] / y_max * plot_height));
      const int x0 = static_cast<int>(group_left + s * bar_width);
      cv::rectangle(image, {x0, kTop + plot_height - bar_height},
                    {static_cast<int>(x0 + bar_width) - 2, kTop + plot_height}, series[s].colour, cv::FILLED);
    }
    if (static_cast<std::size_t>(g) < categories.size())
      cv::putText(image, categories[g], {static_cast<int>(group_left + 0.3 * group_width), height - kBottom + 22},
                  cv::FONT_HERSHEY_SIMPLEX, 0.5, kInk, 1, cv::LINE_AA);
  }
  legend(image, series);
  return image;
}

cv::Mat lineChart(const std::string& title, const std::string& x_label, const std::string& y_label,
                  const std::vector<double>& x, const std::vector<Series>& series, int width, int height) {
  const double y_max = niceMaximum(series);
  cv::Mat image = canvas(title, y_label, y_max, width, height);
  if (x.empty()) return image;
  const double x_min = *std::min_element(x.begin(), x.end());
  const double x_max = std::max(*std::max_element(x.begin(), x.end()), x_min + 1e-12);
  const int plot_width = width - kLeft - kRight;
  const int plot_height = height - kTop - kBottom;
  const auto to_pixel = [&](double xv, double yv) {
    return cv::Point(kLeft + static_cast<int>((xv - x_min) / (x_max - x_min) * plot_width),
                     kTop + plot_height - static_cast<int>(yv / y_max * plot_height));
  };
  for (const double xv : x)
    cv::putText(image, tickLabel(xv), to_pixel(xv, 0) + cv::Point(-8, 20), cv::FONT_HERSHEY_SIMPLEX, 0.45, kInk, 1,
                cv::LINE_AA);
  cv::putText(image, x_label, {width / 2 - 40, height - kBottom + 45}, cv::FONT_HERSHEY_SIMPLEX, 0.5, kInk, 1,
              cv::LINE_AA);
  for (const auto& s : series) {
    for (std::size_t i = 0; i < x.size() && i < s.values.size(); ++i) {
      if (!std::isfinite(s.values[i])) continue;
      const cv::Point p = to_pixel(x[i], s.values[i]);
      cv::circle(image, p, 4, s.colour, cv::FILLED, cv::LINE_AA);
      if (i > 0 && std::isfinite(s.values[i - 1])) cv::line(image, to_pixel(x[i - 1], s.values[i - 1]), p, s.colour, 2, cv::LINE_AA);
    }
  }
  legend(image, series);
  return image;
}

void writePng(const std::filesystem::path& path, const cv::Mat& image) {
  support::writeAtomically(path, [&](const std::filesystem::path& temporary) { return cv::imwrite(temporary.string(), image); });
}

}  // namespace mire::app
