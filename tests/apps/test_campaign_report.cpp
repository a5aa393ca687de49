// One report for a campaign (pipeline/campaign_report.hpp, doc/plots.md): the report files found
// under the folder in the chain's order whatever their folders' names, each stage's result with its
// σ, the link to its page, every input's SHA-256 as the file is now; bad files named.
#include <gtest/gtest.h>

#include "mire/pipeline/campaign_report.hpp"
#include "mire/report/sha256.hpp"
#include "test_support.hpp"

#include <string>

namespace mire::pipeline {
namespace {

namespace fs = std::filesystem;

std::string header(const std::string& kind, const fs::path& input) {
  return "{\"format\": \"mire report.json 1\", \"report\": \"" + kind +
         "\", \"provenance\": {\"mire_version\": \"0.1.0\", \"command_line\": [\"mire\", \"" + kind +
         "\", \"--in\", \"" + input.string() + "\"], \"inputs\": [{\"role\": \"--in\", \"path\": \"" + input.string() +
         "\"}], \"outputs\": []}";
}

TEST(CampaignReport, StagesInTheChainsOrderWithTheirSigmaAndTheInputsChecksums) {
  test::TempDir dir;
  const fs::path c = dir.path() / "campaign";
  fs::create_directories(c / "a_accuracy"), fs::create_directories(c / "b_identify"),
      fs::create_directories(c / "z_calibrate"), fs::create_directories(c / "other");
  test::writeText(c / "camera.yaml", "fx: 1\n");
  test::writeText(c / "poses.csv", "pose_id\n");
  // Written last, listed first: the chain's order, not the folders'.
  test::writeText(c / "z_calibrate/report.json",
                  header("calibrate", c / "camera.yaml") +
                      ", \"camera\": {\"parameters\": [{\"name\": \"fx\", \"unit\": \"px\", \"fixed\": false, "
                      "\"value\": 812.3456, \"sigma\": 0.0123}]}, \"quality\": {\"rms_px\": 0.2, \"views_used\": 9, "
                      "\"projection_uncertainty\": {\"centre_px\": 0.05, \"corner_px\": 0.4}}}\n");
  test::writeText(c / "z_calibrate/report.html", "<html></html>\n");
  test::writeText(c / "b_identify/report.json",
                  header("identify", c / "poses.csv") +
                      ", \"model\": {\"name\": \"delta\"}, \"fit\": {\"free_parameters\": 1, \"poses\": 27, "
                      "\"chi2_per_dof\": 1.1, \"rms_joint_residual\": 1e-4}, \"parameters\": [{\"name\": \"L\", "
                      "\"unit\": \"m\", \"fixed\": false, \"value\": 0.35012, \"sigma\": 0.00021}]}\n");
  test::writeText(c / "a_accuracy/accuracy.json",
                  header("accuracy", c / "poses.csv") +
                      ", \"model\": \"delta\", \"cycles_used\": 60, \"positions\": [{\"position\": \"P1\", "
                      "\"AP_p_m\": 0.0009, \"sigma_AP_p_m\": 0.00004, \"RP_l_m\": 0.0005, \"noise_only_AP_p_m\": "
                      "{\"mean\": 0.00005, \"p95\": 0.0001}, \"noise_only_RP_l_m\": {\"mean\": 0.0004, \"p95\": "
                      "0.0005}}, {\"position\": \"P2\", \"AP_p_m\": 0.0011, \"sigma_AP_p_m\": 0.00004, \"RP_l_m\": "
                      "0.0004, \"noise_only_AP_p_m\": {\"mean\": 0.00005, \"p95\": 0.0001}, \"noise_only_RP_l_m\": "
                      "{\"mean\": 0.0004, \"p95\": 0.0005}}]}\n");
  test::writeText(c / "other/report.json", "{\"something\": \"else\"}\n");  // not mire's: skipped

  const CampaignReport report = assembleCampaignReport(c, c, "mire report campaign", "0.1.0");
  ASSERT_EQ(report.stages.size(), 3u);
  EXPECT_EQ(report.stages[0].kind, "calibrate");
  EXPECT_EQ(report.stages[1].kind, "identify");
  EXPECT_EQ(report.stages[2].kind, "accuracy");
  const std::string& html = report.html;
  EXPECT_NE(html.find("812.346 \xC2\xB1 0.012"), std::string::npos);                  // fx ± σ (px), σ to two digits
  EXPECT_NE(html.find("350.12 \xC2\xB1 0.21"), std::string::npos);                    // L in mm
  EXPECT_NE(html.find("joint residual RMS 0.00573 deg"), std::string::npos) << html;  // the Delta's joints turn
  // AP_p mean (0.9 + 1.1)/2 = 1.000 mm, σ √(2·0.04²)/2 = 0.028 mm.
  EXPECT_NE(html.find("mean AP_p 1.000 \xC2\xB1 0.028 mm"), std::string::npos) << html;
  EXPECT_NE(html.find("href=\"z_calibrate/report.html\""), std::string::npos);
  EXPECT_NE(html.find(report::sha256File(c / "camera.yaml")), std::string::npos);
  EXPECT_NE(html.find(report::sha256File(c / "poses.csv")), std::string::npos);
  EXPECT_NE(html.find("mire identify --in " + (c / "poses.csv").string()), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
}

TEST(CampaignReport, BadFilesAreNamed) {
  test::TempDir dir;
  const fs::path c = dir.path() / "campaign";
  fs::create_directories(c);
  EXPECT_THROW(assembleCampaignReport(c, c, "", ""), std::runtime_error);
  test::writeText(c / "report.json", "{\"format\": \"mire report.json 1\", \"report\": ");
  try {
    findCampaignReports(c);
    ADD_FAILURE() << "a truncated report.json was read";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find((c / "report.json").string() + ": not JSON"), std::string::npos)
        << error.what();
  }
  EXPECT_THROW(findCampaignReports(c / "missing"), std::runtime_error);
}

}  // namespace
}  // namespace mire::pipeline
