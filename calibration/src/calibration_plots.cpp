// Diagnostic images of a calibration: residual vectors (pooled and per view), projection-uncertainty map
// (doc/plots.md).
#include "mire/calibration/calibration_plots.hpp"
#include "mire/support/constants.hpp"

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
  putLabel(image,
           format("RMS %.3f px", result.camera.rms_px) + ", " + std::to_string(result.rejected_points) +
               " rejected points (red)",
           cv::Point(20, 25));
  return image;
}

namespace {
// Layout of the uncertainty figure: title lines above the map, colour bar right of it.
constexpr int kMapTop = 72, kMapLeft = 8, kBarMargin = 150, kMapBottom = 10;

// 1-2-5 × 10^k values within [low, high] (the contour levels and the colour bar's labelled ticks).
std::vector<double> levels125(double low, double high) {
  std::vector<double> levels;
  if (!(low > 0.0) || !(high > low)) return levels;
  for (double decade = std::pow(10.0, std::floor(std::log10(low))); decade <= high; decade *= 10.0)
    for (const double mantissa : {1.0, 2.0, 5.0})
      if (mantissa * decade >= low && mantissa * decade <= high) levels.push_back(mantissa * decade);
  return levels;
}

// log10 of the uncertainty at grid nodes (c·step, r·step), the last node at or past the image edge;
// NaN where undefined.
cv::Mat sampleLogUncertainty(const CalibrationResult& result, int step) {
  const int cols = (result.camera.width - 2) / step + 2, rows = (result.camera.height - 2) / step + 2;
  cv::Mat values(rows, cols, CV_32F);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const double value =
          projectionUncertaintyPx(result, Eigen::Vector2d(c * step, r * step), result.uncertainty_distance_m);
      values.at<float>(r, c) = static_cast<float>(value > 0.0 ? std::log10(value) : std::nan(""));
    }
  return values;
}

// Every image pixel from the grid, bicubic in log10 (smooth contours); NaN nodes take the grid's minimum.
cv::Mat interpolateToImage(cv::Mat grid, int step, cv::Size size, double fill) {
  cv::patchNaNs(grid, fill);
  cv::Mat map_x(size, CV_32F), map_y(size, CV_32F);
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      map_x.at<float>(y, x) = static_cast<float>(x) / static_cast<float>(step);
      map_y.at<float>(y, x) = static_cast<float>(y) / static_cast<float>(step);
    }
  cv::Mat full;
  cv::remap(grid, full, map_x, map_y, cv::INTER_CUBIC, cv::BORDER_REPLICATE);
  return full;
}

// Viridis over [log_low, log_high].
cv::Mat colourLog(const cv::Mat& log_values, double log_low, double log_high) {
  cv::Mat index;
  log_values.convertTo(index, CV_8U, 255.0 / (log_high - log_low), -255.0 * log_low / (log_high - log_low));
  cv::Mat image;
  cv::applyColorMap(index, image, cv::COLORMAP_VIRIDIS);
  return image;
}

// The contour of `level` (px): the edge of {σ ≥ level}, without the stretches along the image border; each
// piece labelled at its point farthest from the border.
void drawContourLevel(cv::Mat& map, const cv::Mat& log_values, double level) {
  const cv::Mat mask = log_values >= std::log10(level);
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_LIST, cv::CHAIN_APPROX_NONE);
  const auto inset = [&](const cv::Point& p) { return std::min({p.x, p.y, map.cols - 1 - p.x, map.rows - 1 - p.y}); };
  for (const auto& contour : contours) {
    cv::Point label_at = contour.front();
    for (std::size_t k = 0; k < contour.size(); ++k) {
      const cv::Point& a = contour[k];
      const cv::Point& b = contour[(k + 1) % contour.size()];
      if (inset(a) > 0 || inset(b) > 0) cv::line(map, a, b, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
      if (inset(a) > inset(label_at)) label_at = a;
    }
    if (inset(label_at) > 12) putLabel(map, format("%g", level), label_at + cv::Point(3, -3), 0.4);
  }
}

void drawObservations(cv::Mat& map, const CalibrationResult& result) {
  for (const auto& view : result.views)
    if (view.used)
      for (const auto& pixel : view.pixels)
        cv::circle(map, cv::Point2d(pixel.x(), pixel.y()), 1, cv::Scalar(0, 0, 0), cv::FILLED, cv::LINE_AA);
}

