#pragma once
// Small charts drawn with OpenCV for the reports (bars and polylines, labelled axes).
#include <opencv2/core.hpp>

#include <filesystem>
#include <string>
#include <vector>

namespace mire::app {

struct Series {
  std::string label;
  std::vector<double> values;  // one per category (bars) or per x (lines); NaN = missing
  cv::Scalar colour;
};

// Grouped bar chart: one group per category, one bar per series, y from 0.
cv::Mat barChart(const std::string& title, const std::string& y_label, const std::vector<std::string>& categories,
                 const std::vector<Series>& series, int width = 960, int height = 540);

// Line chart over x values (shared by all series), y from 0.
cv::Mat lineChart(const std::string& title, const std::string& x_label, const std::string& y_label,
                  const std::vector<double>& x, const std::vector<Series>& series, int width = 960, int height = 540);

// Writes a PNG atomically; throws naming the path on failure.
void writePng(const std::filesystem::path& path, const cv::Mat& image);

// Distinct colours for series (BGR).
cv::Scalar seriesColour(int index);

}  // namespace mire::app
