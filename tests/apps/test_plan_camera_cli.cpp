// `mire plan --camera --target` through the binary (doc/plan-and-select.md, "--camera"): the
// demo's camera and target, the visibility column, the predicted pose σ per planned pose in the
// report and report.json; too few visible candidates fail naming the reason (exit 1, nothing
// written).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "mire/support/csv.hpp"
#include "test_support.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;

const char* kH4Workspace = "x_m: [-0.1, 0.1]\ny_m: [-0.1, 0.1]\nz_m: [-0.70, -0.55]\ntheta_deg: [-20, 20]\n";

std::string cameraArgs() {
  const fs::path specs = test::sourceDir() / "datasets/specs";
  return " --camera " + (specs / "reference_camera.yaml").string() + " --target " + (specs / "target_h4.yaml").string();
}

TEST(PlanCameraCli, DemoCameraFillsVisibilityAndPoseSigma) {
  test::TempDir dir;
  const fs::path d = dir.path();
  test::writeText(d / "workspace.yaml", kH4Workspace);
  ASSERT_EQ(test::runMireIn(dir, "plan --model h4-12 --workspace " + (d / "workspace.yaml").string() +
                                     " --count 15 --candidates 1000 --images-per-pose 3 -o " +
                                     (d / "plan.csv").string() + " --report " + (d / "report").string() + cameraArgs()),
            0)
      << test::readText(d / "stderr.txt");
  const support::CsvTable plan = support::readCsv(d / "plan.csv");
  ASSERT_EQ(plan.rows.size(), 15u);
  for (const auto& row : plan.rows) EXPECT_EQ(row[plan.column("visible")], "yes");
  const std::string out = test::readText(d / "stdout.txt");
  EXPECT_NE(out.find("candidates visible"), std::string::npos) << out;
  EXPECT_NE(out.find("predicted pose sigma per planned pose"), std::string::npos) << out;

  const nlohmann::json doc = nlohmann::json::parse(test::readText(d / "report" / "report.json"));
  const auto& camera = doc.at("camera");
  EXPECT_EQ(camera.at("images_per_pose").get<int>(), 3);
  EXPECT_EQ(camera.at("systematic_model").get<std::string>(), "board");
  EXPECT_DOUBLE_EQ(camera.at("systematic_mean_px").get<double>(), 0.0278);
  EXPECT_DOUBLE_EQ(camera.at("systematic_grid_px").get<double>(), 0.0045);
  EXPECT_EQ(camera.at("candidates_drawn").get<int>(), 1000);
  EXPECT_EQ(camera.at("candidates_visible").get<int>() + camera.at("excluded_outside").get<int>() +
                camera.at("excluded_oblique").get<int>(),
            1000);
  ASSERT_EQ(camera.at("predicted_pose_sigma").size(), 15u);
  for (const auto& pose : camera.at("predicted_pose_sigma")) {
    // The reference camera (no covariance) 0.8–0.95 m away, the default detector noise (σ_f
    // 0.032 px over 3 images): tens of µm in depth, hundredths of a degree.
    const double tz = pose.at("sigma_tz_m").get<double>(), rx = pose.at("sigma_rx_rad").get<double>();
    EXPECT_GT(tz, 1e-6);
    EXPECT_LT(tz, 1e-3);
    EXPECT_GT(rx, 1e-6);
    EXPECT_LT(rx, 3e-3);
  }
}

