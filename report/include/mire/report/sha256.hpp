#pragma once
// SHA-256 (FIPS 180-4) of a byte string or a file, as 64 lowercase hex digits: the checksums of a
// report's input files. A small implementation rather than a new dependency (no OpenSSL in mire).
#include <filesystem>
#include <string>
#include <string_view>

namespace mire::report {

std::string sha256Hex(std::string_view bytes);
// Reads the file in blocks; throws std::runtime_error naming the file when it cannot be read.
std::string sha256File(const std::filesystem::path& path);
// A folder's digest: the SHA-256 of its manifest, the lines "<sha256>  <path>\n" of its regular
// files, those of its sub-folders included, by relative path ("p001/img_00.png") in byte order
// (what `find . -type f | cut -c3- | LC_ALL=C sort | xargs sha256sum` prints there, so a reader can
// check it), and how many files that is.
struct FolderDigest {
  std::string sha256;
  std::size_t files = 0;
};
FolderDigest sha256Folder(const std::filesystem::path& folder);

}  // namespace mire::report
