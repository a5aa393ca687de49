#include "plot.hpp"

#include "mire/support/atomic_file.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace mire::app {
namespace {

// The title and the y-axis label each have their own line above the plot area, so they cannot overlap
// whatever their lengths; text wider than the image is scaled down to fit.
constexpr int kLeft = 90, kRight = 30, kTitleBaseline = 26, kYLabelBaseline = 56, kTop = 70, kBottom = 80;
constexpr double kTitleScale = 0.65, kTextScale = 0.45;
const cv::Scalar kInk(40, 40, 40);
const cv::Scalar kGrid(220, 220, 220);
const cv::Scalar kMinorGrid(240, 240, 240);

std::string tickLabel(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

double sigmaAt(const Series& s, std::size_t i) {
  return i < s.sigma.size() && std::isfinite(s.sigma[i]) ? std::abs(s.sigma[i]) : 0.0;
}

// The y range and the value → pixel mapping of one chart.
struct YAxis {
  YScale scale = YScale::linear;
  double low = 0.0, high = 1.0;  // linear: [0, nice maximum]; log10: [10^a, 10^b]
  int top = kTop, bottom = 0;    // pixel rows of high and low

  double fraction(double v) const {
    if (scale == YScale::log10)
      return v > 0.0 ? (std::log10(v) - std::log10(low)) / (std::log10(high) - std::log10(low)) : -1.0;
    return (v - low) / (high - low);
  }
  int pixel(double v) const {
    const double f = std::clamp(fraction(v), 0.0, 1.0);
    return bottom - static_cast<int>(std::lround(f * (bottom - top)));
  }
};

double niceMaximum(double maximum) {
  if (maximum <= 0.0) return 1.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(maximum)));
  for (const double step : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (step * magnitude >= maximum) return step * magnitude;
  return 10.0 * magnitude;
}

YAxis makeAxis(const std::vector<Series>& series, YScale scale, int height) {
  double minimum = HUGE_VAL, maximum = 0.0;
  for (const auto& s : series)
    for (std::size_t i = 0; i < s.values.size(); ++i) {
      const double v = s.values[i];
      if (!std::isfinite(v)) continue;
      maximum = std::max(maximum, v + sigmaAt(s, i));
      if (v > 0.0) minimum = std::min(minimum, v);
    }
  YAxis axis;
  axis.scale = scale;
  axis.bottom = height - kBottom;
  if (scale == YScale::linear) {
    axis.high = niceMaximum(maximum);
    return axis;
  }
  if (!std::isfinite(minimum)) minimum = maximum > 0.0 ? maximum : 1.0;
  // The smallest value stands at least a quarter decade above the axis (a bar at 0.0106 on an
  // axis from 0.01 would be invisible).
  const double low = std::floor(std::log10(minimum) - 0.25), high = std::ceil(std::log10(std::max(maximum, minimum)));
  axis.low = std::pow(10.0, low);
  axis.high = std::pow(10.0, std::max(high, low + 1.0));
  return axis;
}

void putFitted(cv::Mat& image, const std::string& text, cv::Point origin, double scale) {
  int baseline = 0;
  const int width = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline).width;
  const int room = image.cols - origin.x - 8;
  if (width > room && room > 0) scale *= static_cast<double>(room) / width;
  cv::putText(image, text, origin, cv::FONT_HERSHEY_SIMPLEX, scale, kInk, 1, cv::LINE_AA);
}

// A category label centred under its group, scaled down when wider than the group.
void putCentred(cv::Mat& image, const std::string& text, double centre_x, double room, int y) {
  double scale = 0.5;
  int baseline = 0;
  int width = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline).width;
  if (width > room - 4 && room > 8) {
    scale *= (room - 4) / width;
    width = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline).width;
  }
  cv::putText(image, text, {static_cast<int>(centre_x - width / 2.0), y}, cv::FONT_HERSHEY_SIMPLEX, scale, kInk, 1,
              cv::LINE_AA);
}

void gridLine(cv::Mat& image, int y, const cv::Scalar& colour) {
  cv::line(image, {kLeft, y}, {image.cols - kRight, y}, colour, 1);
}

void yTicks(cv::Mat& image, const YAxis& axis) {
  const auto label = [&](double v) {
    cv::putText(image, tickLabel(v), {8, axis.pixel(v) + 5}, cv::FONT_HERSHEY_SIMPLEX, kTextScale, kInk, 1, cv::LINE_AA);
  };
  if (axis.scale == YScale::linear) {
    for (int tick = 0; tick <= 5; ++tick) {
      const double v = axis.high * tick / 5.0;
      gridLine(image, axis.pixel(v), kGrid);
      label(v);
    }
    return;
  }
  for (double decade = axis.low; decade <= axis.high * 1.0001; decade *= 10.0) {
    for (int k = 2; k <= 9 && decade * k < axis.high; ++k) gridLine(image, axis.pixel(decade * k), kMinorGrid);
    gridLine(image, axis.pixel(decade), kGrid);
    label(decade);
  }
}

// Canvas with title, y-axis label (own line), y grid with labelled ticks and axes.
cv::Mat canvas(const std::string& title, const std::string& y_label, const YAxis& axis, int width, int height) {
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  putFitted(image, title, {kLeft, kTitleBaseline}, kTitleScale);
  putFitted(image, y_label + (axis.scale == YScale::log10 ? " (log scale)" : ""), {8, kYLabelBaseline}, kTextScale);
  yTicks(image, axis);
  cv::line(image, {kLeft, kTop}, {kLeft, height - kBottom}, kInk, 1);
  cv::line(image, {kLeft, height - kBottom}, {width - kRight, height - kBottom}, kInk, 1);
  return image;
}

