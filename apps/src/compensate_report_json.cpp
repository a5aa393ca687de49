// report.json of `mire compensate --report` (compensate_report.hpp, doc/report-json.md).
#include "compensate_report.hpp"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

namespace mire::app {

void writeCompensateReportJson(const std::filesystem::path& path, const CompensateReportData& data) {
  Json doc = reportHeader("compensate", data.provenance);
  doc["mode"] = data.mode;
  doc["model"] = data.model;
  doc["output"] = data.output;
  doc["rows_written"] = data.sigmas.size();
  doc["left_out"] = data.left_out;
  doc["parameter_covariance"] = data.has_covariance;
  Json components = Json::array();
  for (std::size_t k = 0; k < data.component_names.size(); ++k) {
    Json item{{"name", data.component_names[k]}, {"unit", mechanism::unitName(data.units[k])}};
    double largest = 0.0, sum2 = 0.0;
    for (const auto& s : data.sigmas)
      if (static_cast<Eigen::Index>(k) < s.size())
        largest = std::max(largest, s[static_cast<Eigen::Index>(k)]),
        sum2 += s[static_cast<Eigen::Index>(k)] * s[static_cast<Eigen::Index>(k)];
    const bool any = !data.sigmas.empty() && data.has_covariance;
    setNumber(item, "sigma_rms", any ? std::sqrt(sum2 / static_cast<double>(data.sigmas.size())) : NAN,
              data.has_covariance ? "no row written" : "no parameter covariance");
    setNumber(item, "sigma_max", any ? largest : NAN, data.has_covariance ? "no row written" : "no parameter covariance");
    components.push_back(item);
  }
  doc["components"] = components;
  if (data.controller) {
    const mechanism::ControllerFit& fit = *data.controller;
    Json c{{"model", data.controller_model}, {"poses", fit.poses}, {"draws", fit.draws}};
    setNumber(c, "rms_position_error_m", fit.rms_position_error, "not computed");
    setNumber(c, "max_position_error_m", fit.max_position_error, "not computed");
    setNumber(c, "rms_joint_residual", fit.rms_joint_residual, "not computed");
    setNumber(c, "expected_rms_position_error_m", fit.expected_rms_position_error, "no parameter covariance");
    setNumber(c, "sigma_rms_position_error_m", fit.sigma_rms_position_error, "no parameter covariance");
    doc["controller_fit"] = c;
  }
  writeReportJson(path, doc);
}

}  // namespace mire::app
