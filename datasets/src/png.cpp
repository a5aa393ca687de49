// PNG encoding of the simulated images (png.hpp): libpng for the stored (uncompressed) files.
#include "mire/datasets/png.hpp"

#include "mire/support/atomic_file.hpp"

#include <opencv2/imgcodecs.hpp>

#include <png.h>

#include <csetjmp>
#include <stdexcept>
#include <vector>

namespace mire::datasets {
namespace {

// The output buffer is reserved once at its largest possible size, so appending never
// allocates (nothing may throw through libpng's C frames).
struct Sink {
  std::string* bytes = nullptr;
  bool overflow = false;
};

void appendBytes(png_structp png, png_bytep data, png_size_t size) {
  auto* sink = static_cast<Sink*>(png_get_io_ptr(png));
  if (sink->bytes->size() + size > sink->bytes->capacity()) {
    sink->overflow = true;
    png_error(png, "output buffer too small");
  }
  sink->bytes->append(reinterpret_cast<const char*>(data), size);
}

void flushNothing(png_structp) {}

// libpng reports errors by longjmp to here: no object with a destructor lives in this frame.
bool encodeStored(png_structp png, png_infop info, const cv::Mat& gray, Sink* sink) {
  if (setjmp(png_jmpbuf(png))) return false;
  png_set_write_fn(png, sink, appendBytes, flushNothing);
  png_set_IHDR(png, info, static_cast<png_uint_32>(gray.cols), static_cast<png_uint_32>(gray.rows), 8,
               PNG_COLOR_TYPE_GRAY, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_BASE, PNG_FILTER_TYPE_BASE);
  // No filter and zlib level 0 (stored blocks): the bytes are the pixels, plus framing.
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_NONE);
  png_set_compression_level(png, 0);
  png_write_info(png, info);
  for (int row = 0; row < gray.rows; ++row) png_write_row(png, gray.ptr<png_byte>(row));
  png_write_end(png, nullptr);
  return true;
}

// Largest stored PNG of `raw` filtered bytes: zlib adds 5 bytes per stored block (blocks of
// at least a few KiB), PNG 12 bytes per IDAT chunk (8 KiB chunks), plus fixed headers.
std::size_t storedPngBound(std::size_t raw) { return raw + raw / 64 + 4096; }

}  // namespace

std::string encodePng(const cv::Mat& gray, PngEncoding encoding) {
  if (gray.empty() || gray.type() != CV_8UC1)
    throw std::invalid_argument("encodePng expects a non-empty 8-bit grey image (CV_8UC1)");
  if (encoding == PngEncoding::Compressed) {
    std::vector<unsigned char> bytes;
    if (!cv::imencode(".png", gray, bytes)) throw std::runtime_error("PNG encoding failed (OpenCV)");
    return std::string(bytes.begin(), bytes.end());
  }
  std::string bytes;
  bytes.reserve(storedPngBound(static_cast<std::size_t>(gray.rows) * (static_cast<std::size_t>(gray.cols) + 1)));
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  Sink sink{&bytes, false};
  const bool ok = info != nullptr && encodeStored(png, info, gray, &sink);
  png_destroy_write_struct(&png, &info);
  if (!ok)
    throw std::runtime_error(sink.overflow ? "PNG encoding failed (output larger than expected)"
                                           : "PNG encoding failed (libpng)");
  return bytes;
}

void writePng(const std::filesystem::path& path, const cv::Mat& gray, PngEncoding encoding) {
  if (encoding == PngEncoding::Stored) {
    support::writeFileAtomically(path, encodePng(gray, encoding));
    return;
  }
  support::writeAtomically(
      path, [&](const std::filesystem::path& temporary) { return cv::imwrite(temporary.string(), gray); });
}

}  // namespace mire::datasets