// A vertical ±σ bar with caps at x around value v.
void errorBar(cv::Mat& image, const YAxis& axis, int x, double v, double sigma, const cv::Scalar& colour) {
  if (!(sigma > 0.0)) return;
  const int upper = axis.pixel(v + sigma), lower = axis.pixel(v - sigma);
  cv::line(image, {x, upper}, {x, lower}, colour, 1);
  cv::line(image, {x - 5, upper}, {x + 5, upper}, colour, 1);
  if (axis.fraction(v - sigma) > 0.0) cv::line(image, {x - 5, lower}, {x + 5, lower}, colour, 1);
}

void legend(cv::Mat& image, const std::vector<Series>& series) {
  int x = kLeft;
  const int y = image.rows - 20;
  for (const auto& s : series) {
    cv::rectangle(image, {x, y - 10}, {x + 14, y + 2}, s.colour, cv::FILLED);
    int baseline = 0;
    const int text = cv::getTextSize(s.label, cv::FONT_HERSHEY_SIMPLEX, kTextScale, 1, &baseline).width;
    cv::putText(image, s.label, {x + 20, y}, cv::FONT_HERSHEY_SIMPLEX, kTextScale, kInk, 1, cv::LINE_AA);
    x += 40 + text;
  }
}

bool drawable(const YAxis& axis, double v) { return std::isfinite(v) && (axis.scale == YScale::linear || v > 0.0); }

}  // namespace

cv::Scalar seriesColour(int index) {
  static const cv::Scalar kColours[] = {{180, 119, 31}, {14, 127, 255},  {44, 160, 44},
                                        {40, 39, 214},  {189, 103, 148}, {75, 86, 140}};
  return kColours[index % 6];
}

cv::Mat barChart(const std::string& title, const std::string& y_label, const std::vector<std::string>& categories,
                 const std::vector<Series>& series, int width, int height, YScale y_scale) {
  const YAxis axis = makeAxis(series, y_scale, height);
  cv::Mat image = canvas(title, y_label, axis, width, height);
  const int plot_width = width - kLeft - kRight;
  const int groups = std::max<int>(1, static_cast<int>(categories.size()));
  const double group_width = static_cast<double>(plot_width) / groups;
  const double bar_width = 0.8 * group_width / std::max<std::size_t>(1, series.size());
  for (int g = 0; g < groups; ++g) {
    const double group_left = kLeft + g * group_width + 0.1 * group_width;
    for (std::size_t s = 0; s < series.size(); ++s) {
      const auto i = static_cast<std::size_t>(g);
      if (i >= series[s].values.size() || !drawable(axis, series[s].values[i])) continue;
      const int x0 = static_cast<int>(group_left + s * bar_width);
      const int x1 = static_cast<int>(x0 + bar_width) - 2;
      cv::rectangle(image, {x0, axis.pixel(series[s].values[i])}, {x1, axis.bottom}, series[s].colour, cv::FILLED);
      errorBar(image, axis, (x0 + x1) / 2, series[s].values[i], sigmaAt(series[s], i), kInk);
    }
    if (static_cast<std::size_t>(g) < categories.size())
      putCentred(image, categories[static_cast<std::size_t>(g)], group_left + 0.4 * group_width, group_width,
                 height - kBottom + 22);
  }
  legend(image, series);
  return image;
}

cv::Mat lineChart(const std::string& title, const std::string& x_label, const std::string& y_label,
                  const std::vector<double>& x, const std::vector<Series>& series, int width, int height, YScale y_scale) {
  const YAxis axis = makeAxis(series, y_scale, height);
  cv::Mat image = canvas(title, y_label, axis, width, height);
  if (x.empty()) return image;
  const double x_min = *std::min_element(x.begin(), x.end());
  const double x_max = std::max(*std::max_element(x.begin(), x.end()), x_min + 1e-12);
  // A margin at both ends keeps the first and last points (and their error bars) off the axes.
  const int margin = (width - kLeft - kRight) / 25;
  const int plot_width = width - kLeft - kRight - 2 * margin;
  const auto to_x = [&](double xv) {
    return kLeft + margin + static_cast<int>((xv - x_min) / (x_max - x_min) * plot_width);
  };
  for (const double xv : x)
    cv::putText(image, tickLabel(xv), {to_x(xv) - 8, axis.bottom + 20}, cv::FONT_HERSHEY_SIMPLEX, kTextScale, kInk, 1,
                cv::LINE_AA);
  cv::putText(image, x_label, {width / 2 - 40, height - kBottom + 45}, cv::FONT_HERSHEY_SIMPLEX, 0.5, kInk, 1,
              cv::LINE_AA);
  for (const auto& s : series) {
    for (std::size_t i = 0; i < x.size() && i < s.values.size(); ++i) {
      if (!drawable(axis, s.values[i])) continue;
      const cv::Point p(to_x(x[i]), axis.pixel(s.values[i]));
      errorBar(image, axis, p.x, s.values[i], sigmaAt(s, i), s.colour);
      cv::circle(image, p, 4, s.colour, cv::FILLED, cv::LINE_AA);
      if (i > 0 && drawable(axis, s.values[i - 1]))
        cv::line(image, {to_x(x[i - 1]), axis.pixel(s.values[i - 1])}, p, s.colour, 2, cv::LINE_AA);
    }
  }
  legend(image, series);
  return image;
}

cv::Mat sideBySide(const std::vector<cv::Mat>& panels) {
  if (panels.empty()) throw std::invalid_argument("sideBySide: no panels");
  cv::Mat image;
  cv::hconcat(panels, image);
  return image;
}

void writePng(const std::filesystem::path& path, const cv::Mat& image) {
  support::writeAtomically(
      path, [&](const std::filesystem::path& temporary) { return cv::imwrite(temporary.string(), image); });
}

}  // namespace mire::app
