// cameraVispXmlString read back by ViSP's own parser (lives with the metrology tests, the
// suite that links ViSP).
#include "mire/calibration/camera_io.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>
#include <visp3/core/vpCameraParameters.h>
#include <visp3/core/vpXmlParserCamera.h>

#include <fstream>

namespace mire::calibration {
namespace {

TEST(CameraVispXml, LoadsInVispsParserWithTheFittedDistortion) {
  const Camera camera = readCameraYaml(test::sourceDir() / "datasets/specs/reference_camera.yaml");
  const test::TempDir dir;
  const auto path = dir.path() / "camera.xml";
  {
    std::ofstream out(path);
    out << cameraVispXmlString(camera, "reference <camera>");
  }
  vpXmlParserCamera parser;
  vpCameraParameters parameters;
  ASSERT_EQ(parser.parse(parameters, path.string(), "reference <camera>",
                         vpCameraParameters::perspectiveProjWithDistortion, 1024, 768),
            vpXmlParserCamera::SEQUENCE_OK);
  EXPECT_DOUBLE_EQ(parameters.get_px(), camera.fx());
  EXPECT_DOUBLE_EQ(parameters.get_py(), camera.fy());
  EXPECT_DOUBLE_EQ(parameters.get_u0(), camera.cx());
  EXPECT_DOUBLE_EQ(parameters.get_v0(), camera.cy());
  // ViSP's single term must describe the image like OpenCV's five do, to within the
  // residual of a one-term fit: compare a ray near the image corner.
  const Eigen::Vector2d corner_pixel(40.0, 30.0);
  Eigen::Vector2d ray;
  ASSERT_TRUE(camera.unproject(corner_pixel, &ray));
  const double r2 = ray.squaredNorm();
  const double u = parameters.get_u0() + parameters.get_px() * ray.x() * (1.0 + parameters.get_kud() * r2);
  const double v = parameters.get_v0() + parameters.get_py() * ray.y() * (1.0 + parameters.get_kud() * r2);
  EXPECT_LT((Eigen::Vector2d(u, v) - corner_pixel).norm(), 30.0);
  EXPECT_LT(parameters.get_kud(), 0.0);  // barrel, as k1
  EXPECT_GT(parameters.get_kdu(), 0.0);
}

}  // namespace
}  // namespace mire::calibration