// Vertical log colour bar right of the map: 1-2-5 ticks labelled in px, minor ticks at 3, 4, 6…9.
void drawLogColourBar(cv::Mat& canvas, cv::Rect bar, double log_low, double log_high) {
  const auto y_of = [&](double log_value) {
    return bar.y + static_cast<int>(std::lround((log_high - log_value) / (log_high - log_low) * bar.height));
  };
  for (int y = bar.y; y <= bar.y + bar.height; ++y) {
    const double t = 1.0 - static_cast<double>(y - bar.y) / bar.height;
    cv::Mat colour = colourLog(cv::Mat(1, 1, CV_32F, cv::Scalar(log_low + t * (log_high - log_low))), log_low, log_high);
    const cv::Vec3b c = colour.at<cv::Vec3b>(0, 0);
    cv::line(canvas, {bar.x, y}, {bar.x + bar.width, y}, cv::Scalar(c[0], c[1], c[2]));
  }
  cv::rectangle(canvas, bar, cv::Scalar(0, 0, 0));
  const double low = std::pow(10.0, log_low), high = std::pow(10.0, log_high);
  for (double decade = std::pow(10.0, std::floor(log_low)); decade <= high; decade *= 10.0)
    for (int mantissa = 1; mantissa <= 9; ++mantissa) {
      const double value = mantissa * decade;
      if (value < low || value > high) continue;
      const int y = y_of(std::log10(value));
      const bool major = mantissa == 1 || mantissa == 2 || mantissa == 5;
      cv::line(canvas, {bar.x + bar.width, y}, {bar.x + bar.width + (major ? 8 : 4), y}, cv::Scalar(0, 0, 0),
               major ? 2 : 1);
      if (major) putLabel(canvas, format("%g", value), {bar.x + bar.width + 12, y + 5}, 0.45);
    }
  putLabel(canvas, "sigma [px]", {bar.x - 10, bar.y - 22}, 0.45);
  putLabel(canvas, "(log scale)", {bar.x - 10, bar.y - 6}, 0.4);
}

void drawUncertaintyTitle(cv::Mat& canvas, const CalibrationResult& result, int observations) {
  const ProjectionUncertaintySummary summary = summarizeProjectionUncertainty(result);
  putLabel(canvas,
           "projection uncertainty (1 sigma, worst direction) at " + format("%.3f m", result.uncertainty_distance_m),
           {10, 20}, 0.5);
  putLabel(canvas,
           "centre " + format("%.3f", summary.centre_px) + " px, edge " + format("%.3f", summary.edge_px) +
               " px, corner " + format("%.3f px", summary.corner_px) + "; white lines: contours [px]",
           {10, 42}, 0.45);
  putLabel(canvas,
           "black dots: the " + std::to_string(observations) + " observed corners of the " +
               std::to_string(result.used_views) + " views (no dots = no data there)",
           {10, 62}, 0.45);
}
}  // namespace

cv::Mat drawProjectionUncertaintyMap(const CalibrationResult& result, int grid_step_px) {
  const cv::Size size(result.camera.width, result.camera.height);
  const int step = std::max(4, grid_step_px);
  const cv::Mat grid = sampleLogUncertainty(result, step);
  double log_low = 0.0, log_high = 0.0;
  cv::Mat finite = grid == grid;  // false at NaN
  cv::minMaxLoc(grid, &log_low, &log_high, nullptr, nullptr, finite);
  if (cv::countNonZero(finite) == 0) log_low = -3.0, log_high = 0.0;
  if (log_high - log_low < 0.3) log_low -= 0.15, log_high += 0.15;  // a flat field still gets a readable bar
  const cv::Mat log_values = interpolateToImage(grid.clone(), step, size, log_low);
  cv::Mat map = colourLog(log_values, log_low, log_high);
  for (const double level : levels125(std::pow(10.0, log_low), std::pow(10.0, log_high)))
    drawContourLevel(map, log_values, level);
  drawObservations(map, result);
  cv::Mat canvas(kMapTop + size.height + kMapBottom, kMapLeft + size.width + kBarMargin, CV_8UC3,
                 cv::Scalar(255, 255, 255));
  map.copyTo(canvas(cv::Rect({kMapLeft, kMapTop}, size)));
  drawLogColourBar(canvas, cv::Rect(kMapLeft + size.width + 20, kMapTop + 30, 24, size.height - 40), log_low, log_high);
  int observations = 0;
  for (const auto& view : result.views) observations += view.used ? static_cast<int>(view.pixels.size()) : 0;
  drawUncertaintyTitle(canvas, result, observations);
  return canvas;
}

