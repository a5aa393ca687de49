#pragma once
// Small charts drawn with OpenCV for the reports (bars and polylines, labelled axes, optional ±σ error bars and
// logarithmic y axis).
#include <opencv2/core.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace mire::app {

struct Series {
  std::string label;
  std::vector<double> values;  // one per category (bars) or per x (lines); NaN = missing
  cv::Scalar colour;
  std::vector<double> sigma = {};  // optional, one per value: drawn as a ±σ error bar; empty or NaN = none
};

enum class YScale { linear, log10 };

// Grouped bar chart: one group per category, one bar per series. Linear: y from 0; log10: y over the decades
// spanned by the positive values (non-positive values are not drawn).
cv::Mat barChart(const std::string& title, const std::string& y_label, const std::vector<std::string>& categories,
                 const std::vector<Series>& series, int width = 960, int height = 540, YScale y_scale = YScale::linear);

// Line chart over x values (shared by all series); y as in barChart.
cv::Mat lineChart(const std::string& title, const std::string& x_label, const std::string& y_label,
                  const std::vector<double>& x, const std::vector<Series>& series, int width = 960, int height = 540,
                  YScale y_scale = YScale::linear);

// Panels of equal height placed side by side in one image (e.g. one chart per unit).
cv::Mat sideBySide(const std::vector<cv::Mat>& panels);

// Writes a PNG atomically; throws naming the path on failure.
void writePng(const std::filesystem::path& path, const cv::Mat& image);

// Distinct colours for series (BGR).
cv::Scalar seriesColour(int index);

}  // namespace mire::app
