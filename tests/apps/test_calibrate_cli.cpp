// `mire calibrate`: bad input stops with a message naming the cause, a non-zero exit and no
// output file; a small rendered chessboard set calibrates end to end.
#include "mire/calibration/camera_io.hpp"
#include "mire/metrology/target.hpp"
#include "mire/support/atomic_file.hpp"

#include "test_support.hpp"

#include <Eigen/Geometry>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

constexpr int kCols = 9, kRows = 6;
constexpr double kSquare = 0.03;

void writeTarget(const fs::path& path) {
  mire::metrology::TargetSpec spec;
  spec.type = mire::metrology::TargetType::Chessboard;
  spec.cols = kCols;
  spec.rows = kRows;
  spec.square_size_m = kSquare;
  mire::support::writeFileAtomically(path, mire::metrology::Target(spec).yamlString());
}

std::size_t countOf(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// The report's figures (doc/plots.md) as standalone SVG files: the uncertainty map with one cell
// per 32 px of the 640 × 480 image and its colour bar, a residual vector per observed corner,
// one bar per used view, the model check's binned means.
void checkReportImages(const fs::path& report) {
  for (const char* name : {"residuals.svg", "projection_uncertainty.svg", "residuals_per_view.svg", "model_check.svg"}) {
    const std::string svg = mire::test::readText(report / name);
    EXPECT_EQ(svg.rfind("<?xml", 0), 0u) << name;
    EXPECT_NE(svg.find("<svg xmlns=\"http://www.w3.org/2000/svg\""), std::string::npos) << name;
    EXPECT_NE(svg.find("(px)"), std::string::npos) << name << ": an axis in pixels";
  }
  EXPECT_EQ(countOf(mire::test::readText(report / "projection_uncertainty.svg"), "class=\"cell\""), 20u * 15u);
  EXPECT_GT(countOf(mire::test::readText(report / "residuals.svg"), "class=\"vector\""), 7u * 40u);
  EXPECT_EQ(countOf(mire::test::readText(report / "residuals_per_view.svg"), "class=\"bar\""), 7u);
  EXPECT_GT(countOf(mire::test::readText(report / "model_check.svg"), "class=\"vector\""), 8u);
  for (const auto& entry : fs::directory_iterator(report)) EXPECT_NE(entry.path().extension(), ".png") << entry.path();
}

std::string calibrateCommand(const fs::path& dir, const fs::path& images, const fs::path& target) {
  return mire::test::mireBinary().string() + " calibrate --target " + target.string() + " --images " + images.string() +
         " -o " + (dir / "camera.yaml").string();
}

// A pinhole view (no distortion) of a chessboard by warping a flat texture through the
// homography K [r1 r2 t]: exact corners up to the resampling.
cv::Mat renderChessboard(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation) {
  const int square_px = 60, margin = 60;
  const int width_px = 2 * margin + (kCols + 1) * square_px, height_px = 2 * margin + (kRows + 1) * square_px;
  cv::Mat texture(height_px, width_px, CV_8U, cv::Scalar(255));
  for (int j = 0; j <= kRows; ++j)
    for (int i = 0; i <= kCols; ++i)
      if ((i + j) % 2 == 0)
        texture(cv::Rect(margin + i * square_px, margin + j * square_px, square_px, square_px)).setTo(cv::Scalar(0));
  // Texture pixel → target metres: inner corner (0, 0) lies on the edge at margin + square − 0.5.
  const double origin = margin + square_px - 0.5, scale = kSquare / square_px;
  Eigen::Matrix3d texture_to_metric;
  texture_to_metric << scale, 0, -origin * scale, 0, scale, -origin * scale, 0, 0, 1;
  Eigen::Matrix3d k;
  k << 600, 0, 319.5, 0, 600, 239.5, 0, 0, 1;
  Eigen::Matrix3d plane;
  plane << rotation.col(0), rotation.col(1), translation;
  const Eigen::Matrix3d h = k * plane * texture_to_metric;
  cv::Mat homography(3, 3, CV_64F);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) homography.at<double>(r, c) = h(r, c);
  cv::Mat image;
  cv::warpPerspective(texture, image, homography, cv::Size(640, 480), cv::INTER_AREA, cv::BORDER_CONSTANT,
                      cv::Scalar(128));
  return image;
}

// Seven views of the board, tilted up to 0.5 rad, about 0.55 m away: view0.png .. view6.png.
void writeChessboardViews(const fs::path& images) {
  fs::create_directories(images);
  const Eigen::Vector3d centre(0.5 * (kCols - 1) * kSquare, 0.5 * (kRows - 1) * kSquare, 0.0);
  const double tilts[][2] = {{0.5, 0.0},   {-0.5, 0.1},   {0.0, 0.5}, {0.1, -0.5},
                             {0.35, 0.35}, {-0.35, -0.3}, {0.2, -0.2}};
  int index = 0;
  for (const auto& tilt : tilts) {
    const Eigen::Matrix3d rotation =
        (Eigen::AngleAxisd(tilt[0], Eigen::Vector3d::UnitX()) * Eigen::AngleAxisd(tilt[1], Eigen::Vector3d::UnitY()))
            .toRotationMatrix();
    const Eigen::Vector3d translation =
        Eigen::Vector3d(0.01 * (index % 3 - 1), 0.01 * (index % 2), 0.55) - rotation * centre;
    cv::imwrite((images / ("view" + std::to_string(index++) + ".png")).string(), renderChessboard(rotation, translation));
  }
}

}  // namespace

