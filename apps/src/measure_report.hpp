#pragma once
// `mire measure --report DIR` (doc/measurement.md): report.json (the campaign's precision in a
// few numbers: poses measured and failed, the median σ per component, total and pixel noise
// only, the detector's shared bias) and report.html (the result first, the σ of every pose by
// component, the failed and flagged poses, the provenance). One writer per file:
// measure_report_json.cpp, measure_report_html.cpp.
#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

#include "mire/metrology/detector_bias.hpp"
#include "mire/metrology/poses_csv.hpp"
#include "report_json.hpp"

namespace mire::app {

struct FailedPose {
  std::string pose_id, reason;
};

struct MeasureReportData {
  ReportProvenance provenance;
  std::vector<metrology::MeasuredPose> measured;
  std::vector<FailedPose> failed;
  metrology::DetectorBiasTerm bias;
  bool camera_covariance = true;  // false: σ from pixel noise only
};

// σ of every component of every measured pose in display units (mm for tx ty tz, deg for rx ry
// rz); `pixel_noise_only` picks the pixel-noise part.
std::vector<Eigen::Matrix<double, 6, 1>> poseSigmasDisplay(const std::vector<metrology::MeasuredPose>& poses,
                                                           bool pixel_noise_only);
// Their median per component.
Eigen::Matrix<double, 6, 1> medianSigmasDisplay(const std::vector<metrology::MeasuredPose>& poses, bool pixel_noise_only);

void writeMeasureReportJson(const std::filesystem::path& path, const MeasureReportData& data);
void writeMeasureReportHtml(const std::filesystem::path& path, const MeasureReportData& data);

}  // namespace mire::app
