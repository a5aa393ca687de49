#include "mire/datasets/data_dir.hpp"

#include <cstdlib>
#include <stdexcept>
#include <system_error>
#include <vector>

namespace mire::datasets {
namespace {

namespace fs = std::filesystem;

bool holdsSpecs(const fs::path& folder) {
  std::error_code error;
  return fs::is_directory(folder / "specs", error);
}

// <exe>/../share/mire, or empty when the executable's path cannot be read (/proc absent).
fs::path besideExecutable() {
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (error || exe.empty()) return {};
  return (exe.parent_path() / ".." / "share" / "mire").lexically_normal();
}

}  // namespace

fs::path dataDirectory() {
  if (const char* env = std::getenv("MIRE_DATA_DIR"); env != nullptr && *env != '\0') {
    if (holdsSpecs(env)) return fs::path(env);
    throw std::runtime_error("MIRE_DATA_DIR=" + std::string(env) + " holds no specs/ folder");
  }
  const std::vector<fs::path> candidates = {besideExecutable(), fs::path(MIRE_INSTALL_DATA_DIR)};
  std::string tried;
  for (const fs::path& candidate : candidates) {
    if (candidate.empty()) continue;
    if (holdsSpecs(candidate)) return candidate;
    tried += (tried.empty() ? "" : ", ") + candidate.string();
  }
  throw std::runtime_error("mire's data (specs/*.yaml) not found in " + tried +
                           "; set MIRE_DATA_DIR to the folder holding specs/ (share/mire of the install)");
}

fs::path specPath(const std::string& name) { return dataDirectory() / "specs" / name; }

}  // namespace mire::datasets