// A camera file from `mire calibrate` carries the intrinsics' covariance: the calibration
// error every pose shares enters the parameters' σ once (doc/plan-and-select.md), and the report
// says how much of the geometric variance it is. Without one, the report says it is left out.
TEST(PlanCameraCli, CameraCovarianceEntersTheParametersSigmaOnce) {
  test::TempDir dir;
  const fs::path d = dir.path();
  test::writeText(d / "workspace.yaml", kH4Workspace);
  const fs::path specs = test::sourceDir() / "datasets/specs";
  std::string camera = test::readText(specs / "reference_camera.yaml");
  // fx, fy 0.5 px (correlated 0.8), cx, cy 0.3 px, k1 k2 k3 1e-3, p1 p2 1e-4.
  camera +=
      "covariance: !!opencv-matrix\n   rows: 9\n   cols: 9\n   dt: d\n   data: [ 0.25, 0.2, 0, 0, 0, 0, 0, 0, 0, "
      "0.2, 0.25, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.09, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.09, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1e-6, "
      "0, 0, 0, 0, 0, 0, 0, 0, 0, 1e-6, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1e-8, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1e-8, 0, 0, 0, 0, "
      "0, 0, 0, 0, 0, 1e-6 ]\n";
  test::writeText(d / "camera.yaml", camera);
  const std::string common = "plan --model h4-12 --workspace " + (d / "workspace.yaml").string() +
                             " --count 15 --candidates 1000 --target " + (specs / "target_h4.yaml").string();
  ASSERT_EQ(test::runMireIn(dir, common + " --camera " + (d / "camera.yaml").string() + " -o " +
                                     (d / "plan.csv").string() + " --report " + (d / "report").string()),
            0)
      << test::readText(d / "stderr.txt");
  const std::string out = test::readText(d / "stdout.txt");
  EXPECT_NE(out.find("the camera calibration's error, shared by every pose, is in the predicted sigma"), std::string::npos)
      << out;
  const support::CsvTable sigma = support::readCsv(d / "report" / "plan_sigma.csv");
  for (const auto& row : sigma.rows) {
    const double plan = std::stod(row[sigma.column("sigma_plan")]),
                 shared = std::stod(row[sigma.column("sigma_plan_shared")]);
    EXPECT_GT(shared, 0.0) << row[0];
    EXPECT_LE(shared, plan) << row[0];
  }
  const nlohmann::json doc = nlohmann::json::parse(test::readText(d / "report" / "report.json"));
  EXPECT_TRUE(doc.at("camera").at("shared_calibration_term").get<bool>());
  EXPECT_GT(doc.at("parameters").at(0).at("sigma_plan_shared").get<double>(), 0.0);

  // The same plan without the covariance: the column is empty and the report says so.
  ASSERT_EQ(test::runMireIn(dir, common + " --camera " + (specs / "reference_camera.yaml").string() + " -o " +
                                     (d / "plain.csv").string() + " --report " + (d / "plain").string()),
            0)
      << test::readText(d / "stderr.txt");
  EXPECT_NE(test::readText(d / "stdout.txt").find("camera calibration error: not included"), std::string::npos);
  const support::CsvTable plain = support::readCsv(d / "plain" / "plan_sigma.csv");
  EXPECT_EQ(plain.rows.at(0)[plain.column("sigma_plan_shared")], "");
}

