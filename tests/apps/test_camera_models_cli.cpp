// `mire calibrate --model pinhole|fisheye --fix ...` (doc/calibration.md) on real images:
// ViSP's circle photos with the pinhole model reproduce ViSP's published intrinsics, --fix
// prints "fixed" and keeps the value, and --refine-target on OpenCV's left*.jpg (Debian
// opencv-doc) writes finite numbers with cy consistent with the flat-board result.
#include "mire/calibration/camera_io.hpp"
#include "mire/metrology/target.hpp"
#include "mire/support/atomic_file.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace {

namespace fs = std::filesystem;

void writeVispTarget(const fs::path& path) {
  mire::metrology::TargetSpec spec;
  spec.type = mire::metrology::TargetType::Circles;
  spec.cols = 6;
  spec.rows = 6;
  spec.spacing_m = 0.034;
  spec.diameter_m = 0.017;
  mire::support::writeFileAtomically(path, mire::metrology::Target(spec).yamlString());
}

std::string calibrate(const fs::path& target, const fs::path& images, const fs::path& output, const std::string& extra,
                      int* code) {
  return mire::test::captureCommand(mire::test::mireBinary().string() + " calibrate --target " + target.string() +
                                        " --images " + images.string() + " -o " + output.string() + " " + extra,
                                    code);
}

}  // namespace

TEST(CameraModelsCli, VispCirclesWithThePinholeModelMatchVisp) {
  MIRE_REQUIRE_SHARED("datasets/external/visp-circles/circles-01.jpg");
  mire::test::TempDir dir;
  writeVispTarget(dir.path() / "target.yaml");
  int code = 0;
  const std::string out =
      calibrate(dir.path() / "target.yaml", mire::test::sharedDir() / "datasets/external/visp-circles",
                dir.path() / "camera.yaml", "--model pinhole", &code);
  ASSERT_EQ(code, 0) << out;
  const auto camera = mire::calibration::readCameraYaml(dir.path() / "camera.yaml");
  EXPECT_EQ(camera.modelName(), "pinhole");
  ASSERT_EQ(camera.params.size(), 4u);
  std::printf(
      "ViSP circles, --model pinhole: px %.4f py %.4f u0 %.4f v0 %.4f (ViSP 276.5098 272.9595 163.8652 113.3046)\n",
      camera.fx(), camera.fy(), camera.cx(), camera.cy());
  EXPECT_NEAR(camera.fx(), 276.5098, 0.5);
  EXPECT_NEAR(camera.fy(), 272.9595, 0.5);
  EXPECT_NEAR(camera.cx(), 163.8652, 0.5);
  EXPECT_NEAR(camera.cy(), 113.3046, 0.5);
}

TEST(CameraModelsCli, FixKeepsTheValueAndSaysSo) {
  MIRE_REQUIRE_SHARED("datasets/external/visp-circles/circles-01.jpg");
  mire::test::TempDir dir;
  writeVispTarget(dir.path() / "target.yaml");
  int code = 0;
  const std::string out =
      calibrate(dir.path() / "target.yaml", mire::test::sharedDir() / "datasets/external/visp-circles",
                dir.path() / "camera.yaml", "--model opencv4 --fix k2,p1,p2", &code);
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("k2 = 0.000000 (fixed)"), std::string::npos) << out;
  EXPECT_NE(out.find("p2 = 0.000000 (fixed)"), std::string::npos) << out;
  const auto camera = mire::calibration::readCameraYaml(dir.path() / "camera.yaml");
  EXPECT_EQ(camera.params[5], 0.0);
  EXPECT_EQ(camera.params[6], 0.0);
  EXPECT_EQ(camera.params[7], 0.0);
  EXPECT_NE(camera.params[4], 0.0);  // k1 free
  // An unknown name is an error naming it, nothing written.
  const std::string bad =
      calibrate(dir.path() / "target.yaml", mire::test::sharedDir() / "datasets/external/visp-circles",
                dir.path() / "other.yaml", "--model opencv4 --fix k3", &code);
  EXPECT_EQ(code, 1) << bad;
  EXPECT_NE(bad.find("k3"), std::string::npos) << bad;
  EXPECT_FALSE(fs::exists(dir.path() / "other.yaml"));
}

// --refine-target on OpenCV's 13 left*.jpg views: the refinement is weakly determined and moves
// cy beyond 3σ; both warnings are printed with their numbers and kept in report.json
// (doc/calibration.md, "Weakly determined target refinement").
TEST(CameraModelsCli, RefineTargetOnLeftJpgWarnsWithNumbers) {
  const fs::path samples = "/usr/share/doc/opencv-doc/examples/data";
  if (!fs::exists(samples / "left01.jpg"))
    GTEST_SKIP() << "needs OpenCV's left*.jpg (Debian opencv-doc, " << samples << "): absent, skipped";
  mire::test::TempDir dir;
  fs::create_directories(dir.path() / "left");
  for (const auto& entry : fs::directory_iterator(samples)) {
    const std::string name = entry.path().filename().string();
    if (name.size() == 10 && name.rfind("left", 0) == 0 && entry.path().extension() == ".jpg")
      fs::copy_file(entry.path(), dir.path() / "left" / name);
  }
  mire::metrology::TargetSpec spec;
  spec.cols = 9;
  spec.rows = 6;
  spec.square_size_m = 0.025;
  mire::support::writeFileAtomically(dir.path() / "target.yaml", mire::metrology::Target(spec).yamlString());
  int code = 0;
  const std::string out = calibrate(dir.path() / "target.yaml", dir.path() / "left", dir.path() / "camera.yaml",
                                    "--refine-target --threads 1 --report " + (dir.path() / "report").string(), &code);
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("warning: --refine-target is weakly determined by these views: its 155 extra unknowns"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("at the corner from 19.67 to 761.19 px"), std::string::npos) << out;
  EXPECT_NE(out.find("warning: --refine-target moved cy 233.923 -> 238.950 px (5.0 sigma)"), std::string::npos) << out;
  // The model check does not send the user back to --refine-target.
  EXPECT_EQ(out.find("--refine-target (a board that is not flat)"), std::string::npos) << out;
  const std::string report = mire::test::readText(dir.path() / "report" / "report.json");
  EXPECT_NE(report.find("\"target_refinement\""), std::string::npos);
  EXPECT_NE(report.find("\"weakly_determined\": true"), std::string::npos) << report.substr(0, 2000);
}
