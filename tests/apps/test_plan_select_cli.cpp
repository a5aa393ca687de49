// `mire plan` and `mire select` through the binary (doc/plan-and-select.md): the plan.csv
// columns and the report, the last line of select, and bad input (file, line, key; exit 1,
// nothing written).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "described_examples.hpp"
#include "mire/datasets/mechanism_campaign.hpp"
#include "mire/support/csv.hpp"
#include "test_support.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;

const char* kH4Workspace =
    "x_m: [-0.1, 0.1]\ny_m: [-0.1, 0.1]\nz_m: [-0.70, -0.55]\ntheta_deg: [-20, 20]\njoint_margin_deg: 1\n";

TEST(PlanCli, WritesThePlanAndTheReport) {
  test::TempDir dir;
  const fs::path d = dir.path();
  test::writeText(d / "workspace.yaml", kH4Workspace);
  const std::string nominal = (test::sourceDir() / "datasets/specs/h4_nominal.yaml").string();
  ASSERT_EQ(test::runMireIn(dir, "plan --model h4-12 --nominal " + nominal + " --workspace " +
                                     (d / "workspace.yaml").string() + " --count 15 --candidates 2000 -o " +
                                     (d / "plan.csv").string() + " --report " + (d / "report").string()),
            0)
      << test::readText(d / "stderr.txt");
  std::istringstream plan(test::readText(d / "plan.csv"));
  std::string line;
  std::getline(plan, line);
  EXPECT_EQ(line, "pose_id,x_m,y_m,z_m,theta_rad,q1_rad,q2_rad,q3_rad,q4_rad,visible");
  int rows = 0;
  while (std::getline(plan, line)) {
    ++rows;
    EXPECT_EQ(line.rfind(rows < 10 ? "p00" : "p01", 0), 0u) << line;
  }
  EXPECT_EQ(rows, 15);
  const std::string out = test::readText(d / "stdout.txt");
  EXPECT_NE(out.find("median sigma ratio plan/random"), std::string::npos) << out;
  EXPECT_TRUE(fs::exists(d / "report" / "plan_report.txt"));
  EXPECT_TRUE(fs::exists(d / "report" / "plan_sigma.csv"));
}

TEST(PlanCli, BadWorkspaceIsNamedAndNothingIsWritten) {
  test::TempDir dir;
  const fs::path d = dir.path();
  test::writeText(d / "workspace.yaml",
                  "x_m: [-0.1, 0.1]\ny_m: [-0.1, 0.1]\nz_m: [-0.70, -0.55]\ntheta_dg: [-20, 20]\n");
  EXPECT_EQ(test::runMireIn(dir, "plan --model h4-12 --workspace " + (d / "workspace.yaml").string() +
                                     " --count 15 -o " + (d / "plan.csv").string()),
            1);
  const std::string err = test::readText(d / "stderr.txt");
  EXPECT_NE(err.find("workspace.yaml:4"), std::string::npos) << err;
  EXPECT_NE(err.find("theta_dg"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(d / "plan.csv"));
  // Too few poses for the parameters.
  test::writeText(d / "workspace.yaml", kH4Workspace);
  EXPECT_EQ(test::runMireIn(dir, "plan --model h4-12 --workspace " + (d / "workspace.yaml").string() +
                                     " --count 3 --candidates 200 -o " + (d / "plan.csv").string()),
            1);
  EXPECT_NE(test::readText(d / "stderr.txt").find("poses are needed"), std::string::npos);
  EXPECT_FALSE(fs::exists(d / "plan.csv"));
}

// A described robot (doc/mechanisms.md, "Described mechanisms"): the linear delta of
// examples/mechanisms/ with a declared stroke on every carriage. Its home readings are 0.292 m
// (z 0.10 + √(0.25² − 0.16²)); the workspace's corners need 0.17–0.38 m, so the stroke cuts it and
// every planned pose's nominal readings lie inside [0.25, 0.34].
TEST(PlanCli, DescribedRobotPlansInsideItsStrokes) {
  test::TempDir dir;
  const fs::path d = dir.path();
  test::writeText(d / "printer.yaml", test::linearDeltaWithStrokes("0.25", "0.34"));
  test::writeText(d / "workspace.yaml", "x_m: [-0.04, 0.04]\ny_m: [-0.04, 0.04]\nz_m: [0.05, 0.15]\n");
  ASSERT_EQ(test::runMireIn(dir, "plan --model " + (d / "printer.yaml").string() + " --workspace " +
                                     (d / "workspace.yaml").string() + " --count 30 --candidates 600 -o " +
                                     (d / "plan.csv").string()),
            0)
      << test::readText(d / "stderr.txt");
  const support::CsvTable plan = support::readCsv(d / "plan.csv");
  ASSERT_EQ(plan.rows.size(), 30u);
  double lo = 1.0, hi = 0.0;
  for (std::size_t r = 0; r < plan.rows.size(); ++r)
    for (const char* q : {"q1_m", "q2_m", "q3_m"}) {
      lo = std::min(lo, plan.number(r, plan.column(q)));
      hi = std::max(hi, plan.number(r, plan.column(q)));
    }
  EXPECT_GE(lo, 0.25);
  EXPECT_LE(hi, 0.34);
  EXPECT_GT(hi - lo, 0.04);  // the plan spreads over the stroke, not a point
}

TEST(SelectCli, LastLineIsTheRecommendation) {
  test::TempDir dir;
  const fs::path d = dir.path();
  const datasets::Campaign c = datasets::simulateCampaign("h4-12", 21);
  datasets::writeCampaignFiles(c, d, 0, c.poses.size());
  ASSERT_EQ(
      test::runMireIn(dir, "select --poses " + (d / "poses.csv").string() + " --joints " + (d / "joints.csv").string() +
                               " --models h4-12:C,D,h4-31c:H --folds 5 --report " + (d / "report").string()),
      0)
      << test::readText(d / "stderr.txt");
  const std::string out = test::readText(d / "stdout.txt");
  const auto last = out.rfind("recommended: ");
  ASSERT_NE(last, std::string::npos) << out;
  const std::string rec = out.substr(last);
  EXPECT_TRUE(rec == "recommended: C\n" || rec == "recommended: D\n") << out;
  EXPECT_TRUE(fs::exists(d / "report" / "select_scores.csv"));
  EXPECT_TRUE(fs::exists(d / "report" / "select_cv.svg"));
  EXPECT_TRUE(fs::exists(d / "report" / "report.html"));
  EXPECT_EQ(test::runMireIn(dir, "select --poses " + (d / "poses.csv").string() + " --joints " +
                                     (d / "joints.csv").string() + " --models h4-12:E"),
            1);
  EXPECT_NE(test::readText(d / "stderr.txt").find("does not belong to h4-12"), std::string::npos);
}

}  // namespace
}  // namespace mire::app
