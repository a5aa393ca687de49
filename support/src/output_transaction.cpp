#include "mire/support/output_transaction.hpp"

#include <dirent.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <csignal>
#include <cstring>
#include <random>
#include <stdexcept>
#include <system_error>

namespace mire::support {
namespace fs = std::filesystem;

namespace {

// The interrupt handler may only call async-signal-safe functions, so the temporaries live in
// fixed slots of plain characters (the one process-wide state here: a signal handler has no
// other way to reach them).
constexpr std::size_t kSlots = 256, kPathChars = 4096;
struct Slot {
  std::atomic<bool> used{false};
  char path[kPathChars] = {};
};
std::array<Slot, kSlots>& slots() {
  static std::array<Slot, kSlots> table;
  return table;
}

// Removes a file, or a folder and what it holds down to a few levels (mire's outputs are
// at most three deep: DIR/poses/<id>/img.png). Async-signal-safe calls only.
void removeRaw(const char* path, int depth = 4) {
  if (::unlink(path) == 0 || depth == 0) return;
  if (DIR* dir = ::opendir(path)) {
    char child[kPathChars];
    while (const dirent* entry = ::readdir(dir)) {
      if (std::strcmp(entry->d_name, ".") == 0 || std::strcmp(entry->d_name, "..") == 0) continue;
      const std::size_t a = std::strlen(path), b = std::strlen(entry->d_name);
      if (a + b + 2 > kPathChars) continue;
      std::memcpy(child, path, a);  // NOLINT(bugprone-not-null-terminated-result): d_name's '\0' ends it below
      child[a] = '/';
      std::memcpy(child + a + 1, entry->d_name, b + 1);
      removeRaw(child, depth - 1);
    }
    ::closedir(dir);
    ::rmdir(path);
  }
}

extern "C" void onInterrupt(int signal_number) {
  for (Slot& slot : slots())
    if (slot.used.load()) removeRaw(slot.path);
  ::_exit(128 + signal_number);
}

fs::path uniqueBeside(const fs::path& final_path, const std::string& kind) {
  std::random_device device;
  const fs::path parent = final_path.parent_path();
  const std::string name = final_path.filename().string();
  for (int attempt = 0; attempt < 100; ++attempt) {
    fs::path candidate = parent / (".tmp-" + kind + std::to_string(device()) + "-" + name);
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(candidate, ec))) return candidate;
  }
  throw std::runtime_error(final_path.string() + ": cannot choose a temporary name beside it");
}

void removeQuietly(const fs::path& path) {
  std::error_code ignored;
  fs::remove_all(path, ignored);
}

}  // namespace

void registerTemporary(const fs::path& path) {
  const std::string text = path.string();
  if (text.size() >= kPathChars) return;
  for (Slot& slot : slots()) {
    bool expected = false;
    if (!slot.used.load() && slot.used.compare_exchange_strong(expected, true)) {
      // Marked used before the path is complete: the handler then unlinks a prefix at worst,
      // which names no file of ours; the final byte makes it complete.
      std::memcpy(slot.path, text.c_str(), text.size() + 1);
      return;
    }
  }
}

void unregisterTemporary(const fs::path& path) {
  const std::string text = path.string();
  for (Slot& slot : slots())
    if (slot.used.load() && text == slot.path) {
      slot.used.store(false);
      return;
    }
}

void installInterruptCleanup() {
  static std::atomic<bool> installed{false};
  if (installed.exchange(true)) return;
  struct sigaction action {};
  action.sa_handler = onInterrupt;
  sigemptyset(&action.sa_mask);
  ::sigaction(SIGINT, &action, nullptr);
  ::sigaction(SIGTERM, &action, nullptr);
}

OutputTransaction::~OutputTransaction() {
  for (const Entry& entry : entries_) {
    if (!committed_) removeQuietly(entry.temporary);
    unregisterTemporary(entry.temporary);
  }
}

fs::path OutputTransaction::stageFile(const fs::path& final_path) {
  fs::path temporary = uniqueBeside(final_path, "");
  registerTemporary(temporary);
  entries_.push_back({temporary, final_path, false});
  return temporary;
}

fs::path OutputTransaction::stageFolder(const fs::path& final_path, FolderCommit mode) {
  fs::path temporary = uniqueBeside(final_path, "dir-");
  std::error_code ec;
  if (!final_path.parent_path().empty()) fs::create_directories(final_path.parent_path(), ec);
  registerTemporary(temporary);
  if (ec || !fs::create_directory(temporary, ec) || ec) {
    unregisterTemporary(temporary);
    throw std::runtime_error(final_path.string() + ": cannot create a folder beside it" +
                             (ec ? ": " + ec.message() : std::string()));
  }
  entries_.push_back({temporary, final_path, true, mode});
  return temporary;
}

void OutputTransaction::commitFolder(const Entry& entry) {
  std::error_code ec;
  if (!fs::is_directory(entry.final_path, ec)) {
    fs::rename(entry.temporary, entry.final_path, ec);
    if (ec) throw std::runtime_error(entry.final_path.string() + ": cannot create: " + ec.message());
    return;
  }
  if (entry.mode == FolderCommit::MergeFiles) {
    for (const auto& child : fs::directory_iterator(entry.temporary)) {
      fs::rename(child.path(), entry.final_path / child.path().filename(), ec);
      if (ec) throw std::runtime_error((entry.final_path / child.path().filename()).string() + ": cannot replace: " + ec.message());
    }
    removeQuietly(entry.temporary);
    return;
  }
  // A folder cannot be renamed onto a non-empty one: move the old one aside first.
  const fs::path previous = uniqueBeside(entry.final_path, "old-");
  fs::rename(entry.final_path, previous, ec);
  if (ec) throw std::runtime_error(entry.final_path.string() + ": cannot replace: " + ec.message());
  registerTemporary(previous);
  fs::rename(entry.temporary, entry.final_path, ec);
  if (ec) {
    std::error_code ignored;
    fs::rename(previous, entry.final_path, ignored);
    unregisterTemporary(previous);
    throw std::runtime_error(entry.final_path.string() + ": cannot replace: " + ec.message());
  }
  removeQuietly(previous);
  unregisterTemporary(previous);
}

void OutputTransaction::commit() {
  for (const Entry& entry : entries_) {
    std::error_code ec;
    if (!fs::exists(entry.temporary, ec))
      throw std::runtime_error(entry.final_path.string() + ": was not written");
  }
  for (const Entry& entry : entries_) {
    if (entry.folder) {
      commitFolder(entry);
    } else {
      std::error_code ec;
      fs::rename(entry.temporary, entry.final_path, ec);
      if (ec) throw std::runtime_error(entry.final_path.string() + ": cannot replace: " + ec.message());
    }
    unregisterTemporary(entry.temporary);
  }
  committed_ = true;
}

}  // namespace mire::support
