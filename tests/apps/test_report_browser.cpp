// report.html in a real browser (headless Chromium, Debian's `chromium`): each page type is
// opened offline, must log nothing to the console, must lay out every figure with drawn data
// (checked by the browser's own geometry, getBBox, on a copy of the page with a probe script),
// and must print to a PDF of at most 12 A4 pages. The screenshots and PDFs are kept under the
// build folder (report-screenshots/) for a person to look at. Skips when chromium is absent.
#include <gtest/gtest.h>

#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/metrology/target.hpp"
#include "mire/report/sha256.hpp"
#include "mire/support/atomic_file.hpp"
#include "test_support.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace mire::app {
namespace {

namespace fs = std::filesystem;

const fs::path kOpenCvSamples = "/usr/share/doc/opencv-doc/examples/data";

bool haveChromium() { return test::runCommand("command -v chromium > /dev/null 2>&1") == 0; }

fs::path artifactDir() {
  const fs::path dir = test::mireBinary().parent_path().parent_path() / "report-screenshots";
  fs::create_directories(dir);
  return dir;
}

// chromium --headless with a throw-away profile; returns stdout, the log (stderr) in `log`.
std::string chromium(const test::TempDir& dir, const std::string& arguments, std::string* log = nullptr) {
  const fs::path out = dir.path() / "chromium.out", err = dir.path() / "chromium.err";
  const std::string command =
      "timeout 120 chromium --headless --no-sandbox --disable-gpu --hide-scrollbars "
      "--no-first-run --user-data-dir=" +
      (dir.path() / "profile").string() + " --enable-logging=stderr --v=0 " + arguments + " > " + out.string() +
      " 2> " + err.string();
  EXPECT_EQ(test::runCommand(command), 0) << test::readText(err);
  if (log) *log = test::readText(err);
  return test::readText(out);
}

// The page's own console messages (the page has no script: any message is an error, e.g. a
// resource it failed to load).
std::vector<std::string> consoleLines(const std::string& log) {
  std::vector<std::string> lines;
  std::istringstream in(log);
  for (std::string line; std::getline(in, line);)
    if (line.find(":CONSOLE") != std::string::npos) lines.push_back(line);
  return lines;
}

// A copy of the page with a probe that writes, per figure, its laid-out size and how many data
// marks (points, bars, vectors, cells, lines, bands) have a non-empty box.
constexpr const char* kProbe = R"(<script>
const out = [];
document.querySelectorAll('figure svg').forEach((svg, i) => {
  const r = svg.getBoundingClientRect();
  let drawn = 0;
  svg.querySelectorAll('.point,.bar,.vector,.cell,.series-line,.band').forEach(e => {
    const b = e.getBBox(); if (b.width + b.height > 0) drawn++; });
  out.push((i + 1) + ' ' + Math.round(r.width) + ' ' + Math.round(r.height) + ' ' + drawn);
});
const p = document.createElement('pre'); p.id = 'mire-probe'; p.textContent = out.join(';');
document.body.appendChild(p);
</script>)";

struct FigureProbe {
  int width = 0, height = 0, drawn = 0;
};

std::vector<FigureProbe> probeFigures(const test::TempDir& dir, const fs::path& html) {
  std::string page = test::readText(html);
  const auto end = page.rfind("</body>");
  EXPECT_NE(end, std::string::npos);
  page.insert(end, kProbe);
  const fs::path probe = dir.path() / "probe.html";
  test::writeText(probe, page);
  const std::string dom = chromium(dir, "--dump-dom file://" + probe.string());
  std::smatch match;
  std::vector<FigureProbe> figures;
  if (!std::regex_search(dom, match, std::regex("<pre id=\"mire-probe\">([^<]*)</pre>"))) {
    ADD_FAILURE() << "the probe did not run";
    return figures;
  }
  std::istringstream in(match[1].str());
  for (std::string entry; std::getline(in, entry, ';');) {
    std::istringstream fields(entry);
    int index = 0;
    FigureProbe f;
    fields >> index >> f.width >> f.height >> f.drawn;
    figures.push_back(f);
  }
  return figures;
}

int pdfPages(const fs::path& pdf) {
  const std::string bytes = test::readText(pdf);
  const std::regex page("/Type\\s*/Page[^s]");
  return static_cast<int>(std::distance(std::sregex_iterator(bytes.begin(), bytes.end(), page), std::sregex_iterator()));
}