namespace {
// Per-view figure: panels of kPanelsWidth / columns px, a header above them.
constexpr int kPanelsWidth = 1500, kHeader = 64, kPanelTitle = 20;

struct PanelScale {
  double image_to_panel = 1.0;  // panel px per image px
  double magnification = 1.0;   // panel px per px of residual
  double view_rms_flag = 0.0;   // a view RMS above this is flagged (red title)
};

void drawViewPanel(cv::Mat panel, const CalibrationViewResult& view, const PanelScale& scale, const cv::Size image) {
  const cv::Rect frame(2, kPanelTitle, static_cast<int>(image.width * scale.image_to_panel) - 4,
                       static_cast<int>(image.height * scale.image_to_panel) - 4);
  cv::rectangle(panel, frame, cv::Scalar(180, 180, 180));
  for (std::size_t k = 0; k < view.residuals.size(); ++k) {
    const cv::Point2d from =
        cv::Point2d(frame.x, frame.y) + scale.image_to_panel * cv::Point2d(view.pixels[k].x(), view.pixels[k].y());
    const cv::Point2d to = from + scale.magnification * cv::Point2d(view.residuals[k].x(), view.residuals[k].y());
    cv::circle(panel, from, 1, cv::Scalar(150, 150, 150), cv::FILLED, cv::LINE_AA);
    cv::line(panel, from, to, view.inlier[k] ? cv::Scalar(200, 80, 0) : cv::Scalar(0, 0, 230), 1, cv::LINE_AA);
  }
  const bool flagged = view.rms_px > scale.view_rms_flag;
  std::string title = view.name + format("  RMS %.3f px", view.rms_px);
  double font = 0.42;
  while (font > 0.25 && cv::getTextSize(title, cv::FONT_HERSHEY_SIMPLEX, font, 1, nullptr).width > panel.cols - 4)
    font -= 0.02;
  cv::putText(panel, title, {3, kPanelTitle - 6}, cv::FONT_HERSHEY_SIMPLEX, font,
              flagged ? cv::Scalar(0, 0, 220) : cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

// One magnification for all panels: the 95th-percentile inlier residual draws ≈ 6 % of a panel's width.
PanelScale panelScale(const CalibrationResult& result, int panel_width) {
  std::vector<double> norms;
  for (const auto& view : result.views)
    if (view.used)
      for (std::size_t k = 0; k < view.residuals.size(); ++k)
        if (view.inlier[k]) norms.push_back(view.residuals[k].norm());
  std::sort(norms.begin(), norms.end());
  const double p95 = norms.empty() ? 1.0 : std::max(norms[static_cast<std::size_t>(0.95 * (norms.size() - 1))], 1e-6);
  PanelScale scale;
  scale.image_to_panel = static_cast<double>(panel_width) / result.camera.width;
  scale.magnification = niceNumber(0.06 * panel_width / p95);
  scale.view_rms_flag = 1.5 * result.camera.rms_px;
  return scale;
}

void drawPerViewHeader(cv::Mat& canvas, const CalibrationResult& result, const PanelScale& scale, int views) {
  putLabel(canvas,
           "residuals per view (projected - observed): " + std::to_string(views) + " views (" +
               std::to_string(result.rejected_views) + " rejected, see views.csv), overall RMS " +
               format("%.3f px", result.camera.rms_px),
           {10, 20}, 0.45);
  const double bar_px = niceNumber(0.08 * kPanelsWidth / 5.0 / scale.magnification);
  const int bar_length = static_cast<int>(std::lround(bar_px * scale.magnification));
  const cv::Point start(10, 50);
  cv::line(canvas, start, start + cv::Point(bar_length, 0), cv::Scalar(0, 0, 0), 2);
  putLabel(canvas,
           "= " + format("%g", bar_px) +
               " px residual, the same scale in every panel; red title: view RMS > 1.5 x overall; red vectors: "
               "rejected points",
           start + cv::Point(bar_length + 8, 5), 0.45);
}
}  // namespace

cv::Mat drawResidualsPerView(const CalibrationResult& result) {
  std::vector<const CalibrationViewResult*> views;
  for (const auto& view : result.views)
    if (view.used) views.push_back(&view);
  const int count = std::max(1, static_cast<int>(views.size()));
  const int columns = std::max(1, static_cast<int>(std::ceil(std::sqrt(count * 1.3))));
  const int rows = (count + columns - 1) / columns;
  const int panel_width = kPanelsWidth / columns;
  const int panel_height =
      kPanelTitle +
      static_cast<int>(std::ceil(panel_width * result.camera.height / static_cast<double>(result.camera.width))) + 4;
  cv::Mat canvas(kHeader + rows * panel_height, kPanelsWidth, CV_8UC3, cv::Scalar(255, 255, 255));
  const PanelScale scale = panelScale(result, panel_width);
  for (std::size_t i = 0; i < views.size(); ++i) {
    const int column = static_cast<int>(i) % columns, row = static_cast<int>(i) / columns;
    drawViewPanel(canvas(cv::Rect(column * panel_width, kHeader + row * panel_height, panel_width, panel_height)),
                  *views[i], scale, cv::Size(result.camera.width, result.camera.height));
  }
  drawPerViewHeader(canvas, result, scale, static_cast<int>(views.size()));
  return canvas;
}

cv::Mat drawModelCheck(const CalibrationResult& result, const ModelCheck& check) {
  const int width = result.camera.width, height = result.camera.height, top = 72;
  cv::Mat image(height + top, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const ResidualStructure& structure = check.structure;
  const cv::Point2d centre(result.camera.cx(), result.camera.cy() + top);
  const cv::Scalar grey(170, 170, 170);
  for (std::size_t r = 1; r < structure.ring_edges_px.size(); ++r)
    cv::circle(image, centre, static_cast<int>(std::lround(structure.ring_edges_px[r])), grey, 1, cv::LINE_AA);
  const double outer = structure.ring_edges_px.empty() ? 0.0 : structure.ring_edges_px.back();
  for (int s = 0; s < structure.sectors; ++s) {
    const double angle = -support::kPi + s * 2.0 * support::kPi / structure.sectors;
    cv::line(image, centre, centre + outer * cv::Point2d(std::cos(angle), std::sin(angle)), grey, 1, cv::LINE_AA);
  }
  double largest = 0.0;
  for (const auto& bin : structure.bins) largest = std::max(largest, bin.mean_px.norm());
  const double ring_width = outer / std::max(1, structure.rings);
  const double magnification = niceNumber(0.45 * ring_width / std::max(largest, 1e-6));
  for (const auto& bin : structure.bins) {
    if (bin.points == 0) continue;
    const double radius = 0.5 * (bin.radius_min_px + bin.radius_max_px);
    const double angle = 0.5 * (bin.angle_min_rad + bin.angle_max_rad);
    const cv::Point2d from = centre + radius * cv::Point2d(std::cos(angle), std::sin(angle));
    const cv::Point2d to = from + magnification * cv::Point2d(bin.mean_px.x(), bin.mean_px.y());
    const cv::Scalar colour = !bin.tested ? grey : bin.significant ? cv::Scalar(0, 0, 220) : cv::Scalar(200, 80, 0);
    cv::circle(image, from, 3, colour, cv::FILLED, cv::LINE_AA);
    cv::arrowedLine(image, from, to, colour, 2, cv::LINE_AA, 0, 0.2);
  }
  const double bar_px = niceNumber(0.08 * width / magnification);
  const int bar_length = static_cast<int>(std::lround(bar_px * magnification));
  const cv::Point start(20, top + height - 25);
  cv::line(image, start, start + cv::Point(bar_length, 0), cv::Scalar(0, 0, 0), 2);
  putLabel(image, format("%g px mean residual", bar_px) + format(" (arrows x%g)", magnification),
           start + cv::Point(0, -8));
  std::string verdict = check.verdictLine();
  if (verdict.size() > 110) verdict = verdict.substr(0, 107) + "...";
  putLabel(image, verdict, cv::Point(10, 25));
  putLabel(image,
           std::to_string(structure.rings) + " rings x " + std::to_string(structure.sectors) +
               " directions; red: bin mean significant (views as clusters, Bonferroni), blue: not, grey: untested",
           cv::Point(10, 55), 0.45);
  return image;
}

}  // namespace mire::calibration