TEST(PlanCameraCli, TooFewVisibleCandidatesFailNamingTheReason) {
  test::TempDir dir;
  const fs::path d = dir.path();
  test::writeText(d / "workspace.yaml", kH4Workspace);
  const std::string base = "plan --model h4-12 --workspace " + (d / "workspace.yaml").string() +
                           " --count 15 --candidates 300 -o " + (d / "plan.csv").string() + cameraArgs();
  // No target is seen square on: a limit of 0.01° leaves only too oblique candidates.
  EXPECT_EQ(test::runMireIn(dir, base + " --max-tilt-deg 0.01"), 1);
  std::string err = test::readText(d / "stderr.txt");
  EXPECT_NE(err.find("300 too oblique"), std::string::npos) << err;
  EXPECT_NE(err.find("reference_camera.yaml"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(d / "plan.csv"));
  // The camera 1 m to the side of the workspace: the board is never in the image.
  test::writeText(d / "mounting.yaml",
                  "tx_CB: -1.0\nty_CB: 0\ntz_CB: 1.5\nrx_CB: 0\nry_CB: 0\nrz_CB: 0\n"
                  "tx_EM: 0\nty_EM: 0\ntz_EM: 0\nrx_EM: 3.141592653589793\nry_EM: 0\nrz_EM: 0\n");
  EXPECT_EQ(test::runMireIn(dir, base + " --externals " + (d / "mounting.yaml").string()), 1);
  err = test::readText(d / "stderr.txt");
  EXPECT_NE(err.find("300 outside the image"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(d / "plan.csv"));
  // The board model's A,B must give a systematic error >= 0 (B <= A).
  EXPECT_EQ(test::runMireIn(dir, base + " --systematic-board 0.01,0.02"), 2);
  EXPECT_NE(test::readText(d / "stderr.txt").find("--systematic-board"), std::string::npos);
  // --camera needs --target.
  EXPECT_EQ(test::runMireIn(dir, "plan --model h4-12 --workspace " + (d / "workspace.yaml").string() +
                                     " --count 15 -o " + (d / "plan.csv").string() + " --camera " +
                                     (test::sourceDir() / "datasets/specs/reference_camera.yaml").string()),
            2);
}

// The camera on the effector (doc/plan-and-select.md): on the Delta (its protocol volume, the demo's camera and
// board), the externals are eTc and bTm, the visibility check is made in that mounting, and the
// report says so; on a described robot (the linear delta) too. The same mounting guess turned into
// the camera-fixed names is refused (unknown keys), and a target placed where the camera on the
// effector never sees it leaves no visible candidate (exit 1).
TEST(PlanCameraCli, CameraOnTheEffector) {
  test::TempDir dir;
  const fs::path d = dir.path();
  test::writeText(d / "workspace.yaml", "x_m: [-0.15, 0.15]\ny_m: [-0.15, 0.15]\nz_m: [-0.725, -0.575]\n");
  const std::string base = "plan --model delta --workspace " + (d / "workspace.yaml").string() +
                           " --count 12 --candidates 600 --mounting camera-on-effector" + cameraArgs();
  ASSERT_EQ(test::runMireIn(dir, base + " -o " + (d / "plan.csv").string() + " --report " + (d / "report").string()), 0)
      << test::readText(d / "stderr.txt");
  const support::CsvTable plan = support::readCsv(d / "plan.csv");
  ASSERT_EQ(plan.rows.size(), 12u);
  for (const auto& row : plan.rows) EXPECT_EQ(row[plan.column("visible")], "yes");
  const std::string out = test::readText(d / "stdout.txt");
  EXPECT_NE(out.find("mounting: camera-on-effector (externals eTc and bTm"), std::string::npos) << out;
  EXPECT_NE(test::readText(d / "report" / "plan_report.txt").find("mounting: camera-on-effector"), std::string::npos);
  const nlohmann::json doc = nlohmann::json::parse(test::readText(d / "report" / "report.json"));
  EXPECT_EQ(doc.at("mounting").get<std::string>(), "camera-on-effector");
  bool eye_in_hand_externals = false;
  for (const auto& p : doc.at("parameters")) {
    const std::string name = p.at("name").get<std::string>();
    EXPECT_EQ(name.find("_CB"), std::string::npos) << name;
    if (p.at("role").get<std::string>() == "mounting")
      eye_in_hand_externals |= name.find("_EC") != std::string::npos || name.find("_BM") != std::string::npos;
  }
  EXPECT_TRUE(eye_in_hand_externals);
  EXPECT_LT(doc.at("summary").at("median_ratio_plan_random").get<double>(), 1.0);

  // The board 1 m to the side of the workspace: never in the image of the camera on the plate.
  test::writeText(d / "mounting.yaml",
                  "tx_EC: 0\nty_EC: 0\ntz_EC: 0\nrx_EC: 3.141592653589793\nry_EC: 0\nrz_EC: 0\n"
                  "tx_BM: 1.0\nty_BM: 0\ntz_BM: -1.5\nrx_BM: 0\nry_BM: 0\nrz_BM: 0\n");
  EXPECT_EQ(
      test::runMireIn(dir, base + " -o " + (d / "far.csv").string() + " --externals " + (d / "mounting.yaml").string()),
      1);
  std::string err = test::readText(d / "stderr.txt");
  EXPECT_NE(err.find("600 outside the image"), std::string::npos) << err;
  EXPECT_FALSE(fs::exists(d / "far.csv"));
  // The camera-fixed names with the camera on the effector: unknown keys, named.
  test::writeText(d / "fixed.yaml",
                  "tx_CB: 0\nty_CB: 0\ntz_CB: 1.5\nrx_CB: 0\nry_CB: 0\nrz_CB: 0\n"
                  "tx_EM: 0\nty_EM: 0\ntz_EM: 0\nrx_EM: 3.141592653589793\nry_EM: 0\nrz_EM: 0\n");
  EXPECT_EQ(
      test::runMireIn(dir, base + " -o " + (d / "fixed.csv").string() + " --externals " + (d / "fixed.yaml").string()),
      1);
  err = test::readText(d / "stderr.txt");
  EXPECT_NE(err.find("fixed.yaml"), std::string::npos) << err;
  EXPECT_NE(err.find("tx_CB"), std::string::npos) << err;

  // A described robot: the linear delta of examples/mechanisms (no camera check).
  test::writeText(d / "printer_workspace.yaml", "x_m: [-0.04, 0.04]\ny_m: [-0.04, 0.04]\nz_m: [0.05, 0.15]\n");
  ASSERT_EQ(test::runMireIn(dir, "plan --model " + (test::sourceDir() / "examples/mechanisms/linear-delta.yaml").string() +
                                     " --workspace " + (d / "printer_workspace.yaml").string() +
                                     " --count 20 --candidates 400 --mounting camera-on-effector -o " +
                                     (d / "printer.csv").string() + " --report " + (d / "printer").string()),
            0)
      << test::readText(d / "stderr.txt");
  EXPECT_EQ(nlohmann::json::parse(test::readText(d / "printer" / "report.json")).at("mounting").get<std::string>(),
            "camera-on-effector");
}

}  // namespace
}  // namespace mire::app