// Opens `html` as a reader would and keeps the evidence as `name`.png / .pdf.
void checkInBrowser(const test::TempDir& dir, const fs::path& html, const std::string& name, int expected_figures) {
  ASSERT_TRUE(fs::exists(html));
  const fs::path screenshot = artifactDir() / (name + ".png"), pdf = artifactDir() / (name + ".pdf");
  std::string log;
  chromium(dir, "--window-size=1000,4200 --screenshot=" + screenshot.string() + " file://" + html.string(), &log);
  EXPECT_TRUE(consoleLines(log).empty()) << consoleLines(log).front();
  const cv::Mat image = cv::imread(screenshot.string(), cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(image.empty()) << screenshot;
  const double inked = static_cast<double>(cv::countNonZero(image < 200)) / static_cast<double>(image.total());
  // A blank page inks nothing; the shortest page (measure's: one figure, two tables) inks 1.5 % of
  // the 1000 × 4200 window.
  EXPECT_GT(inked, 0.01) << "a blank page: " << screenshot;

  const auto figures = probeFigures(dir, html);
  EXPECT_EQ(static_cast<int>(figures.size()), expected_figures);
  for (std::size_t k = 0; k < figures.size(); ++k) {
    EXPECT_GT(figures[k].width, 300) << "figure " << k + 1;
    EXPECT_GT(figures[k].height, 150) << "figure " << k + 1;
    EXPECT_GT(figures[k].drawn, 0) << "figure " << k + 1 << " is empty";
  }

  chromium(dir, "--no-pdf-header-footer --print-to-pdf=" + pdf.string() + " file://" + html.string());
  const int pages = pdfPages(pdf);
  std::printf("%s: %zu figures, %d PDF pages (A4), %.1f %% of the screenshot inked; %s\n", name.c_str(), figures.size(),
              pages, 100.0 * inked, screenshot.c_str());
  EXPECT_GE(pages, 1);
  EXPECT_LE(pages, 12);
}

TEST(ReportBrowser, CalibrateOnOpenCvPhotos) {
  if (!haveChromium()) GTEST_SKIP() << "needs chromium (Debian package chromium) for the browser check: skipped";
  if (!fs::exists(kOpenCvSamples / "left01.jpg"))
    GTEST_SKIP() << "needs OpenCV's left*.jpg (Debian opencv-doc, " << kOpenCvSamples << "): absent, skipped";
  test::TempDir dir;
  fs::create_directories(dir.path() / "images");
  for (const auto& entry : fs::directory_iterator(kOpenCvSamples)) {
    const std::string name = entry.path().filename().string();
    if (std::regex_match(name, std::regex("left[0-9]+\\.jpg")))
      fs::copy_file(entry.path(), dir.path() / "images" / name);
  }
  metrology::TargetSpec spec;
  spec.cols = 9, spec.rows = 6, spec.square_size_m = 0.025;
  support::writeFileAtomically(dir.path() / "target.yaml", metrology::Target(spec).yamlString());
  const fs::path d = dir.path();
  ASSERT_EQ(test::runMireIn(dir, "calibrate --target " + (d / "target.yaml").string() + " --images " +
                                     (d / "images").string() + " -o " + (d / "camera.yaml").string() + " --report " +
                                     (d / "report").string()),
            0)
      << test::readText(d / "stderr.txt") << test::readText(d / "stdout.txt");
  const std::string html = test::readText(d / "report" / "report.html");
  EXPECT_NE(html.find("fx = "), std::string::npos);
  checkInBrowser(dir, d / "report" / "report.html", "calibrate-opencv-left", 4);
}

// identify on a simulated campaign of `mechanism` (no images: poses.csv with its σ columns).
void identifyReport(const std::string& mechanism, unsigned seed, int legs) {
  if (!haveChromium()) GTEST_SKIP() << "needs chromium (Debian package chromium) for the browser check: skipped";
  test::TempDir dir;
  const fs::path d = dir.path();
  const datasets::Campaign c = datasets::simulateCampaign(mechanism, seed);
  datasets::writeCampaignFiles(c, d, 0, c.poses.size());
  ASSERT_EQ(test::runMireIn(dir, "identify --model " + mechanism + " --poses " + (d / "poses.csv").string() +
                                     " --joints " + (d / "joints.csv").string() + " -o " + (d / "id.yaml").string() +
                                     " --mc 20 --mc-repeats 8 --report " + (d / "report").string()),
            0)
      << test::readText(d / "stderr.txt");
  const std::string html = test::readText(d / "report" / "report.html");
  // One residual panel per leg of the mechanism, before and after: no "leg N+1".
  EXPECT_NE(html.find(">leg " + std::to_string(legs) + "<"), std::string::npos);
  EXPECT_EQ(html.find(">leg " + std::to_string(legs + 1) + "<"), std::string::npos);
  checkInBrowser(dir, d / "report" / "report.html", "identify-" + mechanism, 4);
}

// The demos' pages (`--quick`): calibration, measurement, identification against the truth and
// the closed loop, each figure with its uncertainty.
void demoReport(const std::string& mechanism, int figures) {
  if (!haveChromium()) GTEST_SKIP() << "needs chromium (Debian package chromium) for the browser check: skipped";
  test::TempDir dir;
  const fs::path out = dir.path() / "demo";
  ASSERT_EQ(test::runMireIn(dir, "demo --quick" + (mechanism == "h4" ? std::string() : " --mechanism " + mechanism) +
                                     " -o " + out.string()),
            0)
      << test::readText(dir.path() / "stderr.txt");
  const std::string html = test::readText(out / "report.html");
  EXPECT_NE(html.find("class=\"lead\""), std::string::npos);
  checkInBrowser(dir, out / "report.html", "demo-" + mechanism, figures);
}

TEST(ReportBrowser, DemoH4) { demoReport("h4", 6); }
TEST(ReportBrowser, DemoDelta) { demoReport("delta", 4); }
TEST(ReportBrowser, DemoGoughStewart) { demoReport("gough-stewart", 4); }

// A whole campaign as a user runs it on `mire simulate campaign`'s Delta: every command with
// --report, then `mire report` over the folder; each page type in the browser.
TEST(ReportBrowser, CampaignOfEveryCommand) {
  if (!haveChromium()) GTEST_SKIP() << "needs chromium (Debian package chromium) for the browser check: skipped";
  test::TempDir dir;
  const fs::path c = dir.path() / "campaign";
  const auto run = [&](const std::string& args) {
    const int code = test::runMireIn(dir, args);
    EXPECT_EQ(code, 0) << args << "\n" << test::readText(dir.path() / "stderr.txt");
    return code == 0;
  };
  ASSERT_TRUE(
      run("simulate campaign --mechanism delta --seed 5 --images-per-pose 2 --calibration-views 12 -o " + c.string()));
  const std::string cs = c.string();
  ASSERT_TRUE(run("calibrate --target " + cs + "/target.yaml --images " + cs + "/calibration/images -o " + cs +
                  "/camera.yaml --report " + cs + "/reports/calibrate"));
  ASSERT_TRUE(run("measure --camera " + cs + "/camera.yaml --target " + cs + "/target.yaml --poses " + cs +
                  "/poses -o " + cs + "/poses.csv --report " + cs + "/reports/measure"));
  test::writeText(c / "workspace.yaml", "x_m: [-0.1, 0.1]\ny_m: [-0.1, 0.1]\nz_m: [-0.72, -0.58]\n");
  ASSERT_TRUE(run("plan --model delta --workspace " + cs + "/workspace.yaml --count 12 --candidates 300 -o " + cs +
                  "/plan.csv --report " + cs + "/reports/plan"));
  ASSERT_TRUE(run("select --poses " + cs + "/poses.csv --joints " + cs + "/joints.csv --models delta,delta-legs " +
                  "--report " + cs + "/reports/select"));
  ASSERT_TRUE(run("identify --model delta-legs --poses " + cs + "/poses.csv --joints " + cs + "/joints.csv --lines " +
                  cs + "/lines.csv -o " + cs + "/identified.yaml --report " + cs + "/reports/identify"));
  ASSERT_TRUE(run("compensate --params " + cs +
                  "/identified.yaml --controller-model delta --workspace "
                  "-0.08,0.08,-0.08,0.08,-0.70,-0.60 -o " +
                  cs + "/controller.yaml --report " + cs + "/reports/compensate"));
  ASSERT_TRUE(run("accuracy --params " + cs + "/truth/iso9283.yaml --commanded " + cs + "/iso9283/commanded.csv " +
                  "--poses " + cs + "/iso9283/poses.csv -o " + cs + "/accuracy.json --report " + cs +
                  "/reports/accuracy"));
  // The terminal leads with the result and its uncertainty.
  EXPECT_EQ(test::readText(dir.path() / "stdout.txt").rfind("pose accuracy AP_p ", 0), 0u);
  ASSERT_TRUE(run("report " + cs));
  const std::string page = test::readText(c / "campaign_report.html");
  for (const char* stage : {"Camera calibration", "Pose measurement", "Experiment plan", "Model selection",
                            "Identification", "Compensation", "Accuracy (ISO 9283)"})
    EXPECT_NE(page.find(stage), std::string::npos) << stage;
  // The inputs' checksums: the camera file calibrate wrote and measure read.
  EXPECT_NE(page.find(report::sha256File(c / "camera.yaml")), std::string::npos);
  EXPECT_NE(page.find("href=\"reports/identify/report.html\""), std::string::npos);
  checkInBrowser(dir, c / "campaign_report.html", "campaign", 1);
  checkInBrowser(dir, c / "reports/measure/report.html", "measure", 1);
  checkInBrowser(dir, c / "reports/plan/report.html", "plan", 1);
  checkInBrowser(dir, c / "reports/select/report.html", "select", 1);
  checkInBrowser(dir, c / "reports/compensate/report.html", "compensate", 1);
  checkInBrowser(dir, c / "reports/accuracy/report.html", "accuracy", 1);
}

TEST(CampaignReport, AFolderWithoutReportFilesIsNamed) {
  test::TempDir dir;
  fs::create_directories(dir.path() / "empty");
  EXPECT_EQ(test::runMireIn(dir, "report " + (dir.path() / "empty").string()), 1);
  EXPECT_NE(test::readText(dir.path() / "stderr.txt").find("no report.json or accuracy.json"), std::string::npos)
      << test::readText(dir.path() / "stderr.txt");
}

TEST(ReportBrowser, IdentifyH4) { identifyReport("h4-12", 21, 4); }
TEST(ReportBrowser, IdentifyDelta) { identifyReport("delta", 22, 3); }
TEST(ReportBrowser, IdentifyGoughStewart) { identifyReport("gough-stewart", 23, 6); }

}  // namespace
}  // namespace mire::app
