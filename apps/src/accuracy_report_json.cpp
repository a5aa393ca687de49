// accuracy.json (accuracy_report.hpp).
#include "accuracy_report.hpp"

#include <nlohmann/json.hpp>

namespace mire::app {
namespace {

namespace mech = mire::mechanism;

Json noiseJson(const mech::NoiseOnly& n) { return Json{{"mean", n.mean}, {"p95", n.p95}}; }

Json positionJson(const mech::PositionAccuracy& p) {
  const char* xyz[3] = {"x", "y", "z"};
  const char* abc[3] = {"a", "b", "c"};
  Json item{{"position", p.position}, {"cycles", p.cycles}};
  item["commanded"] = numberArray(Eigen::VectorXd(p.commanded));
  item["barycentre"] = numberArray(Eigen::VectorXd(p.barycentre));
  item["AP_p_m"] = p.ap_p;
  item["sigma_AP_p_m"] = p.sigma_ap_p;
  item["noise_only_AP_p_m"] = noiseJson(p.noise_ap_p);
  for (int k = 0; k < 3; ++k) {
    item[std::string("AP_") + xyz[k] + "_m"] = p.ap_xyz[k];
    item[std::string("sigma_AP_") + xyz[k] + "_m"] = p.sigma_ap_xyz[k];
  }
  for (int k = 0; k < 3; ++k) {
    item[std::string("AP_") + abc[k] + "_rad"] = p.ap_abc[k];
    item[std::string("sigma_AP_") + abc[k] + "_rad"] = p.sigma_ap_abc[k];
    item[std::string("noise_only_AP_") + abc[k] + "_rad"] = noiseJson(p.noise_ap_abc[static_cast<std::size_t>(k)]);
  }
  item["l_mean_m"] = p.l_mean;
  item["S_l_m"] = p.s_l;
  item["RP_l_m"] = p.rp_l;
  item["noise_only_RP_l_m"] = noiseJson(p.noise_rp_l);
  for (int k = 0; k < 3; ++k) {
    item[std::string("RP_") + abc[k] + "_rad"] = p.rp_abc[k];
    item[std::string("noise_only_RP_") + abc[k] + "_rad"] = noiseJson(p.noise_rp_abc[static_cast<std::size_t>(k)]);
  }
  item["warnings"] = p.warnings;
  return item;
}

Json distanceJson(const mech::DistanceAccuracy& d) {
  Json item{{"from", d.from}, {"to", d.to}, {"cycles", d.cycles}};
  item["D_commanded_m"] = d.d_commanded;
  item["D_mean_m"] = d.d_mean;
  item["AD_p_m"] = d.ad_p;
  item["sigma_AD_p_m"] = d.sigma_ad_p;
  item["noise_only_AD_p_m"] = noiseJson(d.noise_ad_p);
  item["S_D_m"] = d.s_d;
  item["RD_m"] = d.rd;
  item["noise_only_RD_m"] = noiseJson(d.noise_rd);
  item["warnings"] = d.warnings;
  return item;
}

Json lineJson(const mech::LineStraightness& l) {
  Json item{{"line", l.line}, {"points", l.points}};
  item["straightness_rms_m"] = l.rms;
  item["straightness_max_m"] = l.max;
  item["straightness_rms_beyond_noise_m"] = l.rms_beyond_noise;
  item["noise_only_rms_m"] = noiseJson(l.noise_rms);
  item["noise_only_max_m"] = noiseJson(l.noise_max);
  item["warnings"] = l.warnings;
  return item;
}

}  // namespace

Json accuracyFiguresJson(const pipeline::AccuracyResult& result) {
  Json doc;
  doc["pose_components"] = {"x_m", "y_m", "z_m", "a_rad", "b_rad", "c_rad"};
  doc["cycles_used"] = result.cycles_used;
  doc["unmeasured"] = result.unmeasured;
  Json positions = Json::array(), distances = Json::array(), lines = Json::array();
  for (const auto& p : result.positions) positions.push_back(positionJson(p));
  for (const auto& d : result.distances) distances.push_back(distanceJson(d));
  for (const auto& l : result.lines) lines.push_back(lineJson(l));
  doc["positions"] = positions;
  doc["distances"] = distances;
  doc["lines"] = lines;
  return doc;
}

void writeAccuracyJson(const std::filesystem::path& path, const ReportProvenance& provenance,
                       const std::string& model_name, const pipeline::AccuracyResult& result) {
  Json doc = reportHeader("accuracy", provenance);
  doc["model"] = model_name;
  doc["standard"] = "ISO 9283:1998";
  doc.update(accuracyFiguresJson(result));
  writeReportJson(path, doc);
}

}  // namespace mire::app
