// Target layout (frame M, doc/file-formats.md), target.yaml round trip and bad specs.
#include "mire/metrology/target.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace mire::metrology {
namespace {

using test::writeText;

// The message of the runtime_error thrown by Target::fromFile, or "" if none.
std::string loadError(const std::filesystem::path& path) {
  return test::runtimeErrorOf([&] { Target::fromFile(path); });
}

TEST(Target, ChessboardAndCircleLayouts) {
  TargetSpec spec;
  spec.type = TargetType::Chessboard;
  spec.cols = 10;
  spec.rows = 7;
  spec.square_size_m = 0.03;
  const Target board(spec);
  ASSERT_EQ(board.points().size(), 70u);
  EXPECT_TRUE(board.points()[0].isZero());
  EXPECT_TRUE(board.points()[1].isApprox(Eigen::Vector3d(0.03, 0, 0)));   // x along cols
  EXPECT_TRUE(board.points()[10].isApprox(Eigen::Vector3d(0, 0.03, 0)));  // y along rows
  EXPECT_TRUE(board.points()[69].isApprox(Eigen::Vector3d(0.27, 0.18, 0)));
  EXPECT_FALSE(board.isRotationallyAmbiguous());
  spec.cols = 9;
  EXPECT_TRUE(Target(spec).isRotationallyAmbiguous());
  EXPECT_DOUBLE_EQ(board.featureSpacing(), 0.03);

  TargetSpec acircles;
  acircles.type = TargetType::AsymmetricCircles;
  acircles.cols = 4;
  acircles.rows = 11;
  acircles.spacing_m = 0.02;
  acircles.diameter_m = 0.01;
  const Target grid(acircles);
  ASSERT_EQ(grid.points().size(), 44u);
  // OpenCV's asymmetric layout: (c, r) at ((2c + r mod 2)·s, r·s).
  EXPECT_TRUE(grid.points()[1].isApprox(Eigen::Vector3d(0.04, 0, 0)));
  EXPECT_TRUE(grid.points()[4].isApprox(Eigen::Vector3d(0.02, 0.02, 0)));
  EXPECT_TRUE(grid.points()[43].isApprox(Eigen::Vector3d(0.12, 0.20, 0)));
  EXPECT_NEAR(grid.featureSpacing(), 0.02 * std::sqrt(2.0), 1e-15);
  EXPECT_FALSE(grid.isRotationallyAmbiguous());
  acircles.rows = 10;
  EXPECT_TRUE(Target(acircles).isRotationallyAmbiguous());
}

TEST(Target, AprilTagGridCorners) {
  TargetSpec spec;
  spec.type = TargetType::AprilTag;
  spec.cols = 3;
  spec.rows = 2;
  spec.family = "tag36h11";
  spec.tag_size_m = 0.04;
  spec.tag_spacing_m = 0.05;
  spec.first_id = 10;
  const Target target(spec);
  ASSERT_EQ(target.points().size(), 24u);
  // Tag k = 4 (row 1, col 1), corners top-left, top-right, bottom-right, bottom-left.
  EXPECT_TRUE(target.points()[16].isApprox(Eigen::Vector3d(0.05, 0.05, 0)));
  EXPECT_TRUE(target.points()[17].isApprox(Eigen::Vector3d(0.09, 0.05, 0)));
  EXPECT_TRUE(target.points()[18].isApprox(Eigen::Vector3d(0.09, 0.09, 0)));
  EXPECT_TRUE(target.points()[19].isApprox(Eigen::Vector3d(0.05, 0.09, 0)));
  EXPECT_EQ(target.tagIndex(14), 4);
  EXPECT_EQ(target.tagIndex(9), -1);
  EXPECT_EQ(target.tagIndex(16), -1);
  EXPECT_FALSE(target.isRotationallyAmbiguous());
}

TEST(Target, YamlRoundTripForEveryType) {
  const test::TempDir dir;
  for (const char* name :
       {"target_chessboard.yaml", "target_circles.yaml", "target_acircles.yaml", "target_apriltag.yaml"}) {
    const Target original = Target::fromFile(test::sourceDir() / "datasets" / "specs" / name);
    writeText(dir.path() / "copy.yaml", original.yamlString());
    const Target copy = Target::fromFile(dir.path() / "copy.yaml");
    EXPECT_EQ(copy.spec().type, original.spec().type) << name;
    EXPECT_EQ(copy.yamlString(), original.yamlString()) << name;
    ASSERT_EQ(copy.points().size(), original.points().size()) << name;
    for (std::size_t i = 0; i < copy.points().size(); ++i) EXPECT_EQ(copy.points()[i], original.points()[i]) << name;
  }
}

TEST(Target, BadSpecsAreRejectedNamingFileAndKey) {
  const test::TempDir dir;
  const auto path = dir.path() / "target.yaml";
  const auto expectError = [&](const std::string& text, const std::string& needle) {
    writeText(path, "%YAML:1.0\n---\n" + text);
    const std::string message = loadError(path);
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find(needle), std::string::npos) << "expected '" << needle << "' in: " << message;
  };
  expectError("cols: 9\nrows: 6\nsquare_size_m: 0.02\n", "missing key 'type'");
  expectError("type: hexagons\ncols: 9\nrows: 6\n", "'type'");
  expectError("type: chessboard\ncols: 9\nsquare_size_m: 0.02\n", "missing key 'rows'");
  expectError("type: chessboard\ncols: 9.5\nrows: 6\nsquare_size_m: 0.02\n", "key 'cols': '9.5' is not an integer");
  expectError("type: chessboard\ncols: 9\nrows: 6\nsquare_size_m: -0.02\n", "'square_size_m'");
  expectError("type: chessboard\ncols: 2\nrows: 6\nsquare_size_m: 0.02\n", "at least 3");
  expectError("type: circles\ncols: 9\nrows: 6\nspacing_m: 0.02\n", "missing key 'diameter_m'");
  expectError("type: circles\ncols: 9\nrows: 6\nspacing_m: 0.02\ndiameter_m: 0.03\n", "diameter_m must be smaller");
  expectError("type: apriltag\ncols: 3\nrows: 2\nfamily: tag99h1\ntag_size_m: 0.04\ntag_spacing_m: 0.05\n",
              "unknown AprilTag family");
  expectError("type: apriltag\ncols: 3\nrows: 2\nfamily: tag36h11\ntag_size_m: 0.04\ntag_spacing_m: 0.03\n",
              "tag_spacing_m");
  expectError(
      "type: apriltag\ncols: 3\nrows: 2\nfamily: tag36h11\ntag_size_m: 0.04\ntag_spacing_m: 0.05\nfirst_id: 584\n",
      "do not exist");
  writeText(path, "type: [unclosed\n");
  EXPECT_NE(loadError(path).find(path.string()), std::string::npos);
  EXPECT_NE(loadError(dir.path() / "absent.yaml").find("absent.yaml"), std::string::npos);
}

}  // namespace
}  // namespace mire::metrology
