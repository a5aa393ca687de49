// report.html of `mire measure --report` (measure_report.hpp): the median precision per component
// first, then the σ of every pose by component (translation in mm and rotation in degrees on their
// own axes, the pixel-noise-only part beside the total), the failed and flagged poses, and the
// provenance.
#include "measure_report.hpp"
#include "number_text.hpp"
#include "report_html.hpp"

#include "mire/support/constants.hpp"
#include "mire/support/statistics.hpp"

#include <cstdio>

namespace mire::app {
namespace {

namespace rp = mire::report;

// One panel for the translation (mm), one for the rotation (deg): per pose (file order) the total
// σ of each component as points and the pixel-noise-only σ as a line beneath.
rp::Figure sigmaFigure(const MeasureReportData& data) {
  const auto total = poseSigmasDisplay(data.measured, false);
  const auto noise = poseSigmasDisplay(data.measured, true);
  const char* names[6] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  rp::Figure figure;
  figure.columns = 2;
  figure.panel_width = 390.0;
  figure.panel_height = 300.0;
  for (int part = 0; part < 2; ++part) {
    rp::Panel panel;
    panel.title = part == 0 ? "translation of cTm" : "rotation of cTm";
    panel.x = rp::makeAxis("pose (file order)", "");
    panel.y = rp::makeAxis("\xCF\x83", part == 0 ? "mm" : "deg");
    panel.y.include_zero = true;
    for (int c = 3 * part; c < 3 * part + 3; ++c) {
      rp::Series s, n;
      s.label = std::string(names[c]) + " total";
      s.mark = rp::Mark::points;
      s.colour = rp::paletteColour(static_cast<std::size_t>(c % 3));
      n.label = part == 0 && c == 0 ? "pixel noise only (lines)" : "";
      n.mark = rp::Mark::line;
      n.colour = s.colour;
      for (std::size_t k = 0; k < total.size(); ++k) {
        s.x.push_back(static_cast<double>(k + 1)), s.y.push_back(total[k][c]);
        n.x.push_back(static_cast<double>(k + 1)), n.y.push_back(noise[k][c]);
      }
      panel.series.push_back(s);
      panel.series.push_back(n);
    }
    figure.panels.push_back(panel);
  }
  return figure;
}

}  // namespace

std::vector<Eigen::Matrix<double, 6, 1>> poseSigmasDisplay(const std::vector<metrology::MeasuredPose>& poses,
                                                           bool pixel_noise_only) {
  std::vector<Eigen::Matrix<double, 6, 1>> out;
  for (const auto& pose : poses) {
    Eigen::Matrix<double, 6, 1> s = metrology::PoseEstimate::sigmas(
        pixel_noise_only ? pose.estimate.covariance_pixel_noise : pose.estimate.covariance);
    s.head<3>() *= 1e3;
    s.tail<3>() *= 180.0 / support::kPi;
    out.push_back(s);
  }
  return out;
}

Eigen::Matrix<double, 6, 1> medianSigmasDisplay(const std::vector<metrology::MeasuredPose>& poses, bool pixel_noise_only) {
  const auto sigmas = poseSigmasDisplay(poses, pixel_noise_only);
  Eigen::Matrix<double, 6, 1> out = Eigen::Matrix<double, 6, 1>::Constant(NAN);
  if (sigmas.empty()) return out;
  for (int c = 0; c < 6; ++c) {
    std::vector<double> values;
    for (const auto& s : sigmas) values.push_back(s[c]);
    out[c] = support::median(values);
  }
  return out;
}

void writeMeasureReportHtml(const std::filesystem::path& path, const MeasureReportData& data) {
  const Eigen::Matrix<double, 6, 1> total = medianSigmasDisplay(data.measured, false);
  const Eigen::Matrix<double, 6, 1> noise = medianSigmasDisplay(data.measured, true);
  rp::HtmlReport page("Pose measurement report");
  page.lead(std::to_string(data.measured.size()) + " of " + std::to_string(data.measured.size() + data.failed.size()) +
            " poses measured; median \xCF\x83 per component " + format("%.3f", total[0]) + ", " +
            format("%.3f", total[1]) + ", " + format("%.3f", total[2]) + " mm (tx, ty, tz) and " +
            format("%.4f", total[3]) + ", " + format("%.4f", total[4]) + ", " + format("%.4f", total[5]) +
            " deg (rx, ry, rz)" +
            (data.camera_covariance ? std::string(", the camera's calibration uncertainty included.")
                                    : std::string(": pixel noise only (the camera file has no covariance: "
                                                  "too optimistic).")));
  page.section("Precision per component");
  page.table({"", "tx (mm)", "ty (mm)", "tz (mm)", "rx (deg)", "ry (deg)", "rz (deg)"},
             {{"median \xCF\x83, total", format("%.4f", total[0]), format("%.4f", total[1]), format("%.4f", total[2]),
               format("%.5f", total[3]), format("%.5f", total[4]), format("%.5f", total[5])},
              {"median \xCF\x83, pixel noise only", format("%.4f", noise[0]), format("%.4f", noise[1]),
               format("%.4f", noise[2]), format("%.5f", noise[3]), format("%.5f", noise[4]), format("%.5f", noise[5])}});
  page.figure(sigmaFigure(data),
              "The standard uncertainty of every measured pose by component (points: total, the camera's "
              "calibration uncertainty included; lines: the pixel noise of the pose's own images alone), "
              "translation and rotation each on its own unit's axis.");
  page.paragraph("Detector bias shared by the poses (doc/uncertainty.md): " + data.bias.text() + ".");
  std::vector<std::vector<std::string>> notes;
  for (const auto& f : data.failed) notes.push_back({f.pose_id, "failed", f.reason});
  for (const auto& pose : data.measured) {
    std::string flags;
    for (const auto& flag : pose.flags) flags += (flags.empty() ? "" : "; ") + flag;
    if (!flags.empty() || pose.estimate.ambiguous)
      notes.push_back({pose.pose_id, "measured, flagged", flags.empty() ? std::string("ambiguous") : flags});
  }
  if (!notes.empty()) {
    page.section("Failed and flagged poses");
    page.table({"pose", "status", "reason"}, notes);
  }
  addProvenance(page, data.provenance);
  writeHtml(path, page);
}

}  // namespace mire::app
