// Stored PNG files (datasets/include/mire/datasets/png.hpp): ordinary PNG files that
// OpenCV reads back pixel for pixel, uncompressed; the spec key chooses the encoding.
#include "mire/datasets/png.hpp"
#include "mire/datasets/simulation.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <fstream>

namespace mire::datasets {
namespace {

namespace fs = std::filesystem;

cv::Mat noisyImage(int width, int height) {
  cv::Mat image(height, width, CV_8U);
  cv::RNG(7).fill(image, cv::RNG::UNIFORM, 0, 256);
  return image;
}

TEST(Png, StoredFilesReadBackExactly) {
  for (const cv::Size size : {cv::Size(1024, 768), cv::Size(1, 1), cv::Size(3000, 7)}) {
    const cv::Mat image = noisyImage(size.width, size.height);
    const std::string bytes = encodePng(image, PngEncoding::Stored);
    const std::size_t raw = image.total() + static_cast<std::size_t>(image.rows);  // a filter byte per row
    EXPECT_GE(bytes.size(), raw);
    EXPECT_LT(bytes.size(), raw + raw / 64 + 4096);
    const cv::Mat back = cv::imdecode(std::vector<unsigned char>(bytes.begin(), bytes.end()), cv::IMREAD_UNCHANGED);
    ASSERT_EQ(back.type(), CV_8UC1);
    ASSERT_EQ(back.size(), image.size());
    EXPECT_EQ(cv::norm(back, image, cv::NORM_INF), 0.0);
  }
}

TEST(Png, CompressedAndStoredFilesHoldTheSamePixels) {
  const test::TempDir dir;
  cv::Mat image(480, 640, CV_8U, cv::Scalar(110));
  cv::circle(image, {320, 240}, 100, cv::Scalar(25), cv::FILLED);
  writePng(dir.path() / "stored.png", image, PngEncoding::Stored);
  writePng(dir.path() / "compressed.png", image, PngEncoding::Compressed);
  EXPECT_GT(fs::file_size(dir.path() / "stored.png"), 10 * fs::file_size(dir.path() / "compressed.png"));
  for (const char* name : {"stored.png", "compressed.png"})
    EXPECT_EQ(cv::norm(cv::imread((dir.path() / name).string(), cv::IMREAD_UNCHANGED), image, cv::NORM_INF), 0.0) << name;
}

TEST(Png, OnlyGreyBytesAreAccepted) {
  EXPECT_THROW(encodePng(cv::Mat(), PngEncoding::Stored), std::invalid_argument);
  EXPECT_THROW(encodePng(cv::Mat(4, 4, CV_8UC3, cv::Scalar::all(1)), PngEncoding::Stored), std::invalid_argument);
  EXPECT_THROW(encodePng(cv::Mat(4, 4, CV_16U, cv::Scalar(1)), PngEncoding::Compressed), std::invalid_argument);
}

TEST(Png, SpecKeyChoosesTheEncoding) {
  const test::TempDir dir;
  for (const char* file : {"reference_camera.yaml", "target_chessboard.yaml"})
    fs::copy_file(test::sourceDir() / "datasets/specs" / file, dir.path() / file);
  const auto read = [&](const std::string& extra) {
    const auto path = dir.path() / "spec.yaml";
    std::ofstream(path, std::ios::binary) << "camera: reference_camera.yaml\ntarget: target_chessboard.yaml\n" << extra;
    return readSimulationSpec(path);
  };
  EXPECT_EQ(read("").png, PngEncoding::Compressed);
  EXPECT_EQ(read("png: stored\n").png, PngEncoding::Stored);
  EXPECT_EQ(read("png: compressed\n").png, PngEncoding::Compressed);
  try {
    read("png: fast\n");
    ADD_FAILURE() << "png: fast was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'fast' is not one of compressed, stored"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mire::datasets
