// The charuco, aruco_grid and free AprilTag layouts (doc/targets.md): frame M and feature
// order against OpenCV's own board object points, plain-YAML round trips, and bad specs named
// by file, line and key.
#include "mire/metrology/aruco_boards.hpp"
#include "mire/metrology/target.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace mire::metrology {
namespace {

using test::writeText;

std::string loadError(const std::filesystem::path& path) {
  return test::runtimeErrorOf([&] { Target::fromFile(path); });
}

TEST(TargetLayouts, CharucoFeaturesAreOpenCVsChessboardCorners) {
  const Target target = Target::fromFile(test::sourceDir() / "datasets/specs/target_charuco.yaml");
  const cv::Ptr<cv::aruco::CharucoBoard> board = charucoBoard(target);
  ASSERT_EQ(target.points().size(), board->chessboardCorners.size());
  ASSERT_EQ(target.points().size(), 24u);  // (5 − 1) × (7 − 1)
  for (std::size_t i = 0; i < target.points().size(); ++i) {
    const cv::Point3f& p = board->chessboardCorners[i];
    EXPECT_NEAR((target.points()[i] - Eigen::Vector3d(p.x, p.y, p.z)).norm(), 0.0, 1e-7) << i;
  }
  EXPECT_TRUE(target.points()[0].isApprox(Eigen::Vector3d(0.04, 0.04, 0)));  // origin: the board's outer corner
  EXPECT_TRUE(target.points()[1].isApprox(Eigen::Vector3d(0.08, 0.04, 0)));  // x along cols
  EXPECT_TRUE(target.points()[4].isApprox(Eigen::Vector3d(0.04, 0.08, 0)));  // y along rows
  EXPECT_FALSE(target.isRotationallyAmbiguous());
  EXPECT_DOUBLE_EQ(target.featureSpacing(), 0.04);
}

TEST(TargetLayouts, ArucoGridCornersAreOpenCVsMarkerCorners) {
  const Target target = Target::fromFile(test::sourceDir() / "datasets/specs/target_aruco_grid.yaml");
  const cv::Ptr<cv::aruco::GridBoard> board = arucoGridBoard(target);
  ASSERT_EQ(target.points().size(), 4 * board->ids.size());
  for (std::size_t k = 0; k < board->ids.size(); ++k) {
    EXPECT_EQ(target.tagIndex(board->ids[k]), static_cast<int>(k));
    for (int j = 0; j < 4; ++j) {
      const cv::Point3f& p = board->objPoints[k][j];
      EXPECT_NEAR((target.points()[4 * k + j] - Eigen::Vector3d(p.x, p.y, p.z)).norm(), 0.0, 1e-7) << k << " " << j;
    }
  }
  // Marker 6 = row 1, col 1: top-left at (0.05, 0.05), pitch = marker + spacing.
  EXPECT_TRUE(target.points()[24].isApprox(Eigen::Vector3d(0.05, 0.05, 0)));
  EXPECT_TRUE(target.points()[26].isApprox(Eigen::Vector3d(0.09, 0.09, 0)));
  EXPECT_EQ(target.tagIndex(35), -1);
}

TEST(TargetLayouts, FreeAprilTagLayoutAndSingleTag) {
  const Target target = Target::fromFile(test::sourceDir() / "datasets/specs/target_apriltag_layout.yaml");
  ASSERT_EQ(target.points().size(), 16u);
  EXPECT_EQ(target.tagIndex(21), 2);
  EXPECT_EQ(target.tagIndex(10), -1);
  // Tag id 4 (entry 3) at (0.15, 0.10), 60 mm: its corners.
  EXPECT_TRUE(target.points()[12].isApprox(Eigen::Vector3d(0.15, 0.10, 0)));
  EXPECT_TRUE(target.points()[13].isApprox(Eigen::Vector3d(0.21, 0.10, 0)));
  EXPECT_TRUE(target.points()[14].isApprox(Eigen::Vector3d(0.21, 0.16, 0)));
  EXPECT_TRUE(target.points()[15].isApprox(Eigen::Vector3d(0.15, 0.16, 0)));

  const test::TempDir dir;
  // A single tag: as a one-entry list, or as a 1 x 1 grid without tag_spacing_m.
  writeText(dir.path() / "one.yaml",
            "type: apriltag\nfamily: tag36h11\ntag_size_m: 0.1\ntags: [{id: 8, x: 0, y: 0}]\n");
  writeText(dir.path() / "grid.yaml",
            "type: apriltag\nfamily: tag36h11\ntag_size_m: 0.1\ncols: 1\nrows: 1\nfirst_id: 8\n");
  for (const char* name : {"one.yaml", "grid.yaml"}) {
    const Target single = Target::fromFile(dir.path() / name);
    ASSERT_EQ(single.points().size(), 4u) << name;
    EXPECT_EQ(single.tagIndex(8), 0) << name;
    EXPECT_TRUE(single.points()[2].isApprox(Eigen::Vector3d(0.1, 0.1, 0))) << name;
  }
}

TEST(TargetLayouts, PlainYamlRoundTripsOfTheNewExamples) {
  const test::TempDir dir;
  for (const char* name : {"target_charuco.yaml", "target_aruco_grid.yaml", "target_apriltag_layout.yaml"}) {
    const Target original = Target::fromFile(test::sourceDir() / "datasets" / "specs" / name);
    const std::string text = original.yamlString();
    EXPECT_EQ(text.find("%YAML"), std::string::npos) << "plain YAML: " << name;
    writeText(dir.path() / "copy.yaml", text);
    const Target copy = Target::fromFile(dir.path() / "copy.yaml");
    EXPECT_EQ(copy.yamlString(), text) << name;
    ASSERT_EQ(copy.points().size(), original.points().size()) << name;
    for (std::size_t i = 0; i < copy.points().size(); ++i) EXPECT_EQ(copy.points()[i], original.points()[i]) << name;
    // Flow style and CRLF read the same.
    std::string crlf;
    for (const char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    writeText(dir.path() / "crlf.yaml", crlf);
    EXPECT_EQ(Target::fromFile(dir.path() / "crlf.yaml").yamlString(), text) << name;
    // Plain YAML that PyYAML (python3-yaml, scripts/setup.sh) reads, with the same numbers.
    int code = 0;
    const std::string check =
        "python3 -c \"import sys, yaml; d = yaml.safe_load(open(sys.argv[1])); "
        "sys.exit(0 if isinstance(d['" +
        std::string(std::string(name) == "target_apriltag_layout.yaml" ? "tag_size_m" : "marker_size_m") +
        "'], float) else 3)\" " + (dir.path() / "copy.yaml").string();
    const std::string out = test::captureCommand(check, &code);
    EXPECT_EQ(code, 0) << name << ": " << out;
  }
}

TEST(TargetLayouts, BadSpecsNameFileLineAndKey) {
  const test::TempDir dir;
  const auto path = dir.path() / "target.yaml";
  const auto expectError = [&](const std::string& text, const std::string& needle) {
    writeText(path, text);
    const std::string message = loadError(path);
    EXPECT_EQ(message.rfind(path.string() + ":", 0), 0u) << message;
    EXPECT_NE(message.find(needle), std::string::npos) << "expected '" << needle << "' in: " << message;
  };
  const std::string charuco = "type: charuco\ncols: 5\nrows: 7\nsquare_size_m: 0.04\nmarker_size_m: 0.02\n";
  expectError(charuco + "dictionary: DICT_6X6_2500\n", ":6: key 'dictionary': unknown dictionary 'DICT_6X6_2500'");
  expectError(charuco + "dictionary: DICT_6X6_250\nfirst_id: 3\n", ":7: unknown key 'first_id'");
  expectError("type: charuco\ncols: 5\nrows: 7\nsquare_size_m: 0.04\nmarker_size_m: 0.05\ndictionary: DICT_6X6_250\n",
              "marker_size_m must be smaller than square_size_m");
  expectError("type: charuco\ncols: 30\nrows: 30\nsquare_size_m: 0.04\nmarker_size_m: 0.02\ndictionary: DICT_4X4_50\n",
              "do not exist in DICT_4X4_50");
  expectError("type: aruco_grid\ncols: 5\nrows: 7\nmarker_size_m: 0.04\ndictionary: DICT_4X4_50\n",
              "missing key 'marker_spacing_m'");
  const std::string tags = "type: apriltag\nfamily: tag36h11\ntag_size_m: 0.05\ntags:\n";
  expectError(tags + "  - {id: 1, x: 0, y: 0}\n  - {id: 1, x: 0.1, y: 0}\n", ":6: key 'tags[1]'");
  expectError(tags + "  - {id: 1, x: 0, y: 0}\n  - {id: 1, x: 0.1, y: 0}\n", "listed twice");
  expectError(tags + "  - {id: 1, x: 0, y: 0}\n  - {id: 2, x: 0.03, y: 0.01}\n", "overlaps");
  expectError(tags + "  - {id: 1, x: 0, y: 0}\n  - {id: 700, x: 0.1, y: 0}\n", "does not exist in tag36h11");
  expectError(tags + "  - {id: 1, x: 0}\n", "missing key 'tags[0].y'");
  expectError(tags + "  - {id: 1, x: 0, y: 0, z: 1}\n", "unknown key 'tags[0].z'");
  expectError(tags + "  - [1, 0, 0]\n", ":5: key 'tags[0]': each tag must be a map");
  expectError("type: apriltag\nfamily: tag36h11\ntag_size_m: 0.05\ntags: []\n",
              ":4: key 'tags': must be a non-empty list");
  expectError("type: apriltag\nfamily: tag36h11\ntag_size_m: 0.05\ncols: 2\nrows: 1\n", "missing key 'tag_spacing_m'");
}

}  // namespace
}  // namespace mire::metrology
