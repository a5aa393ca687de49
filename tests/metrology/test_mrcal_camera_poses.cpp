// An mrcal .cameramodel and the equivalent camera.yaml give the same poses (doc/file-formats.md):
// rendered images of a chessboard measured through both files agree to well below 1 µm. The
// .cameramodel is written by mrcal itself (Debian's python3-mrcal, 10 significant digits) when
// it is installed, and otherwise by hand in mrcal's exact syntax (comments, Python literals,
// trailing commas).
#include "mire/calibration/camera_formats.hpp"
#include "mire/calibration/camera_io.hpp"
#include "mire/datasets/feature_campaign.hpp"
#include "mire/datasets/render.hpp"
#include "mire/metrology/pose_measurement.hpp"

#include "chessboard_views.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace mire::metrology {
namespace {

const char* kPython = "/usr/bin/python3";  // Debian's interpreter, where python3-mrcal lives

// mrcal's own writer, or the same text by hand ('%.10g' like mrcal's).
std::string writeCameramodel(const calibration::Camera& camera, const std::filesystem::path& path, bool* by_mrcal) {
  std::string values;
  for (const double value : camera.params) {
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%.10g, ", value);
    values += buffer;
  }
  const std::string size = std::to_string(camera.width) + ", " + std::to_string(camera.height);
  *by_mrcal = test::runCommand(std::string(kPython) + " -c 'import mrcal' >/dev/null 2>&1") == 0;
  if (*by_mrcal) {
    const std::string script =
        "import mrcal, numpy as np\nmrcal.cameramodel(intrinsics=('LENSMODEL_OPENCV5', "
        "np.array([" +
        values + "])), imagersize=(" + size + ")).write('" + path.string() + "')\n";
    test::writeText(path.string() + ".py", script);
    EXPECT_EQ(test::runCommand(std::string(kPython) + " " + path.string() + ".py"), 0);
  } else {
    test::writeText(path,
                    "# generated with mrcal-calibrate-cameras --lensmodel LENSMODEL_OPENCV5\n{\n"
                    "    'lensmodel':  'LENSMODEL_OPENCV5',\n\n"
                    "    # intrinsics are fx,fy,cx,cy,distortion-specific-params\n"
                    "    'intrinsics': [ " +
                        values +
                        "],\n\n    # extrinsics are rt_fromref\n    'extrinsics': [ 0, 0, 0, 0, 0, 0,],\n\n"
                        "    'imagersize': [ " +
                        size + ",],\n}\n");
  }
  return test::readText(path);
}

}  // namespace

TEST(MrcalCameraPoses, CameramodelAndCameraYamlGiveTheSamePoses) {
  const test::TempDir dir;
  calibration::Camera camera = datasets::referenceCamera();
  // Values with more digits than mrcal keeps, so that the file's rounding is exercised.
  camera.params = {817.2345678912,  816.98765432101, 511.4321098765,   383.6789012345,  -0.30123456789,
                   0.1012345678901, 4.123456789e-4,  -3.0987654321e-4, -0.0151234567891};
  test::writeText(dir.path() / "camera.yaml", calibration::cameraYamlString(camera));
  bool by_mrcal = false;
  const std::string text = writeCameramodel(camera, dir.path() / "camera.cameramodel", &by_mrcal);
  const calibration::Camera from_yaml = calibration::readCamera(dir.path() / "camera.yaml");
  const calibration::Camera from_mrcal = calibration::readCamera(dir.path() / "camera.cameramodel");
  ASSERT_EQ(from_mrcal.params.size(), camera.params.size()) << text;

  const Target target = test::chessboard9x6();
  const datasets::Renderer renderer(camera, target);
  double worst_t = 0.0, worst_r = 0.0;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Isometry3d pose = test::tiltedBoardPose(-0.1 + 0.06 * k, -0.06 + 0.04 * k, 0.5 + 0.05 * k, 25.0);
    const cv::Mat image = datasets::addNoise(renderer.render(pose).radiance, {1.0, 0.0}, 11 + k);
    const PoseMeasurement a = measurePose(from_yaml, target, {image}, {"a.png"});
    const PoseMeasurement b = measurePose(from_mrcal, target, {image}, {"a.png"});
    ASSERT_TRUE(a.ok && b.ok) << a.error << b.error;
    worst_t = std::max(worst_t, (a.estimate.translation - b.estimate.translation).norm());
    worst_r = std::max(worst_r, (a.estimate.rotation_vector - b.estimate.rotation_vector).norm());
  }
  std::printf(".cameramodel (%s) vs camera.yaml: poses differ by %.3g m and %.3g rad at most\n",
              by_mrcal ? "written by mrcal" : "mrcal's syntax by hand", worst_t, worst_r);
  EXPECT_LT(worst_t, 1e-6);
  EXPECT_LT(worst_r, 1e-6);
}

}  // namespace mire::metrology
