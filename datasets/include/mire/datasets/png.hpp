#pragma once
// PNG encoding of the simulated images (doc/detection-speed.md). OpenCV's PNG
// writer (zlib level 1, Sub filter) costs 7 ms to write and 4.5 ms to read back one noisy
// 1024x768 image; the same pixels stored without compression cost 0.7 ms and 0.6 ms, for
// twice the disk space (770 KiB against 406 KiB). Both are ordinary PNG files.
#include <opencv2/core.hpp>

#include <filesystem>
#include <string>

namespace mire::datasets {

enum class PngEncoding {
  Compressed,  // OpenCV's default (cv::imwrite)
  Stored,      // deflate "stored" blocks, no filter: fast to write and to read, larger
};

// The PNG file of an 8-bit grey image (CV_8UC1), as bytes. Throws std::invalid_argument for
// another image type, std::runtime_error if the encoder fails.
std::string encodePng(const cv::Mat& gray, PngEncoding encoding);

// Writes the image as PNG, atomically (support/atomic_file.hpp). Throws naming the path.
void writePng(const std::filesystem::path& path, const cv::Mat& gray, PngEncoding encoding);

}  // namespace mire::datasets