TEST(CalibrateCli, EmptyFolderFailsWithoutOutput) {
  mire::test::TempDir dir;
  fs::create_directories(dir.path() / "images");
  writeTarget(dir.path() / "target.yaml");
  int code = 0;
  const std::string out =
      mire::test::captureCommand(calibrateCommand(dir.path(), dir.path() / "images", dir.path() / "target.yaml"), &code);
  EXPECT_NE(code, 0) << out;
  EXPECT_NE(out.find("no image"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir.path() / "camera.yaml"));
}

TEST(CalibrateCli, UnreadableImageIsNamed) {
  mire::test::TempDir dir;
  fs::create_directories(dir.path() / "images");
  writeTarget(dir.path() / "target.yaml");
  std::ofstream(dir.path() / "images" / "broken.png") << "this is not a PNG";
  int code = 0;
  const std::string out =
      mire::test::captureCommand(calibrateCommand(dir.path(), dir.path() / "images", dir.path() / "target.yaml"), &code);
  EXPECT_NE(code, 0) << out;
  EXPECT_NE(out.find("broken.png"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir.path() / "camera.yaml"));
}

TEST(CalibrateCli, BadTargetSpecIsNamed) {
  mire::test::TempDir dir;
  fs::create_directories(dir.path() / "images");
  cv::imwrite((dir.path() / "images" / "a.png").string(), cv::Mat(48, 64, CV_8U, cv::Scalar(200)));
  std::ofstream(dir.path() / "target.yaml") << "%YAML:1.0\n---\ntype: hexagons\ncols: 9\nrows: 6\n";
  int code = 0;
  const std::string out =
      mire::test::captureCommand(calibrateCommand(dir.path(), dir.path() / "images", dir.path() / "target.yaml"), &code);
  EXPECT_NE(code, 0) << out;
  EXPECT_NE(out.find("target"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir.path() / "camera.yaml"));
}

TEST(CalibrateCli, TooFewUsableViewsFailsWithoutOutput) {
  mire::test::TempDir dir;
  fs::create_directories(dir.path() / "images");
  writeTarget(dir.path() / "target.yaml");
  for (const char* name : {"a.png", "b.png"})
    cv::imwrite((dir.path() / "images" / name).string(), cv::Mat(480, 640, CV_8U, cv::Scalar(200)));
  int code = 0;
  const std::string out =
      mire::test::captureCommand(calibrateCommand(dir.path(), dir.path() / "images", dir.path() / "target.yaml"), &code);
  EXPECT_NE(code, 0) << out;
  EXPECT_NE(out.find("found in 0 of 2"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir.path() / "camera.yaml"));
}

TEST(CalibrateCli, CalibratesRenderedChessboards) {
  mire::test::TempDir dir;
  writeTarget(dir.path() / "target.yaml");
  writeChessboardViews(dir.path() / "images");
  // One image without the board: listed and skipped, not fatal.
  cv::imwrite((dir.path() / "images" / "zz_empty.png").string(), cv::Mat(480, 640, CV_8U, cv::Scalar(200)));
  int code = -1;
  const std::string out =
      mire::test::captureCommand(calibrateCommand(dir.path(), dir.path() / "images", dir.path() / "target.yaml") +
                                     " --model opencv4 --report " + (dir.path() / "report").string(),
                                 &code);
  ASSERT_EQ(code, 0) << out;
  EXPECT_NE(out.find("skipped zz_empty.png"), std::string::npos) << out;
  const auto camera = mire::calibration::readCameraYaml(dir.path() / "camera.yaml");
  EXPECT_NEAR(camera.fx(), 600.0, 3.0) << out;
  EXPECT_NEAR(camera.fy(), 600.0, 3.0) << out;
  EXPECT_NEAR(camera.cx(), 319.5, 3.0) << out;
  EXPECT_NEAR(camera.cy(), 239.5, 3.0) << out;
  EXPECT_LT(camera.rms_px, 0.3) << out;
  EXPECT_EQ(camera.sigmas().size(), 8u);
  EXPECT_TRUE(fs::exists(dir.path() / "report" / "residuals.svg"));
  EXPECT_TRUE(fs::exists(dir.path() / "report" / "projection_uncertainty.svg"));
  EXPECT_TRUE(fs::exists(dir.path() / "report" / "views.csv"));
  EXPECT_TRUE(fs::exists(dir.path() / "report" / "report.html"));
  checkReportImages(dir.path() / "report");
}

// The same images give the same camera.yaml, byte for byte, whatever --threads and on every run.
// With Ceres' threads (the solve used --threads until 2026-11) each thread summed the cost and
// gradient of the blocks it happened to take, and the last digits changed from run to run.
TEST(CalibrateCli, SameBytesWhateverTheThreads) {
  mire::test::TempDir dir;
  writeTarget(dir.path() / "target.yaml");
  writeChessboardViews(dir.path() / "images");
  std::vector<std::string> outputs;
  for (const char* threads : {"2", "2", "2", "1", "4"}) {
    int code = -1;
    const std::string out = mire::test::captureCommand(
        calibrateCommand(dir.path(), dir.path() / "images", dir.path() / "target.yaml") + " --threads " + threads, &code);
    ASSERT_EQ(code, 0) << out;
    outputs.push_back(mire::test::readText(dir.path() / "camera.yaml"));
  }
  for (std::size_t k = 1; k < outputs.size(); ++k) EXPECT_EQ(outputs[k], outputs[0]) << "run " << k;
}
