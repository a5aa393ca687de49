// report.json of `mire measure --report` (measure_report.hpp, doc/report-json.md).
#include "measure_report.hpp"

#include "mire/support/statistics.hpp"

#include <nlohmann/json.hpp>

namespace mire::app {

void writeMeasureReportJson(const std::filesystem::path& path, const MeasureReportData& data) {
  Json doc = reportHeader("measure", data.provenance);
  doc["poses_measured"] = data.measured.size();
  Json failed = Json::array();
  for (const FailedPose& f : data.failed) failed.push_back({{"pose_id", f.pose_id}, {"reason", f.reason}});
  doc["poses_failed"] = failed;
  doc["camera_covariance"] = data.camera_covariance;
  const Eigen::Matrix<double, 6, 1> total = medianSigmasDisplay(data.measured, false);
  const Eigen::Matrix<double, 6, 1> noise = medianSigmasDisplay(data.measured, true);
  doc["median_sigma_translation_mm"] = numberArray(Eigen::VectorXd(total.head<3>()));
  doc["median_sigma_rotation_deg"] = numberArray(Eigen::VectorXd(total.tail<3>()));
  doc["median_sigma_pixel_noise_translation_mm"] = numberArray(Eigen::VectorXd(noise.head<3>()));
  doc["median_sigma_pixel_noise_rotation_deg"] = numberArray(Eigen::VectorXd(noise.tail<3>()));
  std::vector<double> rms, used;
  int ambiguous = 0, flagged = 0;
  for (const auto& pose : data.measured) {
    rms.push_back(pose.estimate.rms_px);
    used.push_back(pose.images_used);
    ambiguous += pose.estimate.ambiguous ? 1 : 0;
    flagged += pose.flags.empty() ? 0 : 1;
  }
  setNumber(doc, "median_rms_px", rms.empty() ? NAN : support::median(rms), "no pose measured");
  setNumber(doc, "median_images_used", used.empty() ? NAN : support::median(used), "no pose measured");
  doc["ambiguous_poses"] = ambiguous;
  doc["flagged_poses"] = flagged;
  Json bias{{"modes", data.bias.names.size()}, {"text", data.bias.text()}};
  setNumber(bias, "sigma_px", data.bias.features > 0 ? data.bias.sigma_px : NAN, "too few poses");
  setNumber(bias, "significance", data.bias.features > 0 ? data.bias.significance : NAN, "too few poses");
  doc["detector_bias"] = bias;
  writeReportJson(path, doc);
}

}  // namespace mire::app
