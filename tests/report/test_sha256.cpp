// SHA-256 against the FIPS 180-4 / NIST example vectors, and a file read in blocks.
#include "mire/report/sha256.hpp"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

using mire::report::sha256File;
using mire::report::sha256Hex;

TEST(Sha256, MatchesTheNistVectors) {
  EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  // 56 bytes: the padding spills into a second block.
  EXPECT_EQ(sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  EXPECT_EQ(sha256Hex(std::string(1000000, 'a')), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, FileEqualsItsBytesAndNamesAMissingFile) {
  const auto path = std::filesystem::temp_directory_path() / ("mire-sha256-" + std::to_string(::getpid()) + ".bin");
  std::string bytes;
  for (int i = 0; i < 200000; ++i) bytes += static_cast<char>((i * 7919) % 256);  // > one 64 kB read block
  std::ofstream(path, std::ios::binary) << bytes;
  EXPECT_EQ(sha256File(path), sha256Hex(bytes));
  std::filesystem::remove(path);
  try {
    sha256File(path);
    FAIL() << "a missing file must throw";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find(path.string()), std::string::npos) << error.what();
  }
}

TEST(Sha256, FolderDigestIsTheSha256sumManifest) {
  const auto folder = std::filesystem::temp_directory_path() / ("mire-sha256-dir-" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder / "sub");
  std::ofstream(folder / "b.png") << "bb";
  std::ofstream(folder / "a.png") << "a";
  const auto digest = mire::report::sha256Folder(folder);
  EXPECT_EQ(digest.files, 2u);  // the sub-folder is not a file
  EXPECT_EQ(digest.sha256, sha256Hex(sha256Hex("a") + "  a.png\n" + sha256Hex("bb") + "  b.png\n"));
  // A file in a sub-folder (one folder per pose) by its relative path.
  std::ofstream(folder / "sub" / "c.png") << "c";
  const auto nested = mire::report::sha256Folder(folder);
  EXPECT_EQ(nested.files, 3u);
  EXPECT_EQ(nested.sha256,
            sha256Hex(sha256Hex("a") + "  a.png\n" + sha256Hex("bb") + "  b.png\n" + sha256Hex("c") + "  sub/c.png\n"));
  std::filesystem::remove_all(folder);
}

}  // namespace
