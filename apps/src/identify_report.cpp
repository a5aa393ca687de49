// Report of `mire identify` (see identify_report.hpp).
#include "identify_report.hpp"
#include "plot.hpp"
#include "report_html.hpp"

#include "mire/support/atomic_file.hpp"
#include "mire/support/constants.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace mire::app {
namespace {

using support::kDegreesPerRadian;
const cv::Scalar kLegColours[4] = {cv::Scalar(200, 80, 30), cv::Scalar(40, 150, 40), cv::Scalar(30, 30, 200),
                                   cv::Scalar(160, 40, 160)};

std::string format(const char* fmt, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, fmt, value);
  return buffer;
}

void text(cv::Mat& image, const std::string& s, cv::Point at, double scale = 0.45, const cv::Scalar& colour = {0, 0, 0}) {
  cv::putText(image, s, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv::LINE_AA);
}

// Text read bottom to top, its first letter at `top_left` (bar labels under narrow bars).
void verticalText(cv::Mat& image, const std::string& s, cv::Point top_left, double scale = 0.4) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(s, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline);
  cv::Mat horizontal(size.height + baseline + 2, size.width + 2, image.type(), cv::Scalar(255, 255, 255));
  cv::putText(horizontal, s, {1, size.height + 1}, cv::FONT_HERSHEY_SIMPLEX, scale, {0, 0, 0}, 1, cv::LINE_AA);
  cv::Mat vertical;
  cv::rotate(horizontal, vertical, cv::ROTATE_90_COUNTERCLOCKWISE);
  const cv::Rect where = cv::Rect(top_left - cv::Point(vertical.cols, 0), vertical.size()) & cv::Rect({}, image.size());
  if (where.area() > 0) vertical(cv::Rect({0, 0}, where.size())).copyTo(image(where));
}

// A panel of per-pose, per-leg residuals (deg) with a shared symmetric y range.
void residualPanel(cv::Mat& image, cv::Rect area, const std::vector<mechanism::PoseResidual>& residuals,
                   double limit_deg, const std::string& title) {
  cv::rectangle(image, area, cv::Scalar(120, 120, 120));
  text(image, title, {area.x + 5, area.y - 8}, 0.5);
  const int mid = area.y + area.height / 2;
  cv::line(image, {area.x, mid}, {area.x + area.width, mid}, cv::Scalar(180, 180, 180));
  text(image, "+" + format("%.3g", limit_deg) + " deg", {area.x - 75, area.y + 10}, 0.4);
  text(image, "-" + format("%.3g", limit_deg) + " deg", {area.x - 75, area.y + area.height}, 0.4);
  const std::size_t n = residuals.size();
  for (std::size_t k = 0; k < n; ++k) {
    const int x = area.x + static_cast<int>((k + 0.5) * area.width / std::max<std::size_t>(n, 1));
    for (int leg = 0; leg < residuals[k].residual.size() && leg < 4; ++leg) {
      const double r = residuals[k].residual[leg] * kDegreesPerRadian;
      const double clamped = std::clamp(r / limit_deg, -1.0, 1.0);
      const int y = mid - static_cast<int>(clamped * area.height / 2);
      cv::circle(image, {x + (leg - 2) * 2, y}, 3, kLegColours[leg], cv::FILLED, cv::LINE_AA);
    }
  }
}

void writeResidualsPng(const std::filesystem::path& path, const IdentifyReportData& data) {
  cv::Mat image(620, 1000, CV_8UC3, cv::Scalar(255, 255, 255));
  double max_before = 0.0, max_after = 0.0;
  for (const auto& p : data.residuals_before) max_before = std::max(max_before, p.residual.cwiseAbs().maxCoeff());
  for (const auto& p : data.residuals_after) max_after = std::max(max_after, p.residual.cwiseAbs().maxCoeff());
  residualPanel(image, {90, 40, 880, 230}, data.residuals_before, std::max(max_before * kDegreesPerRadian, 1e-6),
                "joint residuals q - f(X) per pose, before identification (nominal geometry)");
  residualPanel(image, {90, 330, 880, 230}, data.residuals_after, std::max(max_after * kDegreesPerRadian, 1e-6),
                "after identification (" + data.model_label + ")");
  for (int leg = 0; leg < 4; ++leg) {
    cv::circle(image, {100 + leg * 120, 595}, 5, kLegColours[leg], cv::FILLED);
    text(image, "leg " + std::to_string(leg + 1), {110 + leg * 120, 600});
  }
  text(image, "x: poses in file order", {620, 600});
  writePng(path, image);
}

