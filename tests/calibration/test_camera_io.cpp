// camera.yaml round trip and errors (doc/file-formats.md).
#include "mire/calibration/camera_io.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace mire::calibration {
namespace {

using test::writeText;

std::string loadError(const std::filesystem::path& path) {
  return test::runtimeErrorOf([&] { readCameraYaml(path); });
}

Camera cameraWithCovariance(int count) {
  std::vector<double> distortion = {-0.3, 0.1, 1e-3, -1e-3, -0.02, 0.01, -0.005, 0.002, 1e-3, -5e-4, 8e-4, -3e-4};
  distortion.resize(count);
  Camera camera = cameraFromOpenCV(1024, 768, 817.2043010752688, 816.5, 511.5, 383.5, distortion);
  camera.rms_px = 0.0731;
  const int n = static_cast<int>(camera.params.size());
  Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n) * 1e-3;
  camera.covariance = a * a.transpose();
  camera.covariance(4, 4) = 0.0;  // a fixed parameter
  camera.covariance.row(4).setZero();
  camera.covariance.col(4).setZero();
  return camera;
}

TEST(CameraIo, YamlRoundTripIsExact) {
  const test::TempDir dir;
  for (const int count : {4, 5, 8, 12}) {
    const Camera camera = cameraWithCovariance(count);
    writeText(dir.path() / "camera.yaml", cameraYamlString(camera));
    const Camera copy = readCameraYaml(dir.path() / "camera.yaml");
    EXPECT_EQ(copy.width, camera.width);
    EXPECT_EQ(copy.height, camera.height);
    EXPECT_EQ(copy.params, camera.params) << count;
    EXPECT_EQ(copy.rms_px, camera.rms_px);
    EXPECT_EQ(copy.covariance, camera.covariance) << count;
  }
  // Without covariance.
  Camera plain = cameraWithCovariance(5);
  plain.covariance.resize(0, 0);
  writeText(dir.path() / "plain.yaml", cameraYamlString(plain));
  EXPECT_EQ(readCameraYaml(dir.path() / "plain.yaml").covariance.size(), 0);
}

TEST(CameraIo, ReadsTheReferenceCameraAndReorderedCovariances) {
  const Camera reference = readCameraYaml(test::sourceDir() / "datasets/specs/reference_camera.yaml");
  EXPECT_EQ(reference.width, 1024);
  EXPECT_EQ(reference.distortionCount(), 5);
  EXPECT_NEAR(reference.fx(), 817.2043010752688, 1e-12);
  EXPECT_DOUBLE_EQ(reference.params[4], -0.30);

  const test::TempDir dir;
  writeText(
      dir.path() / "camera.yaml",
      "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
      "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 500., 0., 320., 0., 501., 240., "
      "0., 0., 1. ]\n"
      "distortion_coefficients: !!opencv-matrix\n   rows: 4\n   cols: 1\n   dt: d\n   data: [ -0.1, 0.01, 0., 0. ]\n"
      "covariance: !!opencv-matrix\n   rows: 8\n   cols: 8\n   dt: d\n"
      "   data: [ 4., 0., 0., 0., 0., 0., 0., 0.,  0., 1., 0., 0., 0., 0., 0., 0.,  0., 0., 1., 0., 0., 0., 0., 0.,\n"
      "           0., 0., 0., 1., 0., 0., 0., 0.,  0., 0., 0., 0., 1., 0., 0., 0.,  0., 0., 0., 0., 0., 1., 0., 0.,\n"
      "           0., 0., 0., 0., 0., 0., 1., 0.,  0., 0., 0., 0., 0., 0., 0., 9. ]\n"
      "covariance_parameters: [ cy, fx, fy, cx, k1, k2, p1, p2 ]\n");
  const Camera reordered = readCameraYaml(dir.path() / "camera.yaml");
  EXPECT_EQ(reordered.sigmas(), (std::vector<double>{1, 1, 1, 2, 1, 1, 1, 3}));  // cy's 4 is variance 4 → σ 2
}

TEST(CameraIo, BadFilesNameTheFileAndTheKey) {
  const test::TempDir dir;
  const auto path = dir.path() / "camera.yaml";
  const std::string k =
      "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ 500., 0., 320., 0., 500., 240., "
      "0., 0., 1. ]\n";
  const auto d = [](int n) {
    std::string text = "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: " + std::to_string(n) +
                       "\n   dt: d\n   data: [ ";
    for (int i = 0; i < n; ++i) text += std::string(i ? ", " : "") + "0.";
    return text + " ]\n";
  };
  const std::string size = "image_width: 640\nimage_height: 480\n";
  const auto expectError = [&](const std::string& text, const std::string& needle) {
    writeText(path, "%YAML:1.0\n---\n" + text);
    const std::string message = loadError(path);
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    EXPECT_NE(message.find(needle), std::string::npos) << "expected '" << needle << "' in: " << message;
  };
  expectError("image_height: 480\n" + k + d(5), "missing key 'image_width'");
  expectError("image_width: -640\nimage_height: 480\n" + k + d(5),
              "key 'image_width': -640 is out of range (1..100000)");
  expectError(size + d(5), "missing key 'camera_matrix'");
  expectError(size + "camera_matrix: [1, 2, 3]\n" + d(5), "'camera_matrix'");
  expectError(size + k, "missing key 'distortion_coefficients'");
  expectError(size + k + d(6), "'distortion_coefficients': has 6 values");
  expectError(size + k + d(14), "'distortion_coefficients': has 14 values");
  expectError(size + k + d(5) + "model: fisheye\n", "'model'");
  expectError(size + k + d(5) + "rms_px: fast\n", "'rms_px'");
  expectError(
      size + k + d(5) + "covariance: !!opencv-matrix\n   rows: 2\n   cols: 2\n   dt: d\n   data: [ 1., 0., 0., 1. ]\n",
      "'covariance': must be 9x9");
  expectError(size + k + d(5) + "sigma: [ 1, 2 ]\n", "'sigma'");
  expectError(size +
                  "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n   data: [ -500., 0., 320., 0., "
                  "500., 240., 0., 0., 1. ]\n" +
                  d(5),
              "focal lengths must be positive");
  writeText(path, "image_width: [unclosed\n");
  EXPECT_NE(loadError(path).find(path.string()), std::string::npos);
  EXPECT_NE(loadError(dir.path() / "absent.yaml").find("file not found"), std::string::npos);
}

}  // namespace
}  // namespace mire::calibration
