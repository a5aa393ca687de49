// Diagnostic images of a calibration: residual vectors, projection-uncertainty map.
#include "mire/calibration/calibration_plots.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace mire::calibration {

namespace {
// 1, 2 or 5 × 10^k nearest below `value`.
double niceNumber(double value) {
  if (!(value > 0.0)) return 1.0;
  const double exponent = std::floor(std::log10(value));
  const double base = std::pow(10.0, exponent);
  const double mantissa = value / base;
  return (mantissa >= 5.0 ? 5.0 : mantissa >= 2.0 ? 2.0 : 1.0) * base;
}

std::string format(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

void putLabel(cv::Mat& image, const std::string& text, cv::Point at, double scale = 0.5) {
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(255, 255, 255), 3, cv::LINE_AA);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}
}  // namespace

cv::Mat drawResidualMap(const CalibrationResult& result) {
  const int width = result.camera.width, height = result.camera.height;
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  std::vector<double> norms;
  for (const auto& view : result.views)
    if (view.used)
      for (std::size_t k = 0; k < view.residuals.size(); ++k)
        if (view.inlier[k]) norms.push_back(view.residuals[k].norm());
  if (norms.empty()) return image;
  std::sort(norms.begin(), norms.end());
  const double p95 = std::max(norms[static_cast<std::size_t>(0.95 * (norms.size() - 1))], 1e-6);
  const double magnification = niceNumber(0.03 * width / p95);
  for (const auto& view : result.views) {
    if (!view.used) continue;
    for (std::size_t k = 0; k < view.residuals.size(); ++k) {
      const cv::Point2d from(view.pixels[k].x(), view.pixels[k].y());
      const cv::Point2d to = from + magnification * cv::Point2d(view.residuals[k].x(), view.residuals[k].y());
      const cv::Scalar colour = view.inlier[k] ? cv::Scalar(200, 80, 0) : cv::Scalar(0, 0, 230);
      cv::circle(image, from, 1, cv::Scalar(150, 150, 150), cv::FILLED, cv::LINE_AA);
      cv::line(image, from, to, colour, 1, cv::LINE_AA);
    }
  }
  // Scale bar: a nice residual length drawing about 8 % of the width.
  const double bar_px = niceNumber(0.08 * width / magnification);
  const int bar_length = static_cast<int>(std::lround(bar_px * magnification));
  const cv::Point start(20, height - 25);
  cv::line(image, start, start + cv::Point(bar_length, 0), cv::Scalar(0, 0, 0), 2);
  putLabel(image, format("%g px residual", bar_px) + format(" (vectors x%g)", magnification), start + cv::Point(0, -8));
  putLabel(image, format("RMS %.3f px", result.camera.rms_px) + ", " + std::to_string(result.rejected_points) +
                      " rejected points (red)",
           cv::Point(20, 25));
  return image;
}

cv::Mat drawProjectionUncertaintyMap(const CalibrationResult& result, int grid_step_px) {
  const int width = result.camera.width, height = result.camera.height;
  const int step = std::max(4, grid_step_px);
  const int cols = width / step + 1, rows = height / step + 1;
  cv::Mat values(rows, cols, CV_64F);
  double largest = 0.0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector2d pixel(std::min(c * step, width - 1), std::min(r * step, height - 1));
      const double value = projectionUncertaintyPx(result, pixel, result.uncertainty_distance_m);
      values.at<double>(r, c) = std::isfinite(value) ? value : 0.0;
      if (std::isfinite(value)) largest = std::max(largest, value);
    }
  const double top = largest > 0.0 ? largest : 1.0;
  cv::Mat scaled;
  values.convertTo(scaled, CV_8U, 255.0 / top);
  cv::Mat resized;
  cv::resize(scaled, resized, cv::Size(width, height), 0, 0, cv::INTER_LINEAR);
  cv::Mat image;
  cv::applyColorMap(resized, image, cv::COLORMAP_VIRIDIS);
  // Colour bar on the right.
  const int bar_x = width - 40, bar_top = 80, bar_bottom = height - 40;
  for (int y = bar_top; y <= bar_bottom; ++y) {
    const double t = 1.0 - static_cast<double>(y - bar_top) / (bar_bottom - bar_top);
    cv::Mat one(1, 1, CV_8U, cv::Scalar(static_cast<int>(std::lround(255.0 * t))));
    cv::Mat colour;
    cv::applyColorMap(one, colour, cv::COLORMAP_VIRIDIS);
    const cv::Vec3b c = colour.at<cv::Vec3b>(0, 0);
    cv::line(image, {bar_x, y}, {bar_x + 20, y}, cv::Scalar(c[0], c[1], c[2]));
  }
  putLabel(image, format("%.3f px", top), {bar_x - 70, bar_top - 8}, 0.45);
  putLabel(image, "0 px", {bar_x - 10, bar_bottom + 20});
  const ProjectionUncertaintySummary summary = summarizeProjectionUncertainty(result);
  putLabel(image, "projection uncertainty (1 sigma, worst direction) at " + format("%.3f m", result.uncertainty_distance_m),
           {10, 22}, 0.45);
  putLabel(image,
           "centre " + format("%.3f", summary.centre_px) + " px, edge " + format("%.3f", summary.edge_px) +
               " px, corner " + format("%.3f px", summary.corner_px),
           {10, 44}, 0.45);
  return image;
}

}  // namespace mire::calibration
