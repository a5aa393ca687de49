// --save-detections / --detections (doc/targets.md, "Detections file"): a calibration fed back
// from its own detections (mire's CSV and mrcal's corners vnlog) is identical; measure saves
// its detections; bad detections files and targets name the file and line, exit 1, write nothing.
#include "mire/calibration/camera_io.hpp"
#include "mire/datasets/feature_campaign.hpp"
#include "mire/datasets/render.hpp"
#include "mire/metrology/detections_file.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/csv.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>

#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

mire::metrology::Target chessboard() {
  mire::metrology::TargetSpec spec;
  spec.cols = 9;
  spec.rows = 6;
  spec.square_size_m = 0.03;
  return mire::metrology::Target(spec);
}

Eigen::Isometry3d view(double x, double y, double z, double tilt_x_deg, double tilt_y_deg) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(tilt_x_deg * M_PI / 180, Eigen::Vector3d::UnitX()) *
                   Eigen::AngleAxisd(tilt_y_deg * M_PI / 180, Eigen::Vector3d::UnitY()))
                      .toRotationMatrix();
  pose.translation() = Eigen::Vector3d(x, y, z) - pose.linear() * Eigen::Vector3d(0.12, 0.075, 0);
  return pose;
}

// Six rendered views of the chessboard by the reference camera, as PNG files in `folder`.
void renderViews(const fs::path& folder) {
  fs::create_directories(folder);
  const mire::datasets::Renderer renderer(mire::datasets::referenceCamera(), chessboard());
  const double poses[6][5] = {{0, 0, 0.5, 0, 0},          {-0.1, -0.08, 0.55, 30, -25},
                              {0.1, -0.08, 0.55, 30, 25}, {-0.1, 0.08, 0.55, -30, -25},
                              {0.1, 0.08, 0.55, -30, 25}, {0, 0, 0.6, 0, 40}};
  for (int i = 0; i < 6; ++i) {
    const auto rendering = renderer.render(view(poses[i][0], poses[i][1], poses[i][2], poses[i][3], poses[i][4]));
    cv::imwrite((folder / ("view" + std::to_string(i) + ".png")).string(),
                mire::datasets::addNoise(rendering.radiance, {1.0, 0.0}, 10 + i));
  }
}

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string mire(const std::string& arguments, int* code) {
  return mire::test::captureCommand(mire::test::mireBinary().string() + " " + arguments, code);
}

TEST(DetectionsCli, CalibrationFedBackFromItsDetectionsIsIdentical) {
  const mire::test::TempDir dir;
  const fs::path d = dir.path();
  renderViews(d / "images");
  mire::support::writeFileAtomically(d / "target.yaml", chessboard().yamlString());
  // One solver thread: Ceres' multi-threaded sums may differ in the last bits from run to run.
  const std::string target = " --threads 1 --target " + (d / "target.yaml").string();
  int code = 0;
  std::string out = mire("calibrate" + target + " --images " + (d / "images").string() + " --save-detections " +
                             (d / "detections.csv").string() + " -o " + (d / "camera.yaml").string(),
                         &code);
  ASSERT_EQ(code, 0) << out;
  // The documented format: comments, the image size, the header, one row per image and feature.
  const mire::support::CsvTable table = mire::support::readCsv(d / "detections.csv");
  std::string header;
  for (const auto& column : table.header) header += (header.empty() ? "" : ",") + column;
  EXPECT_EQ(header, mire::metrology::kDetectionsCsvHeader);
  EXPECT_EQ(table.rows.size(), 6u * 54u);
  EXPECT_NE(readText(d / "detections.csv").find("# image_size_px: 1024 768\n"), std::string::npos);
  EXPECT_EQ(table.rows[1][0], "view0.png");
  EXPECT_EQ(table.rows[1][1], "1");
  EXPECT_EQ(table.rows[1][4], "0.029999999999999999");  // x of feature 1: one square along x

  // Fed back: the same camera, bit for bit.
  out = mire(
      "calibrate" + target + " --detections " + (d / "detections.csv").string() + " -o " + (d / "again.yaml").string(),
      &code);
  ASSERT_EQ(code, 0) << out;
  const auto first = mire::calibration::readCameraYaml(d / "camera.yaml");
  const auto again = mire::calibration::readCameraYaml(d / "again.yaml");
  ASSERT_EQ(first.params.size(), again.params.size());
  for (std::size_t i = 0; i < first.params.size(); ++i) EXPECT_EQ(first.params[i], again.params[i]) << i;
  EXPECT_EQ(readText(d / "camera.yaml"), readText(d / "again.yaml"));

  // The same corners as mrcal's corners vnlog (rows in the board's order, one image without
  // its board, one corner marked '-'): the same camera as from mire's file with that corner gone.
  std::ostringstream vnlog, csv;
  vnlog << "# filename x y level\n";
  csv << "# image_size_px: 1024 768\n" << mire::metrology::kDetectionsCsvHeader << "\n";
  for (std::size_t row = 0; row < table.rows.size(); ++row) {
    const auto& r = table.rows[row];
    const bool dropped = r[0] == "view2.png" && r[1] == "7";
    vnlog << r[0] << " " << r[2] << " " << r[3] << (dropped ? " -" : " 0") << "\n";
    if (!dropped)
      csv << r[0] << "," << r[1] << "," << r[2] << "," << r[3] << "," << r[4] << "," << r[5] << "," << r[6] << "\n";
  }
  vnlog << "missing.png - - -\n";
  mire::support::writeFileAtomically(d / "corners.vnlog", vnlog.str());
  mire::support::writeFileAtomically(d / "dropped.csv", csv.str());
  out = mire("calibrate" + target + " --detections " + (d / "corners.vnlog").string() + " --image-size 1024 768 -o " +
                 (d / "mrcal.yaml").string(),
             &code);
  ASSERT_EQ(code, 0) << out;
  out = mire(
      "calibrate" + target + " --detections " + (d / "dropped.csv").string() + " -o " + (d / "dropped.yaml").string(),
      &code);
  ASSERT_EQ(code, 0) << out;
  EXPECT_EQ(readText(d / "mrcal.yaml"), readText(d / "dropped.yaml"));
  // Without the image size, the vnlog cannot calibrate: said, exit 1, nothing written.
  out = mire(
      "calibrate" + target + " --detections " + (d / "corners.vnlog").string() + " -o " + (d / "none.yaml").string(),
      &code);
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("--image-size"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(d / "none.yaml"));

  // mire measure saves every image's detections, named "<pose>/<image>".
  fs::create_directories(d / "poses/p1");
  fs::copy_file(d / "images/view0.png", d / "poses/p1/a.png");
  fs::copy_file(d / "images/view0.png", d / "poses/p1/b.png");
  out = mire("measure --camera " + (d / "camera.yaml").string() + " --target " + (d / "target.yaml").string() +
                 " --poses " + (d / "poses").string() + " -o " + (d / "poses.csv").string() + " --save-detections " +
                 (d / "measured.csv").string(),
             &code);
  ASSERT_EQ(code, 0) << out;
  const mire::support::CsvTable measured = mire::support::readCsv(d / "measured.csv");
  ASSERT_EQ(measured.rows.size(), 2u * 54u);
  EXPECT_EQ(measured.rows.front()[0], "p1/a.png");
  EXPECT_EQ(measured.rows.back()[0], "p1/b.png");
  // Same image, same pixels as calibrate found.
  EXPECT_EQ(measured.rows.front()[2], table.rows.front()[2]);
}

