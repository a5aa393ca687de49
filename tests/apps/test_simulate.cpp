// `mire simulate`: a tiny spec writes a complete folder; a bad spec writes nothing.
#include "test_support.hpp"

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

using mire::test::writeText;

// An inline camera (the reference camera at a quarter of its size), a small chessboard.
void writeTinySpec(const fs::path& dir, const std::string& extra) {
  writeText(dir / "board.yaml", "%YAML:1.0\n---\ntype: chessboard\ncols: 5\nrows: 4\nsquare_size_m: 0.03\n");
  writeText(dir / "spec.yaml",
            "%YAML:1.0\n---\n"
            "camera:\n  image_width: 320\n  image_height: 240\n"
            "  camera_matrix: !!opencv-matrix\n    rows: 3\n    cols: 3\n    dt: d\n"
            "    data: [ 255.4, 0., 159.5, 0., 255.4, 119.5, 0., 0., 1. ]\n"
            "  distortion_coefficients: !!opencv-matrix\n    rows: 5\n    cols: 1\n    dt: d\n"
            "    data: [ -0.30, 0.10, 4.0e-4, -3.0e-4, -0.015 ]\n"
            "target: board.yaml\nseed: 4\n"
            "noise:\n  gaussian_sigma: 2.0\n" +
                extra);
}

TEST(Simulate, CalibrationWritesImagesAndTruth) {
  const mire::test::TempDir dir;
  writeTinySpec(dir.path(), "calibration:\n  views: 3\n  distance_m: [ 0.4, 0.5 ]\n  margin_px: 5\n");
  const fs::path out = dir.path() / "out";
  const std::string command = mire::test::mireBinary().string() + " simulate calibration --spec " +
                              (dir.path() / "spec.yaml").string() + " -o " + out.string() + " > /dev/null";
  ASSERT_EQ(mire::test::runCommand(command), 0);
  for (const char* file : {"images/view_000.png", "images/view_002.png", "truth.yaml", "camera.yaml", "target.yaml"})
    EXPECT_TRUE(fs::exists(out / file)) << file;
  EXPECT_FALSE(fs::exists(out / "images/view_003.png"));
  const cv::Mat image = cv::imread((out / "images/view_001.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(image.cols, 320);
  EXPECT_EQ(image.rows, 240);
  EXPECT_EQ(image.type(), CV_8U);

  cv::FileStorage truth((out / "truth.yaml").string(), cv::FileStorage::READ);
  ASSERT_TRUE(truth.isOpened());
  const cv::FileNode views = truth["views"];
  ASSERT_EQ(views.size(), 3u);
  cv::Mat features;
  views[0]["features"] >> features;
  EXPECT_EQ(features.rows, 20);
  EXPECT_EQ(features.cols, 3);
  EXPECT_EQ(views[0]["t"].size(), 3u);
  EXPECT_GT(static_cast<double>(views[0]["t"][2]), 0.3);

  // Same spec, same images (deterministic for a seed).
  const fs::path again = dir.path() / "again";
  ASSERT_EQ(mire::test::runCommand(mire::test::mireBinary().string() + " simulate calibration --spec " +
                                   (dir.path() / "spec.yaml").string() + " -o " + again.string() + " > /dev/null"),
            0);
  const cv::Mat other = cv::imread((again / "images/view_001.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(cv::norm(image, other, cv::NORM_INF), 0.0);
}

TEST(Simulate, PosesWritesOneFolderPerPose) {
  const mire::test::TempDir dir;
  writeTinySpec(dir.path(),
                "poses:\n  images_per_pose: 2\n  list:\n"
                "    - { id: \"a1\", t: [ 0.0, 0.0, 0.45 ], r: [ 0.0, 0.0, 0.0 ] }\n"
                "    - { id: \"b2\", t: [ -0.02, -0.01, 0.5 ], r: [ 0.3, 0.1, 0.0 ] }\n");
  const fs::path out = dir.path() / "out";
  ASSERT_EQ(mire::test::runCommand(mire::test::mireBinary().string() + " simulate poses --spec " +
                                   (dir.path() / "spec.yaml").string() + " -o " + out.string() + " > /dev/null"),
            0);
  for (const char* file :
       {"poses/a1/img_00.png", "poses/a1/img_01.png", "poses/b2/img_01.png", "truth.yaml", "truth_poses.csv"})
    EXPECT_TRUE(fs::exists(out / file)) << file;
  const cv::Mat first = cv::imread((out / "poses/a1/img_00.png").string(), cv::IMREAD_UNCHANGED);
  const cv::Mat second = cv::imread((out / "poses/a1/img_01.png").string(), cv::IMREAD_UNCHANGED);
  EXPECT_GT(cv::norm(first, second, cv::NORM_INF), 0.0);  // independent noise, same pose
  std::ifstream csv(out / "truth_poses.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  EXPECT_EQ(header.rfind("pose_id,images_used,images_total,tx_m,", 0), 0u);
  EXPECT_EQ(row.rfind("a1,2,2,0,0,0.45", 0), 0u) << row;
}

TEST(Simulate, BadSpecNamesTheKeyAndWritesNothing) {
  const mire::test::TempDir dir;
  writeTinySpec(dir.path(), "render:\n  vignetting: sideways\n");
  const fs::path out = dir.path() / "out";
  const fs::path log = dir.path() / "log.txt";
  EXPECT_EQ(mire::test::runCommand(mire::test::mireBinary().string() + " simulate calibration --spec " +
                                   (dir.path() / "spec.yaml").string() + " -o " + out.string() + " 2> " + log.string()),
            1);
  std::ifstream in(log);
  const std::string message((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(message.find("render.vignetting"), std::string::npos) << message;
  EXPECT_NE(message.find("spec.yaml"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
