#include "mire/support/atomic_file.hpp"
#include "mire/support/output_transaction.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <random>
#include <stdexcept>
#include <system_error>

namespace mire::support {
namespace fs = std::filesystem;

namespace {
fs::path temporaryBeside(const fs::path& path) {
  std::random_device device;
  const auto tag = std::to_string(device());
  return path.parent_path() / (".tmp-" + tag + "-" + path.filename().string());
}
// The path a user asked for: a staged temporary (".tmp-<tag>-out.csv", also nested) is named by
// its final name, which is what the user can act on.
fs::path finalName(const fs::path& path) {
  std::string name = path.filename().string();
  while (name.rfind(".tmp-", 0) == 0 && name.find('-', 5) != std::string::npos)
    name = name.substr(name.find('-', 5) + 1);
  return path.parent_path() / name;
}
}  // namespace

void writeAtomically(const fs::path& path, const std::function<bool(const fs::path&)>& writer) {
  if (!path.parent_path().empty()) {
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    if (ec) throw std::runtime_error(path.parent_path().string() + ": cannot create folder: " + ec.message());
  }
  const fs::path temporary = temporaryBeside(path);
  registerTemporary(temporary);  // removed by the interrupt cleanup if the run is stopped
  // Declared before `unregister`, so released after it: the rename and the unregistration
  // happen under the hold together.
  std::unique_lock<std::recursive_mutex> hold;
  struct Unregister {
    const fs::path& path;
    ~Unregister() { unregisterTemporary(path); }
  } const unregister{temporary};
  bool written = false;
  try {
    written = writer(temporary);
  } catch (...) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
  hold = holdInterruptCleanup();
  std::error_code ec;
  if (!written || !fs::exists(temporary)) {
    fs::remove(temporary, ec);
    throw std::runtime_error(finalName(path).string() + ": could not be written");
  }
  fs::rename(temporary, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw std::runtime_error(path.string() + ": cannot replace: " + ec.message());
  }
}

void writeFileAtomically(const fs::path& path, std::string_view contents) {
  writeAtomically(path, [&](const fs::path& temporary) {
    errno = 0;
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out.write(contents.data(), static_cast<std::streamsize>(contents.size()));
    out.close();
    // The reason (e.g. "No space left on device") with the name the user gave.
    if (!out && errno != 0)
      throw std::runtime_error(finalName(path).string() + ": cannot be written: " + std::strerror(errno));
    return static_cast<bool>(out);
  });
}

}  // namespace mire::support
