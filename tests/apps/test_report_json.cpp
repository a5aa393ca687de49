// report.json beside every report (doc/report-json.md): each command's report.json parsed with
// nlohmann and by Python's json module; its values equal to the last digit those of the
// command's other outputs (camera.yaml, the identified YAML, plan.csv, the CSVs); every
// covariance symmetric with its diagonal = σ²; a second run gives a byte-identical file; a
// failing run, or a report.json path that clashes with an input or an output, writes none.
// One `mire demo --quick` (run twice, for the byte comparison) provides the images, poses and
// joints the other commands read.
#include "commands.hpp"
#include "report_json.hpp"

#include "mire/calibration/camera_io.hpp"
#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/support/csv.hpp"
#include "test_support.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace mire::app {
namespace {

namespace fs = std::filesystem;

Json readJson(const fs::path& path) { return Json::parse(test::readText(path)); }

// mire with `args`; stdout and stderr into `log`. Returns the exit code.
int runMire(const std::string& args, const fs::path& log) {
  return test::runCommand(test::mireBinary().string() + " " + args + " > " + log.string() + " 2>&1");
}

// The double a CSV cell or a YAML scalar holds (the reader's strtod), for exact comparisons.
double parse(const std::string& text) { return std::strtod(text.c_str(), nullptr); }

// Python's json module loads the file (the format is plain JSON: no NaN, no Infinity).
bool pythonLoads(const fs::path& path) {
  return test::runCommand(
             "python3 -c \"import json,sys; json.load(open(sys.argv[1]), parse_constant=lambda c: "
             "sys.exit('non-JSON constant ' + c))\" " +
             path.string()) == 0;
}

// A covariance block {"names", "units", "matrix"}: square, exactly symmetric, diagonal = σ².
void expectCovariance(const Json& covariance, const std::vector<double>& sigma, const std::string& what) {
  const Json& m = covariance.at("matrix");
  ASSERT_EQ(m.size(), covariance.at("names").size()) << what;
  ASSERT_EQ(m.size(), covariance.at("units").size()) << what;
  if (!sigma.empty()) {
    ASSERT_EQ(m.size(), sigma.size()) << what;
  }
  for (std::size_t i = 0; i < m.size(); ++i) {
    ASSERT_EQ(m[i].size(), m.size()) << what;
    for (std::size_t j = 0; j < i; ++j)
      EXPECT_EQ(m[i][j].get<double>(), m[j][i].get<double>()) << what << " " << i << "," << j;
    EXPECT_GE(m[i][i].get<double>(), 0.0) << what;
    if (!sigma.empty()) {
      EXPECT_EQ(std::sqrt(m[i][i].get<double>()), sigma[i]) << what << " " << covariance["names"][i];
    }
  }
}

// Runs `args` twice (the second time after moving the first report.json aside): both succeed
// and their report.json are byte-identical.
void expectDeterministic(const std::string& args, const fs::path& report_json, const fs::path& log) {
  ASSERT_TRUE(fs::exists(report_json));
  const std::string first = test::readText(report_json);
  fs::remove(report_json);
  ASSERT_EQ(runMire(args, log), 0) << test::readText(log);
  EXPECT_TRUE(test::readText(report_json) == first) << report_json << " differs between two identical runs";
}

// The demo's report.json against camera.yaml and identified_D.yaml; `first_json`: the same
// command's report.json from a first run.
void checkDemo(const fs::path& demo, const fs::path& first_json) {
  const fs::path json_path = demo / "report.json";
  EXPECT_TRUE(test::readText(json_path) == test::readText(first_json))
      << "two identical demo runs gave different report.json";
  EXPECT_TRUE(pythonLoads(json_path));
  const Json doc = readJson(json_path);
  EXPECT_EQ(doc.at("report"), "demo");
  EXPECT_EQ(doc.at("provenance").at("mire_version"), versionString());

  // The calibration: camera.yaml's parameters, σ and covariance, to the last digit.
  const calibration::Camera camera = calibration::readCameraYaml(demo / "camera.yaml");
  const Json& calibration = doc.at("calibration");
  ASSERT_EQ(calibration.at("parameters").size(), camera.params.size());
  const std::vector<double> sigma = camera.sigmas();
  for (std::size_t i = 0; i < camera.params.size(); ++i) {
    EXPECT_EQ(calibration["parameters"][i].at("value").get<double>(), camera.params[i]) << i;
    EXPECT_EQ(calibration["parameters"][i].at("sigma").get<double>(), sigma[i]) << i;
  }
  expectCovariance(calibration.at("covariance"), sigma, "demo camera");
  for (Eigen::Index i = 0; i < camera.covariance.rows(); ++i)
    EXPECT_EQ(calibration["covariance"]["matrix"][static_cast<std::size_t>(i)][static_cast<std::size_t>(i)].get<double>(),
              camera.covariance(i, i));

  // Variant D: identified_D.yaml's values and σ, to the last digit.
  const mechanism::ParameterFile yaml = mechanism::readParameterFile(demo / "identified_D.yaml");
  const Json& identified = doc.at("identified");
  std::vector<double> identified_sigma;
  ASSERT_GE(identified.at("parameters").size(), 15u);
  for (const Json& p : identified["parameters"]) {
    const std::string name = p.at("name");
    ASSERT_NE(yaml.find(name), nullptr) << name;
    ASSERT_NE(yaml.find("sigma_" + name), nullptr) << name;
    EXPECT_EQ(p.at("value").get<double>(), yaml.number(*yaml.find(name))) << name;
    EXPECT_EQ(p.at("sigma").get<double>(), yaml.number(*yaml.find("sigma_" + name))) << name;
    identified_sigma.push_back(p["sigma"]);
  }
  expectCovariance(identified.at("covariance"), identified_sigma, "demo variant D");
  EXPECT_EQ(doc.at("variants").size(), 8u);
  EXPECT_EQ(doc.at("pose_counts").size(), 3u);
  EXPECT_EQ(doc.at("run").at("seed"), 2004);
}

void checkIdentify(const fs::path& demo, const fs::path& out) {
  fs::create_directories(out);
  const std::string args = "identify --poses " + (demo / "poses.csv").string() + " --joints " +
                           (demo / "campaign/joints.csv").string() + " --lines " +
                           (demo / "campaign/lines.csv").string() + " -o " + (out / "id.yaml").string() + " --report " +
                           (out / "report").string();
  ASSERT_EQ(runMire(args, out / "log.txt"), 0) << test::readText(out / "log.txt");
  const fs::path json_path = out / "report" / "report.json";
  EXPECT_TRUE(pythonLoads(json_path));
  const Json doc = readJson(json_path);
  EXPECT_EQ(doc.at("report"), "identify");
  EXPECT_EQ(doc.at("model").at("variant"), "D");
  const mechanism::ParameterFile yaml = mechanism::readParameterFile(out / "id.yaml");
  std::map<std::string, double> sigma_of;
  for (const Json& p : doc.at("parameters")) {
    const std::string name = p.at("name");
    ASSERT_NE(yaml.find(name), nullptr) << name;
    EXPECT_EQ(p.at("value").get<double>(), yaml.number(*yaml.find(name))) << name;
    if (p.at("fixed")) continue;
    ASSERT_NE(yaml.find("sigma_" + name), nullptr) << name;
    EXPECT_EQ(p.at("sigma").get<double>(), yaml.number(*yaml.find("sigma_" + name))) << name;
    sigma_of[name] = p["sigma"];
  }
  std::vector<double> sigma;
  for (const Json& name : doc.at("covariance").at("names")) sigma.push_back(sigma_of.at(name));
  expectCovariance(doc["covariance"], sigma, "identify");
  // The named terms' σ add in quadrature to each parameter's (doc/uncertainty.md).
  const Json& terms = doc.at("covariance_terms");
  ASSERT_FALSE(terms.empty());
  EXPECT_EQ(terms[0].at("name"), "fit");
  for (const auto& [name, s] : sigma_of) {
    double sum2 = 0.0;
    for (const Json& term : terms) sum2 += std::pow(term.at("sigma").at(name).get<double>(), 2);
    EXPECT_NEAR(std::sqrt(sum2), s, 1e-9 * s) << name;
  }
  EXPECT_EQ(doc.at("poses").size(), 81u);
  EXPECT_GT(doc.at("fit").at("v3_after_m").get<double>(), 0.0);
  EXPECT_EQ(doc.at("pose_covariances_file"), (demo / "poses_covariance.csv").string());
  expectDeterministic(args, json_path, out / "log.txt");
}

// A failing run writes no report; report.json can be neither -o nor an input.
TEST(ReportJson, IdentifyFailingOrClashingRunsWriteNoReportJson) {
  test::TempDir dir;
  const fs::path out = dir.path();
  const datasets::Campaign campaign = datasets::simulateCampaign("h4-12", 5);
  datasets::writeCampaignFiles(campaign, out, 0, campaign.poses.size());
  fs::create_directories(out / "report");
  const std::string inputs =
      "identify --poses " + (out / "poses.csv").string() + " --joints " + (out / "joints.csv").string();
  EXPECT_EQ(runMire(inputs + " --fix no_such_parameter -o " + (out / "id.yaml").string() + " --report " +
                        (out / "failed").string(),
                    out / "log.txt"),
            1)
      << test::readText(out / "log.txt");
  EXPECT_FALSE(fs::exists(out / "failed"));
  EXPECT_FALSE(fs::exists(out / "id.yaml"));
  // -o is report.json.
  EXPECT_EQ(runMire(inputs + " -o " + (out / "report/report.json").string() + " --report " + (out / "report").string(),
                    out / "log.txt"),
            2);
  EXPECT_NE(test::readText(out / "log.txt").find("would overwrite each other"), std::string::npos)
      << test::readText(out / "log.txt");
  // An input is report.json.
  std::ofstream(out / "report/report.json") << "line_id,q1_rad,q2_rad,q3_rad,q4_rad\n";
  EXPECT_EQ(runMire(inputs + " --lines " + (out / "report/report.json").string() + " -o " + (out / "id.yaml").string() +
                        " --report " + (out / "report").string(),
                    out / "log.txt"),
            2);
  EXPECT_NE(test::readText(out / "log.txt").find("holds the input"), std::string::npos)
      << test::readText(out / "log.txt");
  EXPECT_EQ(test::readText(out / "report/report.json"), "line_id,q1_rad,q2_rad,q3_rad,q4_rad\n");  // untouched
  EXPECT_FALSE(fs::exists(out / "id.yaml"));
}

// --threads 1: with more, Ceres sums the normal equations in thread order and camera.yaml itself
// changes in its last digits from run to run (doc/report-json.md).
void checkCalibrate(const fs::path& demo, const fs::path& out) {
  fs::create_directories(out);
  const std::string args = "calibrate --target " + (demo / "campaign/target.yaml").string() + " --images " +
                           (demo / "campaign/calibration/images").string() + " --model opencv5 --threads 1 -o " +
                           (out / "camera.yaml").string() + " --report " + (out / "report").string();
  ASSERT_EQ(runMire(args, out / "log.txt"), 0) << test::readText(out / "log.txt");
  const fs::path json_path = out / "report" / "report.json";
  EXPECT_TRUE(pythonLoads(json_path));
  const Json doc = readJson(json_path);
  const calibration::Camera camera = calibration::readCameraYaml(out / "camera.yaml");
  const Json& parameters = doc.at("camera").at("parameters");
  ASSERT_EQ(parameters.size(), camera.params.size());
  for (std::size_t i = 0; i < camera.params.size(); ++i) {
    EXPECT_EQ(parameters[i].at("value").get<double>(), camera.params[i]) << i;
    EXPECT_EQ(parameters[i].at("sigma").get<double>(), camera.sigmas()[i]) << i;
  }
  expectCovariance(doc["camera"].at("covariance"), camera.sigmas(), "calibrate");
  EXPECT_EQ(doc["camera"].at("image_width"), camera.width);

  // Every view as views.csv says (10 significant digits there), with its 6×6 pose covariance.
  const support::CsvTable views = support::readCsv(out / "report" / "views.csv");
  const Json& json_views = doc.at("views");
  ASSERT_EQ(json_views.size(), views.rows.size());
  int with_covariance = 0;
  for (std::size_t r = 0; r < views.rows.size(); ++r) {
    const Json& v = json_views[r];
    EXPECT_EQ(v.at("image"), views.rows[r][views.column("image")]);
    for (int k = 0; k < 3; ++k) {
      const std::string t = std::string("t") + "xyz"[k] + "_m", rot = std::string("r") + "xyz"[k] + "_rad";
      EXPECT_EQ(support::formatNumber(v.at("translation_m")[static_cast<std::size_t>(k)], 10),
                views.rows[r][views.column(t)]);
      EXPECT_EQ(support::formatNumber(v.at("rotation_rad")[static_cast<std::size_t>(k)], 10),
                views.rows[r][views.column(rot)]);
    }
    if (v.at("pose_covariance").is_null()) {
      EXPECT_FALSE(v.at("used").get<bool>());
      EXPECT_TRUE(v.contains("pose_covariance_null_reason"));
      continue;
    }
    ++with_covariance;
    EXPECT_EQ(v["pose_covariance"]["matrix"].size(), 6u);
    expectCovariance(v["pose_covariance"], {}, "view " + v["image"].get<std::string>());
  }
  EXPECT_EQ(with_covariance, doc.at("quality").at("views_used").get<int>());
  expectDeterministic(args, json_path, out / "log.txt");
}

TEST(ReportJson, PlanMatchesPlanCsvAndSigmaCsv) {
  test::TempDir dir;
  const fs::path out = dir.path();
  fs::create_directories(out);
  std::ofstream(out / "workspace.yaml")
      << "x_m: [-0.1, 0.1]\ny_m: [-0.1, 0.1]\nz_m: [-0.70, -0.55]\ntheta_deg: [-20, 20]\njoint_margin_deg: 1\n";
  const std::string args = "plan --model h4-12 --workspace " + (out / "workspace.yaml").string() +
                           " --count 15 --candidates 2000 -o " + (out / "plan.csv").string() + " --report " +
                           (out / "report").string();
  ASSERT_EQ(runMire(args, out / "log.txt"), 0) << test::readText(out / "log.txt");
  const fs::path json_path = out / "report" / "report.json";
  EXPECT_TRUE(pythonLoads(json_path));
  const Json doc = readJson(json_path);

  const support::CsvTable plan = support::readCsv(out / "plan.csv");
  const Json& poses = doc.at("poses");
  ASSERT_EQ(poses.size(), plan.rows.size());
  for (std::size_t r = 0; r < plan.rows.size(); ++r) {
    EXPECT_EQ(poses[r].at("pose_id"), plan.rows[r][0]);
    for (const auto& group : {"pose", "joints"})
      for (const auto& item : poses[r].at(group).items())
        EXPECT_EQ(item.value().get<double>(), parse(plan.rows[r][plan.column(item.key())])) << r << " " << item.key();
  }
  const support::CsvTable sigma = support::readCsv(out / "report" / "plan_sigma.csv");
  const Json& parameters = doc.at("parameters");
  ASSERT_EQ(parameters.size(), sigma.rows.size());
  std::vector<double> sigma_plan;
  for (std::size_t r = 0; r < sigma.rows.size(); ++r) {
    EXPECT_EQ(parameters[r].at("name"), sigma.rows[r][0]);
    for (const char* key : {"sigma_plan", "sigma_random", "sigma_all"})  // the CSV has 6 digits
      EXPECT_EQ(support::formatNumber(parameters[r].at(key), 6), sigma.rows[r][sigma.column(key)]) << r << key;
    sigma_plan.push_back(parameters[r]["sigma_plan"]);
  }
  expectCovariance(doc.at("covariance_plan"), sigma_plan, "plan");
  expectDeterministic(args, json_path, out / "log.txt");
}

void checkSelect(const fs::path& demo, const fs::path& out) {
  fs::create_directories(out);
  const std::string args = "select --poses " + (demo / "poses.csv").string() + " --joints " +
                           (demo / "campaign/joints.csv").string() + " --models h4-12:C,D --folds 3 --report " +
                           (out / "report").string();
  ASSERT_EQ(runMire(args, out / "log.txt"), 0) << test::readText(out / "log.txt");
  const fs::path json_path = out / "report" / "report.json";
  EXPECT_TRUE(pythonLoads(json_path));
  const Json doc = readJson(json_path);
  const support::CsvTable scores = support::readCsv(out / "report" / "select_scores.csv");
  ASSERT_EQ(doc.at("scores").size(), scores.rows.size());
  for (std::size_t r = 0; r < scores.rows.size(); ++r) {
    const Json& s = doc["scores"][r];
    EXPECT_EQ(s.at("label"), scores.rows[r][0]);
    for (const char* key : {"cv_rms", "cv_rms_se", "fit_rms", "aic", "bic"})  // the CSV has 8 digits
      EXPECT_EQ(support::formatNumber(s.at(key), 8), scores.rows[r][scores.column(key)]) << key;
    EXPECT_EQ(support::formatNumber(s.at("condition"), 6), scores.rows[r][scores.column("condition")]);
    // No --lines: V3 is null, with its reason beside it (JSON has no NaN).
    EXPECT_TRUE(s.at("v3_m").is_null());
    EXPECT_NE(s.at("v3_m_null_reason").get<std::string>().find("--lines"), std::string::npos);
    EXPECT_EQ(scores.rows[r][scores.column("recommended")] == "1", s["label"] == doc.at("recommended"));
  }
  const std::string log = test::readText(out / "log.txt");
  EXPECT_NE(log.find("recommended: " + doc["recommended"].get<std::string>()), std::string::npos) << log;
  expectDeterministic(args, json_path, out / "log.txt");
}

// One `mire demo --quick` (about 7 s of CPU), run twice: its report.json must not change; its
// images, poses and joints then feed identify, calibrate and select (one test, so that ctest's
// one process per test runs the demo once).
TEST(ReportJson, DemoAndTheCommandsOnItsFiles) {
  test::TempDir dir;
  const fs::path demo = dir.path() / "demo";
  ASSERT_EQ(runMire("demo --quick -o " + demo.string(), dir.path() / "demo.log"), 0)
      << test::readText(dir.path() / "demo.log");
  fs::copy_file(demo / "report.json", dir.path() / "demo_first.json");
  ASSERT_EQ(runMire("demo --quick -o " + demo.string(), dir.path() / "demo.log"), 0)
      << test::readText(dir.path() / "demo.log");
  {
    SCOPED_TRACE("demo");
    checkDemo(demo, dir.path() / "demo_first.json");
  }
  for (const auto& [name, check] : {std::pair{"identify", &checkIdentify}, std::pair{"calibrate", &checkCalibrate},
                                    std::pair{"select", &checkSelect}}) {
    SCOPED_TRACE(name);
    fs::create_directories(dir.path() / name);
    check(demo, dir.path() / name);
  }
}

// The demo's output folder is checked before the simulation: a file there is refused, untouched.
TEST(ReportJsonDemo, OutputThatIsAFileIsRefusedBeforeAnyWork) {
  test::TempDir dir;
  std::ofstream(dir.path() / "report.json") << "{}";
  EXPECT_EQ(runMire("demo --quick -o " + (dir.path() / "report.json").string(), dir.path() / "log.txt"), 1);
  EXPECT_NE(test::readText(dir.path() / "log.txt").find("exists and is not a folder"), std::string::npos);
  EXPECT_EQ(test::readText(dir.path() / "report.json"), "{}");
}

// The policy for non-finite numbers: null plus a reason when the writer knows why; any other
// NaN or Inf fails the report, and nothing is written.
TEST(ReportJsonPolicy, NonFiniteIsNullWithReasonOrFailsTheReport) {
  Json object;
  setNumber(object, "v3_m", NAN, "no --lines given");
  setNumber(object, "sigma", std::numeric_limits<double>::infinity(), "no information");
  setNumber(object, "rms", 0.1, "unused");
  EXPECT_TRUE(object["v3_m"].is_null());
  EXPECT_EQ(object["v3_m_null_reason"], "no --lines given");
  EXPECT_TRUE(object["sigma"].is_null());
  EXPECT_EQ(object["rms"].get<double>(), 0.1);
  EXPECT_FALSE(object.contains("rms_null_reason"));
  EXPECT_THROW(numberArray(std::vector<double>{1.0, NAN}), std::logic_error);
  EXPECT_THROW(matrixJson(Eigen::MatrixXd::Constant(2, 2, std::numeric_limits<double>::infinity())), std::logic_error);

  test::TempDir dir;
  writeReportJson(dir.path() / "ok.json", object);
  EXPECT_EQ(Json::parse(test::readText(dir.path() / "ok.json")), object);
  EXPECT_TRUE(pythonLoads(dir.path() / "ok.json"));
  Json bad{{"values", {{"x", 1.0}}}};
  bad["values"]["x"] = NAN;  // bypassing setNumber
  try {
    writeReportJson(dir.path() / "bad.json", bad);
    ADD_FAILURE() << "a NaN was written";
  } catch (const std::logic_error& error) {
    EXPECT_NE(std::string(error.what()).find("/values/x"), std::string::npos) << error.what();
  }
  EXPECT_FALSE(fs::exists(dir.path() / "bad.json"));
  // Full precision: the shortest decimal that reads back to the same double.
  const double third = 1.0 / 3.0;
  EXPECT_EQ(Json::parse(Json(third).dump()).get<double>(), third);
  EXPECT_EQ(std::strtod(Json(third).dump().c_str(), nullptr), third);
}

}  // namespace
}  // namespace mire::app