TEST(DetectionsCli, BadDetectionsFilesAndTargetsNameFileAndLineAndWriteNothing) {
  const mire::test::TempDir dir;
  const fs::path d = dir.path();
  mire::support::writeFileAtomically(d / "target.yaml", chessboard().yamlString());
  const auto expectFailure = [&](const std::string& target_file, const std::string& detections,
                                 const std::string& needle) {
    mire::support::writeFileAtomically(d / "detections.csv", detections);
    int code = 0;
    const std::string out =
        mire("calibrate --target " + (d / target_file).string() + " --detections " + (d / "detections.csv").string() +
                 " --save-detections " + (d / "saved.csv").string() + " -o " + (d / "camera.yaml").string(),
             &code);
    EXPECT_EQ(code, 1) << out;
    EXPECT_NE(out.find(needle), std::string::npos) << "expected '" << needle << "' in: " << out;
    EXPECT_FALSE(fs::exists(d / "camera.yaml"));
    EXPECT_FALSE(fs::exists(d / "saved.csv"));
  };
  const std::string head = "# image_size_px: 1024 768\nimage,feature_id,u_px,v_px,x_m,y_m,z_m\n";
  const std::string csv = (d / "detections.csv").string();
  expectFailure("target.yaml", head + "a.png,0,10,20,0,0,0\na.png,1,12,x,0.03,0,0\n", csv + ":4: column 'v_px'");
  expectFailure("target.yaml", head + "a.png,0,10,20,0,0,0\na.png,54,12,20,0.03,0,0\n", csv + ":4: column 'feature_id'");
  expectFailure("target.yaml", head + "a.png,1,10,20,0.02,0,0\n", csv + ":3: feature 1 is at (0.02, 0, 0) m");
  expectFailure("target.yaml", head + "a.png,1,10,20,0.03,0,0\na.png,1,10,20,0.03,0,0\n",
                csv + ":4: feature 1 of image 'a.png' given twice");
  expectFailure("target.yaml", "# filename x y level\na.png 10 20 0\na.png 11\n", csv + ":3: expected 4 fields");
  expectFailure("target.yaml", "# filename x y level\na.png 10 20 0\na.png 11 2q 0\n",
                csv + ":3: x, y and level must be numbers");
  // A new target error: an unknown ArUco dictionary, named with its file and line.
  mire::support::writeFileAtomically(d / "charuco.yaml",
                                     "type: charuco\ncols: 5\nrows: 7\nsquare_size_m: 0.04\nmarker_size_m: 0.02\n"
                                     "dictionary: DICT_6X6_251\n");
  expectFailure("charuco.yaml", head, (d / "charuco.yaml").string() + ":6: key 'dictionary': unknown dictionary");
}

}  // namespace
