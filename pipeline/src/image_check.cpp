#include "mire/pipeline/image_check.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace mire::pipeline {
namespace fs = std::filesystem;

bool isImageFile(const fs::path& path) {
  static const std::set<std::string> kExtensions = {".png", ".jpg", ".jpeg", ".bmp", ".tif",  ".tiff",
                                                    ".pgm", ".ppm", ".pnm",  ".pbm", ".webp", ".jp2"};
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  return kExtensions.count(extension) > 0;
}

namespace {

struct Size {
  long long width = 0, height = 0;
};

std::uint32_t bigEndian(const std::vector<unsigned char>& b, std::size_t at, int bytes) {
  std::uint32_t value = 0;
  for (int i = 0; i < bytes; ++i) value = (value << 8) | b[at + static_cast<std::size_t>(i)];
  return value;
}

std::int32_t littleEndian32(const std::vector<unsigned char>& b, std::size_t at) {
  std::uint32_t value = 0;
  for (int i = 3; i >= 0; --i) value = (value << 8) | b[at + static_cast<std::size_t>(i)];
  return static_cast<std::int32_t>(value);
}

// JPEG: the first start-of-frame marker (SOF0..SOF15 but DHT, JPG, DAC) before the scan.
std::optional<Size> jpegSize(std::ifstream& in) {
  std::vector<unsigned char> b(4);
  in.seekg(2);
  while (in.read(reinterpret_cast<char*>(b.data()), 4)) {
    if (b[0] != 0xFF) return std::nullopt;
    const int marker = b[1];
    const std::uint32_t length = bigEndian(b, 2, 2);
    const bool sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (sof) {
      std::vector<unsigned char> f(5);
      if (!in.read(reinterpret_cast<char*>(f.data()), 5)) return std::nullopt;
      return Size{bigEndian(f, 3, 2), bigEndian(f, 1, 2)};
    }
    if (marker == 0xDA || length < 2) return std::nullopt;
    in.seekg(static_cast<std::streamoff>(length) - 2, std::ios::cur);
  }
  return std::nullopt;
}

// PNM: "Pn", then width and height as text, '#' comments allowed.
std::optional<Size> pnmSize(std::ifstream& in) {
  in.seekg(2);
  long long values[2] = {0, 0};
  for (long long& value : values) {
    int c = in.get();
    while (in && (std::isspace(c) || c == '#')) {
      if (c == '#')
        while (in && c != '\n') c = in.get();
      c = in.get();
    }
    if (!in || !std::isdigit(c)) return std::nullopt;
    for (int digits = 0; in && std::isdigit(c) && digits < 12; ++digits, c = in.get()) value = value * 10 + (c - '0');
  }
  return Size{values[0], values[1]};
}

// The last bytes of the file hold the format's end marker (PNG IEND chunk, JPEG EOI).
bool endsWithMarker(std::ifstream& in, const std::string& marker) {
  in.clear();
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  const std::streamoff tail = std::min<std::streamoff>(size, 4096);
  in.seekg(size - tail);
  std::string bytes(static_cast<std::size_t>(tail), '\0');
  in.read(bytes.data(), tail);
  return bytes.find(marker) != std::string::npos;
}

}  // namespace

void checkImageFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<unsigned char> head(26, 0);
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  const std::streamsize got = in.gcount();
  in.clear();
  std::optional<Size> size;
  std::string end_marker;
  if (got >= 24 && head[0] == 0x89 && head[1] == 'P' && head[2] == 'N' && head[3] == 'G') {
    size = Size{bigEndian(head, 16, 4), bigEndian(head, 20, 4)};
    end_marker = "IEND";
  } else if (got >= 4 && head[0] == 0xFF && head[1] == 0xD8) {
    size = jpegSize(in);
    end_marker = "\xFF\xD9";
  } else if (got >= 26 && head[0] == 'B' && head[1] == 'M') {
    size = Size{littleEndian32(head, 18), std::abs(static_cast<long long>(littleEndian32(head, 22)))};
  } else if (got >= 3 && head[0] == 'P' && head[1] >= '1' && head[1] <= '6') {
    size = pnmSize(in);
  }
  if (size &&
      (size->width > kMaxImageSide || size->height > kMaxImageSide || size->width * size->height > kMaxImagePixels)) {
    std::ostringstream message;
    message << "image '" << path.string() << "' is " << size->width << "x" << size->height
            << " px: mire reads images of at most " << kMaxImageSide << " px per side and "
            << kMaxImagePixels / 1'000'000 << " megapixels";
    throw std::runtime_error(message.str());
  }
  if (!end_marker.empty() && !endsWithMarker(in, end_marker))
    throw std::runtime_error("image '" + path.string() + "' is truncated (no end marker): copy it again");
}

}  // namespace mire::pipeline
