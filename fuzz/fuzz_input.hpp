#pragma once
// libFuzzer harness support: mire's readers take a path (their public signatures), so each
// input is written to a per-process scratch file (in /dev/shm when present: no disk I/O) and
// the reader is called on it. A reader may throw std::exception (that is its contract for bad
// input); anything else - a crash, a sanitizer report, a hang - is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>

namespace mire::fuzz {

inline std::filesystem::path scratchPath(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::exists("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
  return dir / ("mire-fuzz-" + std::to_string(::getpid()) + "-" + name);
}

inline void writeScratch(const std::filesystem::path& path, const std::uint8_t* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

// A scratch file removed when the fuzzer exits.
class ScratchFile {
 public:
  explicit ScratchFile(const std::string& name) : path_(scratchPath(name)) {}
  ~ScratchFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;
  operator const std::filesystem::path&() const { return path_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Splits an input in two at the first "\n====\n" (for readers that take two files).
inline std::pair<std::string, std::string> splitInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string separator = "\n====\n";
  const auto at = text.find(separator);
  if (at == std::string::npos) return {text, std::string()};
  return {text.substr(0, at), text.substr(at + separator.size())};
}

}  // namespace mire::fuzz
