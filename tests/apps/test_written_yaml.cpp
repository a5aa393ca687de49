// The YAML files `mire simulate` writes load in PyYAML (OpenCV's matrices through a constructor
// for their tag, the rest as plain YAML) and in cv::FileStorage.
#include "test_support.hpp"

#include <opencv2/core.hpp>

#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

TEST(WrittenYaml, SimulatedTruthAndCameraLoadInPyYamlAndOpenCv) {
  if (mire::test::runCommand("/usr/bin/python3 -c 'import yaml' >/dev/null 2>&1") != 0)
    GTEST_SKIP() << "needs python3-yaml (Debian), absent: skipped";
  const mire::test::TempDir dir;
  // Plain YAML spec (no %YAML line, unquoted strings with trailing comments), tiny camera.
  std::ofstream(dir.path() / "board.yaml")
      << "%YAML:1.0\n---\ntype: chessboard\ncols: 5\nrows: 4\nsquare_size_m: 0.03\n";
  std::ofstream(dir.path() / "spec.yaml")
      << "camera:  # inline\n  image_width: 320\n  image_height: 240\n"
         "  camera_matrix: [255.4, 0, 159.5, 0, 255.4, 119.5, 0, 0, 1]\n"
         "  distortion_coefficients: [-0.30, 0.10, 4.0e-4, -3.0e-4, -0.015]\n"
         "target: board.yaml   # the board\nseed: 4\ncalibration: {views: 2, distance_m: [0.4, 0.5], margin_px: 5}\n";
  const fs::path out = dir.path() / "out";
  int code = -1;
  const std::string log =
      mire::test::captureCommand(mire::test::mireBinary().string() + " simulate calibration --spec " +
                                     (dir.path() / "spec.yaml").string() + " -o " + out.string(),
                                 &code);
  ASSERT_EQ(code, 0) << log;
  const std::string script =
      "import yaml,sys\n"
      "yaml.SafeLoader.add_constructor('tag:yaml.org,2002:opencv-matrix', lambda l, n: l.construct_mapping(n, "
      "deep=True))\n"
      "t = yaml.safe_load(open(sys.argv[1])); c = yaml.safe_load(open(sys.argv[2]))\n"
      "print(len(t['views']), t['views'][0]['features']['cols'], c['image_width'], c['camera_matrix']['data'][0])\n";
  const std::string output = mire::test::captureCommand(
      "/usr/bin/python3 -c \"" + script + "\" " + (out / "truth.yaml").string() + " " + (out / "camera.yaml").string(),
      &code);
  EXPECT_EQ(code, 0) << output;
  EXPECT_EQ(output, "2 3 320 255.4\n");
  cv::FileStorage truth((out / "truth.yaml").string(), cv::FileStorage::READ);
  ASSERT_TRUE(truth.isOpened());
  EXPECT_EQ(truth["views"].size(), 2u);
}

}  // namespace