void writeSingularValuesPng(const std::filesystem::path& path, const mechanism::IdentifiabilityReport& report) {
  cv::Mat image(440, 900, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Rect area(80, 40, 790, 300);
  cv::rectangle(image, area, cv::Scalar(120, 120, 120));
  text(image, "singular values of J (" + report.scaling + "), cond = " + format("%.4g", report.condition_number),
       {area.x, 25}, 0.5);
  const auto& s = report.singular_values;
  if (s.size() > 0 && s[0] > 0.0) {
    const double top = std::ceil(std::log10(s[0])), bottom = std::floor(std::log10(std::max(s.minCoeff(), s[0] * 1e-12)));
    const double span = std::max(top - bottom, 1.0);
    for (int d = 0; d <= static_cast<int>(span); ++d) {
      const int y = area.y + area.height - static_cast<int>(d * area.height / span);
      cv::line(image, {area.x, y}, {area.x + area.width, y}, cv::Scalar(225, 225, 225));
      text(image, "1e" + std::to_string(static_cast<int>(bottom) + d), {20, y + 5}, 0.4);
    }
    const int n = static_cast<int>(s.size());
    for (int k = 0; k < n; ++k) {
      const double v = std::max(s[k], std::pow(10.0, bottom));
      const int height = static_cast<int>((std::log10(v) - bottom) / span * area.height);
      const int x0 = area.x + k * area.width / n + 2, x1 = area.x + (k + 1) * area.width / n - 2;
      cv::rectangle(image, cv::Point(x0, area.y + area.height - height), cv::Point(x1, area.y + area.height),
                    cv::Scalar(180, 110, 40), cv::FILLED);
      if (static_cast<std::size_t>(k) < report.dominant_parameters.size())  // the direction's main parameter
        verticalText(image, report.dominant_parameters[static_cast<std::size_t>(k)],
                     {(x0 + x1) / 2 + 4, area.y + area.height + 6});
    }
  }
  text(image,
       "descending; under each, the parameter dominating its direction; rank " + std::to_string(report.rank) + " of " +
           std::to_string(report.parameter_names.size()) + " free parameters",
       {area.x, 425});
  writePng(path, image);
}

void writeSpreadPng(const std::filesystem::path& path, const mechanism::MonteCarloStudy& study,
                    const mechanism::ParameterSet& parameters) {
  std::vector<std::size_t> shown;  // free parameters only (fixed ones have no spread)
  for (std::size_t i = 0; i < parameters.size(); ++i)
    if (!parameters[i].fixed) shown.push_back(i);
  const int width = std::max(900, static_cast<int>(shown.size()) * 40 + 160);
  cv::Mat image(480, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Rect area(80, 40, width - 120, 320);
  cv::rectangle(image, area, cv::Scalar(120, 120, 120));
  text(image, "Monte-Carlo spread (sigma) of each parameter, mm or deg, log scale", {area.x, 25}, 0.5);
  const double bottom = -5.0, top = 2.0, span = top - bottom;
  for (int d = 0; d <= static_cast<int>(span); ++d) {
    const int y = area.y + area.height - static_cast<int>(d * area.height / span);
    cv::line(image, {area.x, y}, {area.x + area.width, y}, cv::Scalar(225, 225, 225));
    text(image, "1e" + std::to_string(static_cast<int>(bottom) + d), {20, y + 5}, 0.4);
  }
  const cv::Scalar colours[4] = {cv::Scalar(30, 30, 200), cv::Scalar(40, 150, 40), cv::Scalar(200, 80, 30),
                                 cv::Scalar(160, 40, 160)};
  const int groups = static_cast<int>(shown.size());
  const int sets = static_cast<int>(study.summaries.size());
  for (int g = 0; g < groups; ++g) {
    const std::size_t i = shown[static_cast<std::size_t>(g)];
    const int x0 = area.x + g * area.width / std::max(groups, 1);
    const int group_width = area.width / std::max(groups, 1);
    for (int s = 0; s < sets; ++s) {
      const double sigma = mechanism::toDisplay(
          parameters[i].unit, study.summaries[static_cast<std::size_t>(s)].sigma[static_cast<Eigen::Index>(i)]);
      if (!(sigma > 0.0)) continue;
      const double h = std::clamp((std::log10(sigma) - bottom) / span, 0.0, 1.0) * area.height;
      const int bx0 = x0 + 3 + s * (group_width - 6) / std::max(sets, 1);
      const int bx1 = x0 + 3 + (s + 1) * (group_width - 6) / std::max(sets, 1) - 1;
      cv::rectangle(image, cv::Point(bx0, area.y + area.height - static_cast<int>(h)),
                    cv::Point(bx1, area.y + area.height), colours[s % 4], cv::FILLED);
    }
    cv::putText(image, parameters[i].name, {x0 + 2, area.y + area.height + 18}, cv::FONT_HERSHEY_SIMPLEX, 0.35,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  for (int s = 0; s < sets; ++s) {
    cv::rectangle(image, cv::Rect(area.x + s * 160, 440, 12, 12), colours[s % 4], cv::FILLED);
    text(image, std::to_string(study.summaries[static_cast<std::size_t>(s)].subset_size) + " poses",
         {area.x + s * 160 + 18, 451});
  }
  writePng(path, image);
}

}  // namespace

void writeIdentifyReport(const std::filesystem::path& dir, const IdentifyReportData& data) {
  std::filesystem::create_directories(dir);
  writeResidualsPng(dir / "residuals.png", data);
  writeSingularValuesPng(dir / "singular_values.png", data.result.identifiability);
  if (data.study) writeSpreadPng(dir / "monte_carlo_spread.png", *data.study, data.result.model.parameters);

  std::ostringstream md;
  md << "# mire identify report\n\n";
  md << "Command: `"
     << (data.provenance.command_line.empty() ? data.command_line : commandLineText(data.provenance.command_line))
     << "`\n\n";
  md << "Model: " << data.model_label << "\n\n";
  md << "```\n" << data.summary_text << "```\n\n";
  md << "## Residuals per pose and leg\n\n![residuals](residuals.png)\n\n";
  md << "## Identifiability\n\n![singular values](singular_values.png)\n\n```\n"
     << data.result.identifiability.text() << "\n```\n\n";
  if (data.study) md << "## Monte-Carlo study\n\n![spreads](monte_carlo_spread.png)\n\n";
  // The mechanism's own joints and units (a Delta has 3 legs in deg, a hexapod 6 in mm).
  const std::vector<mechanism::Unit> units = data.result.model.mechanism->jointUnits();
  md << "## Poses\n\n| pose |";
  for (std::size_t k = 0; k < units.size(); ++k)
    md << " q" << k + 1 << " - f (" << mechanism::displayUnitName(units[k]) << ") |";
  md << " outlier |\n|---|";
  for (std::size_t k = 0; k < units.size(); ++k) md << "---|";
  md << "---|\n";
  for (const auto& p : data.result.poses) {
    md << "| " << p.id;
    for (int k = 0; k < p.residual.size() && k < static_cast<int>(units.size()); ++k)
      md << " | " << format("%+.4f", mechanism::toDisplay(units[static_cast<std::size_t>(k)], p.residual[k]));
    md << " | " << (p.outlier ? "yes" : "") << " |\n";
  }
  support::writeFileAtomically(dir / "report.md", md.str());
  writeIdentifyReportJson(dir / "report.json", data);
  writeIdentifyReportHtml(dir / "report.html", data);
}

}  // namespace mire::app
