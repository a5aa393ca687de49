// `mire convert`: camera files between formats; every error exits 1, names the file (and line
// and key for YAML), writes nothing and leaves the input untouched.
#include "mire/calibration/camera_formats.hpp"
#include "mire/calibration/camera_io.hpp"

#include "test_support.hpp"

#include <fstream>
#include <sstream>

namespace mire {
namespace {

using test::writeText;

std::string convert(const std::string& arguments, int* code) {
  return test::captureCommand(test::mireBinary().string() + " convert " + arguments, code);
}

const std::filesystem::path kReference = test::sourceDir() / "datasets/specs/reference_camera.yaml";

TEST(ConvertCli, ChainThroughEveryFormatKeepsTheCamera) {
  const test::TempDir dir;
  const calibration::Camera reference = calibration::readCamera(kReference);
  int code = -1;
  // opencv -> ros -> opencv: exact.
  std::string out =
      convert("--camera " + kReference.string() + " -o " + (dir.path() / "ros.yaml").string() + " --to ros", &code);
  ASSERT_EQ(code, 0) << out;
  EXPECT_EQ(calibration::detectCameraFormat(dir.path() / "ros.yaml"), calibration::CameraFormat::Ros);
  out = convert("--camera " + (dir.path() / "ros.yaml").string() + " -o " + (dir.path() / "back.yaml").string(), &code);
  ASSERT_EQ(code, 0) << out;
  EXPECT_EQ(calibration::readCamera(dir.path() / "back.yaml").params, reference.params);
  // .xml -> visp, .cameramodel -> mrcal, from the extension. ViSP's model holds k1 only: refused
  // without --lossy, which writes it and says what is lost.
  out = convert("--camera " + kReference.string() + " -o " + (dir.path() / "camera.xml").string(), &code);
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("visp cannot hold this opencv5 camera: it would lose k2 p1 p2 k3"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "camera.xml"));
  out = convert("--camera " + kReference.string() + " -o " + (dir.path() / "camera.xml").string() + " --lossy", &code);
  ASSERT_EQ(code, 0) << out;
  EXPECT_EQ(calibration::detectCameraFormat(dir.path() / "camera.xml"), calibration::CameraFormat::Visp);
  EXPECT_EQ(calibration::readCamera(dir.path() / "camera.xml").fx(), reference.fx());
  out = convert("--camera " + kReference.string() + " -o " + (dir.path() / "camera.cameramodel").string(), &code);
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(test::readText(dir.path() / "camera.cameramodel").find("LENSMODEL_OPENCV5"), std::string::npos);
}

TEST(ConvertCli, ErrorsExitOneNameTheFileAndWriteNothing) {
  const test::TempDir dir;
  const auto input = dir.path() / "in.yaml";
  const auto output = dir.path() / "out.yaml";
  struct Case {
    std::string text;
    std::string arguments;
    std::string needle;
  };
  const std::string good = test::readText(kReference);
  std::string bad_key = good;
  bad_key.replace(bad_key.find("image_height"), 12, "image_heigth");
  const std::vector<Case> cases{
      {bad_key, "", "in.yaml:10: unknown key 'image_heigth' (did you mean 'image_height'?)"},
      {good + "image_width: 640\n", "", "in.yaml:22: key 'image_width' appears twice (first at line 9)"},
      {"image_width: [1\n", "", "in.yaml:2: invalid YAML"},
      {"", "", "in.yaml: empty file"},
      {good, " --to kalibr", "kalibr cannot hold this opencv5 camera: it would lose k3"},
      {"<root><camera><name>x</name></camera></root>\n", "",
       "in.yaml: no <camera> with a perspectiveProjWithDistortion"},
  };
  for (const Case& c : cases) {
    writeText(input, c.text);
    int code = -1;
    const std::string out = convert("--camera " + input.string() + " -o " + output.string() + c.arguments, &code);
    EXPECT_EQ(code, 1) << out;
    EXPECT_NE(out.find(c.needle), std::string::npos) << "expected '" << c.needle << "' in: " << out;
    EXPECT_FALSE(std::filesystem::exists(output)) << out;
    EXPECT_EQ(test::readText(input), c.text);
  }
  int code = -1;
  const std::string out = convert("--camera " + kReference.string() + " -o " + kReference.string(), &code);
  EXPECT_EQ(code, 1) << out;
  EXPECT_NE(out.find("the output is the input"), std::string::npos) << out;
  EXPECT_EQ(
      convert("--camera " + kReference.string() + " -o " + (dir.path() / "x.txt").string(), &code).find("give --to") !=
          std::string::npos,
      true);
  EXPECT_EQ(code, 2);
  convert("--camera " + kReference.string() + " -o " + output.string() + " --to nonsense", &code);
  EXPECT_EQ(code, 2);
  EXPECT_FALSE(std::filesystem::exists(output));
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "x.txt"));
}

}  // namespace
}  // namespace mire
