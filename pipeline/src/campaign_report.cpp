// A campaign's report from the files its commands wrote (campaign_report.hpp).
#include "mire/pipeline/campaign_report.hpp"

#include "mire/mechanism/parameter_set.hpp"
#include "mire/mechanism/registry.hpp"
#include "mire/report/figure.hpp"
#include "mire/report/html.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <stdexcept>

namespace mire::pipeline {
namespace {

namespace fs = std::filesystem;
namespace rp = mire::report;
namespace mech = mire::mechanism;
using Json = nlohmann::json;

constexpr double kDegPerRad = 180.0 / 3.14159265358979323846;

// The chain's order; anything else after it.
int stageRank(const std::string& kind) {
  static const std::vector<std::string> order{"calibrate", "measure",    "plan",     "select",
                                              "identify",  "compensate", "accuracy", "demo"};
  const auto it = std::find(order.begin(), order.end(), kind);
  return it == order.end() ? static_cast<int>(order.size()) : static_cast<int>(it - order.begin());
}

Json readJson(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot be read");
  try {
    return Json::parse(in);
  } catch (const Json::parse_error& error) {
    throw std::runtime_error(path.string() + ": not JSON (" + error.what() + ")");
  }
}

std::string format(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

// A number of the file, NaN when absent or null (the writer's "<key>_null_reason" says why).
double number(const Json& object, const std::string& key) {
  const auto it = object.find(key);
  return it != object.end() && it->is_number() ? it->get<double>() : std::nan("");
}

std::string text(const Json& object, const std::string& key) {
  const auto it = object.find(key);
  return it != object.end() && it->is_string() ? it->get<std::string>() : std::string();
}

// SI value and σ in the unit a reader expects: m → mm, rad → deg.
std::pair<double, std::string> displayScale(const std::string& si_unit) {
  if (si_unit == "m") return {1e3, "mm"};
  if (si_unit == "rad") return {kDegPerRad, "deg"};
  return {1.0, si_unit == "1" ? "" : si_unit};
}

std::vector<rp::ResultRow> parameterRows(const Json& parameters) {
  std::vector<rp::ResultRow> rows;
  for (const Json& p : parameters) {
    const auto [scale, unit] = displayScale(text(p, "unit"));
    const bool fixed = p.value("fixed", false);
    rows.push_back({text(p, "name"), unit, scale * number(p, "value"), fixed ? 0.0 : scale * number(p, "sigma"),
                    fixed ? "fixed" : ""});
  }
  return rows;
}

// Shell-quoted as a reader would type it.
std::string commandLine(const Json& provenance) {
  std::string out;
  for (const Json& word : provenance.value("command_line", Json::array())) {
    const std::string w = word.is_string() ? word.get<std::string>() : std::string();
    const bool plain = !w.empty() && w.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                         "0123456789-_=./,:+@%") == std::string::npos;
    std::string quoted = w;
    if (!plain) {
      quoted = "'";
      for (const char c : w) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
      quoted += "'";
    }
    out += (out.empty() ? "" : " ") + quoted;
  }
  return out;
}

void addCalibrate(rp::HtmlReport& page, const Json& doc) {
  const Json& quality = doc.value("quality", Json::object());
  const Json& projection = quality.value("projection_uncertainty", Json::object());
  page.paragraph(std::to_string(quality.value("views_used", 0)) + " views used, reprojection RMS " +
                 format("%.3f", number(quality, "rms_px")) + " px; projection uncertainty " +
                 format("%.3f", number(projection, "centre_px")) + " px at the centre, " +
                 format("%.3f", number(projection, "corner_px")) + " px at the corner.");
  page.results(parameterRows(doc.value("camera", Json::object()).value("parameters", Json::array())));
}

void addMeasure(rp::HtmlReport& page, const Json& doc) {
  const Json t = doc.value("median_sigma_translation_mm", Json::array());
  const Json r = doc.value("median_sigma_rotation_deg", Json::array());
  std::vector<std::string> row{"median \xCF\x83"};
  for (const Json& v : t) row.push_back(v.is_number() ? format("%.4f", v.get<double>()) : "n/a");
  for (const Json& v : r) row.push_back(v.is_number() ? format("%.5f", v.get<double>()) : "n/a");
  page.paragraph(std::to_string(doc.value("poses_measured", 0)) + " poses measured, " +
                 std::to_string(doc.value("poses_failed", Json::array()).size()) + " failed; median reprojection RMS " +
                 format("%.3f", number(doc, "median_rms_px")) + " px.");
  page.table({"", "tx (mm)", "ty (mm)", "tz (mm)", "rx (deg)", "ry (deg)", "rz (deg)"}, {row});
}

// identify's joint residual in the model's display unit (report.json keeps SI and does not name
// the unit): the unit of the registered or described model's joints when they share one.
std::string jointResidualText(const std::string& model_name, double rms_si) {
  try {
    const std::vector<mech::Unit> units = mech::makeRegisteredModel(model_name).mechanism->jointUnits();
    if (!units.empty() && std::all_of(units.begin(), units.end(), [&](mech::Unit u) { return u == units[0]; }))
      return format("%.4g", mech::toDisplay(units[0], rms_si)) + " " + mech::displayUnitName(units[0]);
  } catch (const std::exception&) {
    // A description file no longer where identify read it: the SI value, said so.
  }
  return format("%.4g", rms_si) + " (joint unit, SI)";
}

void addIdentify(rp::HtmlReport& page, const Json& doc) {
  const Json& fit = doc.value("fit", Json::object());
  const Json& model = doc.value("model", Json::object());
  std::string line = "Model " + text(model, "name") + ": " + std::to_string(fit.value("free_parameters", 0)) +
                     " free parameters from " + std::to_string(fit.value("poses", 0)) +
                     " poses, \xCF\x87\xC2\xB2/dof " + format("%.3g", number(fit, "chi2_per_dof")) +
                     ", joint residual RMS " + jointResidualText(text(model, "name"), number(fit, "rms_joint_residual"));
  if (std::isfinite(number(fit, "v3_after_m")))
    line += ", straightness V3 " + format("%.4f", 1e3 * number(fit, "v3_before_m")) + " \xE2\x86\x92 " +
            format("%.4f", 1e3 * number(fit, "v3_after_m")) + " mm";
  page.paragraph(line + ".");
  std::vector<rp::ResultRow> rows;
  for (const rp::ResultRow& row : parameterRows(doc.value("parameters", Json::array())))
    if (row.note.empty()) rows.push_back(row);  // the free ones; the fixed are in the stage's page
  page.results(rows);
}

void addSelect(rp::HtmlReport& page, const Json& doc) {
  std::vector<std::vector<std::string>> rows;
  const auto [scale, unit] = displayScale(text(doc, "score_unit"));
  for (const Json& s : doc.value("scores", Json::array()))
    rows.push_back({text(s, "label"), std::to_string(s.value("parameters", 0)),
                    rp::withSigma(scale * number(s, "cv_rms"), scale * number(s, "cv_rms_se"), 5)});
  page.paragraph("Recommended: " + text(doc, "recommended") + " (" + std::to_string(doc.value("folds", 0)) +
                 "-fold cross-validation, the simplest within one standard error of the best).");
  page.table({"candidate", "parameters", "CV joint residual RMS \xC2\xB1 SE (" + unit + ")"}, rows);
}

void addPlan(rp::HtmlReport& page, const Json& doc) {
  page.paragraph(std::to_string(doc.value("count", 0)) + " poses planned for " + text(doc, "model") + " (" +
                 text(doc, "criterion") + "-optimal) from " + std::to_string(doc.value("candidates", 0)) +
                 " candidates.");
}

void addCompensate(rp::HtmlReport& page, const Json& doc) {
  std::string line = "Mode " + text(doc, "mode") + ", " + text(doc, "output") + " written";
  if (!doc.contains("controller_fit"))
    line += ": " + std::to_string(doc.value("rows_written", 0)) + " rows, " +
            std::to_string(doc.value("left_out", Json::array()).size()) + " left out";
  line += ".";
  if (doc.contains("controller_fit")) {
    const Json& c = doc["controller_fit"];
    line += " Controller " + text(c, "model") + ": residual error RMS " +
            format("%.4f", 1e3 * number(c, "rms_position_error_m")) + " mm; expected on the robot " +
            rp::withSigma(1e3 * number(c, "expected_rms_position_error_m"),
                          1e3 * number(c, "sigma_rms_position_error_m"), 4) +
            " mm.";
  }
  page.paragraph(line);
  std::vector<std::vector<std::string>> rows;
  for (const Json& c : doc.value("components", Json::array())) {
    const auto [scale, unit] = displayScale(text(c, "unit"));
    rows.push_back({text(c, "name"), unit, format("%.4g", scale * number(c, "sigma_rms")),
                    format("%.4g", scale * number(c, "sigma_max"))});
  }
  if (!rows.empty()) page.table({"command component", "unit", "\xCF\x83 RMS", "\xCF\x83 max"}, rows);
}

// AP_p ± σ per position beside the noise-only p95, and RP_l, in mm.
rp::Figure accuracyFigure(const Json& positions) {
  rp::Panel ap, rpl;
  ap.title =
      "pose accuracy (\xC2\xB1"
      "1\xCF\x83)",
  rpl.title = "pose repeatability";
  ap.x = rpl.x = rp::makeAxis("position", "");
  ap.y = rp::makeAxis("AP_p", "mm"), rpl.y = rp::makeAxis("RP_l", "mm");
  ap.y.include_zero = rpl.y.include_zero = true;
  rp::Series ap_bars, rp_bars, ap_noise, rp_noise;
  ap_bars.label = "measured", ap_bars.mark = rp_bars.mark = rp::Mark::bars;
  ap_noise.label = "noise-only p95", ap_noise.mark = rp_noise.mark = rp::Mark::points;
  ap_noise.colour = rp_noise.colour = "#555555";
  ap_bars.colour = rp_bars.colour = "#1f77b4";
  double k = 0.0;
  for (const Json& p : positions) {
    ap.categories.push_back(text(p, "position")), rpl.categories.push_back(text(p, "position"));
    ap_bars.x.push_back(k), rp_bars.x.push_back(k), ap_noise.x.push_back(k), rp_noise.x.push_back(k);
    ap_bars.y.push_back(1e3 * number(p, "AP_p_m"));
    ap_bars.sigma.push_back(1e3 * number(p, "sigma_AP_p_m"));
    rp_bars.y.push_back(1e3 * number(p, "RP_l_m"));
    ap_noise.y.push_back(1e3 * number(p.value("noise_only_AP_p_m", Json::object()), "p95"));
    rp_noise.y.push_back(1e3 * number(p.value("noise_only_RP_l_m", Json::object()), "p95"));
    k += 1.0;
  }
  ap.series = {ap_bars, ap_noise}, rpl.series = {rp_bars, rp_noise};
  rp::Figure figure;
  figure.columns = 2;
  figure.panel_width = 390.0, figure.panel_height = 290.0;
  figure.panels = {ap, rpl};
  return figure;
}

void addAccuracy(rp::HtmlReport& page, const Json& doc) {
  const Json positions = doc.value("positions", Json::array());
  double sum = 0.0, variance = 0.0;
  for (const Json& p : positions) sum += number(p, "AP_p_m"), variance += std::pow(number(p, "sigma_AP_p_m"), 2);
  const double n = static_cast<double>(std::max<std::size_t>(1, positions.size()));
  page.paragraph("ISO 9283 with model " + text(doc, "model") + ", " + std::to_string(doc.value("cycles_used", 0)) +
                 " measured cycles at " + std::to_string(positions.size()) + " positions: mean AP_p " +
                 rp::withSigma(1e3 * sum / n, 1e3 * std::sqrt(variance) / n, 3) + " mm.");
  if (!positions.empty())
    page.figure(accuracyFigure(positions),
                "AP_p with its \xC2\xB1"
                "1\xCF\x83 error bar and RP_l per position; the dots are what the camera's "
                "noise alone would show (95th percentile).");
}

void addDemo(rp::HtmlReport& page, const Json& doc) {
  const Json& run = doc.value("run", Json::object());
  page.paragraph("A demo run (seed " + std::to_string(run.value("seed", 0)) +
                 "): its own report.html holds "
                 "the calibration, the measurement and the identification against the simulator's truth.");
}

void addStage(rp::HtmlReport& page, const std::string& kind, const Json& doc) {
  if (kind == "calibrate") addCalibrate(page, doc);
  if (kind == "measure") addMeasure(page, doc);
  if (kind == "plan") addPlan(page, doc);
  if (kind == "select") addSelect(page, doc);
  if (kind == "identify") addIdentify(page, doc);
  if (kind == "compensate") addCompensate(page, doc);
  if (kind == "accuracy") addAccuracy(page, doc);
  if (kind == "demo") addDemo(page, doc);
}

std::string title(const std::string& kind) {
  static const std::map<std::string, std::string> titles{
      {"calibrate", "Camera calibration"}, {"measure", "Pose measurement"},
      {"plan", "Experiment plan"},         {"select", "Model selection"},
      {"identify", "Identification"},      {"compensate", "Compensation"},
      {"accuracy", "Accuracy (ISO 9283)"}, {"demo", "Demo"}};
  const auto it = titles.find(kind);
  return it == titles.end() ? kind : it->second;
}

// The input as named on the command line, resolved against the working folder, then the campaign.
fs::path resolveInput(const std::string& path, const fs::path& campaign) {
  const fs::path p(path);
  if (p.is_absolute() || fs::exists(p)) return p;
  return fs::exists(campaign / p) ? campaign / p : p;
}

}  // namespace

std::vector<CampaignStageFile> findCampaignReports(const fs::path& campaign) {
  if (!fs::is_directory(campaign)) throw std::runtime_error(campaign.string() + ": not a folder");
  std::vector<CampaignStageFile> out;
  for (const auto& entry : fs::recursive_directory_iterator(campaign)) {
    if (!entry.is_regular_file()) continue;
    const std::string name = entry.path().filename().string();
    if (name != "report.json" && name != "accuracy.json") continue;
    const Json doc = readJson(entry.path());
    if (!doc.is_object() || text(doc, "format").rfind("mire report.json", 0) != 0) continue;  // not mire's
    const fs::path html = entry.path().parent_path() / "report.html";
    out.push_back({text(doc, "report"), entry.path(), name == "report.json" && fs::exists(html) ? html : fs::path()});
  }
  if (out.empty())
    throw std::runtime_error(campaign.string() +
                             ": no report.json or accuracy.json under it (run the commands with --report DIR, "
                             "accuracy with -o FILE.json, inside the campaign folder)");
  std::sort(out.begin(), out.end(), [](const CampaignStageFile& a, const CampaignStageFile& b) {
    const int ra = stageRank(a.kind), rb = stageRank(b.kind);
    return ra != rb ? ra < rb : a.file < b.file;
  });
  return out;
}

CampaignReport assembleCampaignReport(const fs::path& campaign, const fs::path& output_dir,
                                      const std::string& command_line, const std::string& version) {
  CampaignReport report;
  report.stages = findCampaignReports(campaign);
  rp::HtmlReport page("Campaign report: " + campaign.filename().string());
  std::string chain;
  for (const auto& stage : report.stages) chain += (chain.empty() ? "" : " \xE2\x86\x92 ") + stage.kind;
  std::vector<std::pair<std::string, Json>> docs;
  for (const auto& stage : report.stages) docs.emplace_back(stage.kind, readJson(stage.file));
  std::string lead = "Campaign " + campaign.string() + ": " + chain + ".";
  for (const auto& [kind, doc] : docs)
    if (kind == "accuracy") {
      double sum = 0.0, variance = 0.0;
      const Json positions = doc.value("positions", Json::array());
      for (const Json& p : positions) sum += number(p, "AP_p_m"), variance += std::pow(number(p, "sigma_AP_p_m"), 2);
      const double n = static_cast<double>(std::max<std::size_t>(1, positions.size()));
      lead += " Accuracy (" + text(doc, "model") + "): mean AP_p " +
              rp::withSigma(1e3 * sum / n, 1e3 * std::sqrt(variance) / n, 3) + " mm.";
    }
  page.lead(lead);
  std::vector<rp::InputFile> inputs;
  std::string commands;
  for (std::size_t i = 0; i < report.stages.size(); ++i) {
    const auto& stage = report.stages[i];
    const Json& doc = docs[i].second;
    page.section(std::to_string(i + 1) + ". " + title(stage.kind));
    addStage(page, stage.kind, doc);
    const fs::path from = fs::relative(stage.file, output_dir);
    if (!stage.html.empty())
      page.link("From " + from.string() + "; the stage's full report:", fs::relative(stage.html, output_dir).string(),
                fs::relative(stage.html, output_dir).generic_string());
    else
      page.paragraph("From " + from.string() + ".");
    const Json& provenance = doc.value("provenance", Json::object());
    commands +=
        "# " + stage.kind + " (mire " + text(provenance, "mire_version") + ")\n" + commandLine(provenance) + "\n";
    for (const Json& input : provenance.value("inputs", Json::array()))
      inputs.push_back({resolveInput(text(input, "path"), campaign), stage.kind + " " + text(input, "role")});
  }
  page.section("Provenance");
  page.paragraph(
      "The command lines as each report file recorded them, then every input they name with its "
      "SHA-256 now (" +
      command_line + ", " + version + ").");
  page.preformatted(commands);
  page.inputTable(inputs);
  report.html = page.html();
  return report;
}

}  // namespace mire::pipeline
