#include "demo_report_parts.hpp"

#include "accuracy_report.hpp"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

namespace mire::app::demo_report {

std::string percent(double after, double before) {
  return before > 0.0 && std::isfinite(after) ? format("%+.0f %%", 100.0 * (after - before) / before) : "n/a";
}

std::string sci(double value) { return std::isfinite(value) ? format("%.2e", value) : "n/a"; }

void writeRunTimeTable(const std::vector<StageTiming>& timings, std::ostream& md) {
  double total = 0.0;
  md << "## Run time\n\n| stage | seconds |\n| --- | ---: |\n";
  for (const auto& t : timings) {
    md << "| " << t.name << " | " << fixed(t.seconds, 1) << " |\n";
    total += t.seconds;
  }
  md << "| **total** | **" << fixed(total, 1) << "** |\n\n";
}

void writeCalibrationSection(const pipeline::CalibrationScore& c, std::ostream& md) {
  md << "## 1. Camera calibration (`camera.yaml`)\n\n"
     << c.views_used << " of " << c.views_total << " views used, RMS " << fixed(c.rms_px, 3)
     << " px; projection uncertainty " << fixed(c.uncertainty_centre_px, 3) << " px at the centre, "
     << fixed(c.uncertainty_corner_px, 3)
     << " px at the corner.\n\n| parameter | estimate | σ | truth | error / σ |\n| --- | ---: | ---: | ---: | ---: |\n";
  for (std::size_t i = 0; i < c.names.size() && i < c.truth.size(); ++i) {
    const double sigma = i < c.sigma.size() ? c.sigma[i] : NAN;
    md << "| " << c.names[i] << " | " << format("%.6g", c.estimate[i]) << " | " << format("%.2g", sigma) << " | "
       << format("%.6g", c.truth[i]) << " | " << fixed((c.estimate[i] - c.truth[i]) / sigma, 2) << " |\n";
  }
}

void writePoseMeasurementTable(const pipeline::MeasurementScore& m, std::ostream& md, const std::string& extra_row) {
  md << "| component | tx | ty | tz | rx | ry | rz |\n| --- | ---: | ---: | ---: | ---: | ---: | ---: |\n"
     << "| predicted σ (mm, °) |";
  for (int k = 0; k < 3; ++k) md << " " << fixed(m.median_sigma_mm[k], 3) << " |";
  for (int k = 0; k < 3; ++k) md << " " << fixed(m.median_sigma_deg[k], 4) << " |";
  md << "\n| RMS error to truth |";
  for (int k = 0; k < 3; ++k) md << " " << fixed(m.rms_error_mm[k], 3) << " |";
  for (int k = 0; k < 3; ++k) md << " " << fixed(m.rms_error_deg[k], 4) << " |";
  if (!extra_row.empty()) md << "\n" << extra_row;
  md << "\n| RMS error/σ, pose by pose |";
  for (int k = 0; k < 6; ++k) md << " " << fixed(m.normalized_error_rms[k], 2) << " |";
  md << "\n| RMS error/σ, whitened across poses |";
  for (int k = 0; k < 6; ++k) md << " " << fixed(m.whitened_error_rms[k], 2) << " |";
  md << "\n\nRMS of error/σ over all components: " << fixed(m.normalized_error_std, 2) << " pose by pose; "
     << fixed(m.whitened_error_rms_all, 2)
     << " with the errors whitened by their whole covariance (1 means the σ are honest). Every pose carries "
     << "the same calibration error (section 1), so error/σ pose by pose is correlated across the campaign: "
     << "its RMS is one draw of that shared error, not an average. The whitened row uses each pose's own "
     << "noise covariance plus the shared term D Σ_k Dᵀ across poses (doc/uncertainty.md).\n";
  md << "\nDetector bias shared by the poses (doc/uncertainty.md, \"The detector's shared bias\"): "
     << m.detector_bias.text() << ".\n";
}

Json calibrationJson(const pipeline::CalibrationScore& c) {
  std::vector<std::string> units(c.names.size(), "1");
  for (std::size_t i = 0; i < units.size() && i < 4; ++i) units[i] = "px";
  Json parameters = Json::array();
  for (std::size_t i = 0; i < c.names.size(); ++i) {
    Json item{{"name", c.names[i]}, {"unit", units[i]}};
    setNumber(item, "value", c.estimate.at(i), "not computed");
    setNumber(item, "sigma", i < c.sigma.size() ? c.sigma[i] : NAN, "no covariance");
    setNumber(item, "truth", i < c.truth.size() ? c.truth[i] : NAN, "no truth for this parameter");
    parameters.push_back(item);
  }
  Json out{{"views_used", c.views_used}, {"views_total", c.views_total}};
  setNumber(out, "rms_px", c.rms_px, "not computed");
  setNumber(out, "projection_uncertainty_centre_px", c.uncertainty_centre_px, "outside the lens model's field");
  setNumber(out, "projection_uncertainty_corner_px", c.uncertainty_corner_px, "outside the lens model's field");
  out["parameters"] = parameters;
  out["covariance"] = covarianceJson(c.names, units, c.covariance);
  return out;
}

Json measurementJson(const pipeline::MeasurementScore& m) {
  Json out{{"measured", m.measured}, {"total", m.total}};
  out["median_sigma_translation_mm"] = numberArray(Eigen::VectorXd(m.median_sigma_mm));
  out["median_sigma_rotation_deg"] = numberArray(Eigen::VectorXd(m.median_sigma_deg));
  out["rms_error_translation_mm"] = numberArray(Eigen::VectorXd(m.rms_error_mm));
  out["rms_error_rotation_deg"] = numberArray(Eigen::VectorXd(m.rms_error_deg));
  setNumber(out, "normalized_error_rms", m.normalized_error_std, "no pose measured");
  out["normalized_error_rms_per_component"] = numberArray(Eigen::VectorXd(m.normalized_error_rms));
  out["whitened_error_rms_per_component"] = numberArray(Eigen::VectorXd(m.whitened_error_rms));
  setNumber(out, "whitened_error_rms", m.whitened_error_rms_all, "no pose measured");
  out["pose_covariances_file"] = "poses_covariance.csv";
  Json bias{{"modes", m.detector_bias.names.size()}};
  setNumber(bias, "sigma_px", m.detector_bias.features > 0 ? m.detector_bias.sigma_px : NAN, "too few poses");
  setNumber(bias, "significance", m.detector_bias.features > 0 ? m.detector_bias.significance : NAN, "too few poses");
  out["detector_bias"] = bias;
  return out;
}

void setParameterScores(Json& out, const std::vector<DemoParameterScore>& scores, const Eigen::MatrixXd& covariance,
                        const std::string& truth_key, const std::string& no_truth_reason) {
  Json parameters = Json::array();
  std::vector<std::string> names, units;
  for (const DemoParameterScore& p : scores) {
    Json item{{"name", p.name}, {"unit", p.si_unit}};
    setNumber(item, "value", p.si_estimate, "not computed");
    setNumber(item, "sigma", p.si_sigma, "not computed");
    setNumber(item, truth_key, p.si_truth, no_truth_reason);
    parameters.push_back(item);
    names.push_back(p.name);
    units.push_back(p.si_unit);
  }
  out["parameters"] = parameters;
  out["covariance"] = covarianceJson(names, units, covariance);
}

namespace {

double meanOf(const std::vector<mechanism::PositionAccuracy>& positions, double mechanism::PositionAccuracy::*figure) {
  double sum = 0.0;
  for (const auto& p : positions) sum += p.*figure;
  return positions.empty() ? std::nan("") : sum / static_cast<double>(positions.size());
}

}  // namespace

void writeClosedLoopSection(const pipeline::ClosedLoopTest& t, const std::string& heading,
                            const std::string& controller, std::ostream& md) {
  md << "\n"
     << heading << "\n\n"
     << "The paper's last step, \"modify the control law accordingly\", checked the ISO 9283 way "
        "(doc/accuracy.md): the simulated true robot runs the standard's test, 5 positions on a diagonal plane of a "
     << fixed(t.spec.side * 1e3, 0) << " mm cube, " << t.spec.cycles << " cycles, measured by the camera ("
     << fixed(t.spec.noise_t * 1e3, 2) << " mm per component). Before: the controller runs " << controller
     << ". After: it sends the identified model's joint commands (`mire compensate --poses`). Commanded poses are "
        "in the identified base frame, read through the identified mounting (`mire accuracy`).\n\n"
        "| position | AP_p before (mm) | AP_p after (mm) | σ after (mm) | RP_l before (mm) | RP_l after (mm) | "
        "noise-only RP_l p95 (mm) |\n| --- | ---: | ---: | ---: | ---: | ---: | ---: |\n";
  for (std::size_t k = 0; k < t.before.positions.size() && k < t.after.positions.size(); ++k) {
    const auto& b = t.before.positions[k];
    const auto& a = t.after.positions[k];
    md << "| " << b.position << " | " << fixed(b.ap_p * 1e3, 3) << " | " << fixed(a.ap_p * 1e3, 3) << " | "
       << fixed(a.sigma_ap_p * 1e3, 3) << " | " << fixed(b.rp_l * 1e3, 3) << " | " << fixed(a.rp_l * 1e3, 3) << " | "
       << fixed(a.noise_rp_l.p95 * 1e3, 3) << " |\n";
  }
  const double before = meanOf(t.before.positions, &mechanism::PositionAccuracy::ap_p);
  const double after = meanOf(t.after.positions, &mechanism::PositionAccuracy::ap_p);
  md << "\nMean AP_p " << fixed(before * 1e3, 3) << " mm before, " << fixed(after * 1e3, 3) << " mm after ("
     << percent(after, before)
     << "). RP_l at or below the noise-only p95 is the camera's, not the robot's "
        "(the standard's repeatability needs a finer measurement than this camera's).\n";
}

std::string nominalController(const DemoResults& r) {
  return r.paper ? "model 12 with the nominal parameters" : "the nominal " + r.truth_model + " geometry";
}

Json closedLoopJson(const pipeline::ClosedLoopTest& t) {
  Json out;
  out["positions"] = static_cast<int>(t.before.positions.size());
  out["cycles"] = t.spec.cycles;
  out["cube_side_m"] = t.spec.side;
  out["camera_noise_m"] = t.spec.noise_t;
  out["camera_noise_rad"] = t.spec.noise_r;
  out["before"] = accuracyFiguresJson(t.before);
  out["after"] = accuracyFiguresJson(t.after);
  return out;
}

}  // namespace mire::app::demo_report
