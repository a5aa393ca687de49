// Kalibr's aprilgrid target file read as a mire target (doc/targets.md, "Kalibr aprilgrid"):
// the file as Kalibr spells it, the layout (tag 0 at the bottom-left of the printed board, ids
// up the page), the refusals, and mire's detection of a rendered aprilgrid (two-bit borders)
// against the renderer's corner truth.
#include "mire/datasets/feature_campaign.hpp"
#include "mire/datasets/render.hpp"
#include "mire/metrology/detection.hpp"
#include "mire/metrology/target.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace mire::metrology {
namespace {

const std::filesystem::path kSpec = "datasets/specs/target_kalibr_aprilgrid.yaml";  // 7 x 5 tags of 40 mm, 0.25

std::string loadError(const test::TempDir& dir, const std::string& text) {
  const auto path = dir.path() / "aprilgrid.yaml";
  test::writeText(path, text);
  try {
    (void)Target::fromFile(path);
  } catch (const std::exception& error) {
    return error.what();
  }
  return {};
}

}  // namespace

TEST(TargetKalibr, AprilgridFileAsKalibrWritesItGivesKalibrsLayout) {
  const Target target = Target::fromFile(test::sourceDir() / kSpec);
  const TargetSpec& spec = target.spec();
  EXPECT_EQ(spec.type, TargetType::AprilTag);
  EXPECT_EQ(spec.family, "tag36h11_border2");
  ASSERT_EQ(target.points().size(), 4u * 7 * 5);
  const double pitch = 0.04 * 1.25;
  // Tag 0 at the bottom-left of the printed board: in M (y down the page) its top-left corner
  // is on the last row; tag 7 (second row up) one pitch above it; tag 34 top-right.
  const auto corner = [&](int id, int j) { return target.points()[4 * target.tagIndex(id) + j]; };
  EXPECT_NEAR(corner(0, 0).x(), 0.0, 1e-12);
  EXPECT_NEAR(corner(0, 0).y(), 4 * pitch, 1e-12);
  EXPECT_NEAR(corner(0, 2).x(), 0.04, 1e-12);
  EXPECT_NEAR(corner(0, 2).y(), 4 * pitch + 0.04, 1e-12);
  EXPECT_NEAR(corner(1, 0).x(), pitch, 1e-12);
  EXPECT_NEAR(corner(7, 0).y(), 3 * pitch, 1e-12);
  EXPECT_NEAR(corner(34, 0).x(), 6 * pitch, 1e-12);
  EXPECT_NEAR(corner(34, 0).y(), 0.0, 1e-12);
  // Written back as mire's own target.yaml, it reads the same.
  const test::TempDir dir;
  test::writeText(dir.path() / "mire.yaml", target.yamlString());
  const Target again = Target::fromFile(dir.path() / "mire.yaml");
  ASSERT_EQ(again.points().size(), target.points().size());
  for (std::size_t i = 0; i < target.points().size(); ++i)
    EXPECT_NEAR((again.points()[i] - target.points()[i]).norm(), 0.0, 1e-15);
}

TEST(TargetKalibr, KalibrsOwnAprilgridFile) {
  MIRE_REQUIRE_SHARED("datasets/external/camera-files/kalibr_aprilgrid.yaml");
  const Target target = Target::fromFile(test::sharedDir() / "datasets/external/camera-files/kalibr_aprilgrid.yaml");
  ASSERT_EQ(target.points().size(), 4u * 6 * 6);
  // 0.088 m tags, tagSpacing 0.3: pitch 0.1144 m; tag 0 bottom-left, tag 35 top-right.
  EXPECT_NEAR(target.points()[4 * target.tagIndex(1)].x(), 0.1144, 1e-12);
  EXPECT_NEAR(target.points()[4 * target.tagIndex(0)].y(), 5 * 0.1144, 1e-12);
  EXPECT_NEAR(target.points()[4 * target.tagIndex(35)].y(), 0.0, 1e-12);
}

TEST(TargetKalibr, OtherKalibrTargetsAndBadValuesAreRefusedByName) {
  const test::TempDir dir;
  const std::string checkerboard = loadError(
      dir,
      "target_type: 'checkerboard'\ntargetCols: 6\ntargetRows: 7\nrowSpacingMeters: 0.06\ncolSpacingMeters: 0.06\n");
  EXPECT_NE(checkerboard.find("Kalibr target 'checkerboard'"), std::string::npos) << checkerboard;
  EXPECT_NE(checkerboard.find("aprilgrid"), std::string::npos) << checkerboard;
  const std::string millimetres =
      loadError(dir, "target_type: 'aprilgrid'\ntagCols: 6\ntagRows: 6\ntagSize: 88\ntagSpacing: 0.3\n");
  EXPECT_NE(millimetres.find("aprilgrid.yaml:4"), std::string::npos) << millimetres;
  EXPECT_NE(millimetres.find("tagSize"), std::string::npos) << millimetres;
  const std::string unknown = loadError(
      dir, "target_type: 'aprilgrid'\ntagCols: 6\ntagRows: 6\ntagSize: 0.088\ntagSpacing: 0.3\ntagSpace: 1\n");
  EXPECT_NE(unknown.find("tagSpace"), std::string::npos) << unknown;
  const std::string missing = loadError(dir, "target_type: 'aprilgrid'\ntagCols: 6\ntagRows: 6\ntagSize: 0.088\n");
  EXPECT_NE(missing.find("tagSpacing"), std::string::npos) << missing;
  const std::string too_many =
      loadError(dir, "target_type: 'aprilgrid'\ntagCols: 30\ntagRows: 20\ntagSize: 0.01\ntagSpacing: 0.3\n");
  EXPECT_NE(too_many.find("tag36h11 has 0..586"), std::string::npos) << too_many;
}

// The aprilgrid rendered as Kalibr prints its tags (two-bit black border): every tag found, the
// corners where the renderer put them; the plain one-bit tag36h11 reading of the same image
// decodes none of them (the border width is part of the family).
TEST(TargetKalibr, RenderedAprilgridCornersAgainstTruth) {
  const calibration::Camera camera = datasets::referenceCamera();
  const Target target = Target::fromFile(test::sourceDir() / kSpec);
  datasets::RenderOptions options;
  options.blur_sigma_px = 0.6;
  const datasets::Renderer renderer(camera, target, options);
  double sum_squared = 0.0, worst = 0.0;
  std::size_t count = 0;
  for (int v = 0; v < 3; ++v) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = (Eigen::AngleAxisd(10.0 * v * M_PI / 180, Eigen::Vector3d::UnitZ()) *
                     Eigen::AngleAxisd(20.0 * (v - 1) * M_PI / 180, Eigen::Vector3d::UnitY()))
                        .toRotationMatrix();
    pose.translation() = Eigen::Vector3d(-0.17 + 0.01 * v, -0.12, 0.5 + 0.05 * v);
    const auto rendering = renderer.render(pose);
    const cv::Mat image = datasets::addNoise(rendering.radiance, {1.0, 0.0}, 40 + v);
    const Detection detection = detectTarget(target, image);
    ASSERT_TRUE(detection.found) << detection.reason;
    EXPECT_EQ(detection.size(), target.points().size()) << "view " << v;
    for (std::size_t i = 0; i < detection.size(); ++i) {
      const double e = (detection.pixels[i] - rendering.truth.pixels[detection.ids[i]]).norm();
      sum_squared += e * e, worst = std::max(worst, e), ++count;
    }
    if (v == 0) {
      EXPECT_TRUE(detectAprilTags(image, "tag36h11", true).empty());
    }
  }
  const double rms = std::sqrt(sum_squared / count);
  std::printf("Kalibr aprilgrid renders: %zu tag corners, RMS %.4f px, worst %.3f px\n", count, rms, worst);
  // A wrong id order or frame shows as errors of a tag pitch (> 50 px here).
  EXPECT_LT(rms, 0.25);
  EXPECT_LT(worst, 0.8);
}

}  // namespace mire::metrology
