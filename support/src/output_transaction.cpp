#include "mire/support/output_transaction.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <mutex>
#include <random>
#include <stdexcept>
#include <system_error>
#include <thread>

namespace mire::support {
namespace fs = std::filesystem;

namespace {

// The temporaries the interrupt cleanup must remove. The cleanup runs in an ordinary thread
// (sigwait, below), not in a signal handler: a handler interrupting a thread inside malloc
// cannot safely open a folder. The mutex is recursive so that a commit can hold it across its
// renames and still unregister.
struct TemporaryRegistry {
  std::recursive_mutex mutex;
  std::vector<fs::path> paths;
};
TemporaryRegistry& registry() {
  static TemporaryRegistry table;  // the one process-wide state here: the signal thread's
  return table;
}

void removeQuietly(const fs::path& path) {
  std::error_code ignored;
  fs::remove_all(path, ignored);
}

// Other threads may still be writing into a temporary when the run is interrupted. Each
// temporary is moved aside and its name taken by a blocker of the other kind (a file where a
// folder was, a folder where a file was or will be), so that no writer can create anything
// there any more; then the moved-aside copy is removed until it stays removed.
fs::path blockAndMoveAside(const fs::path& temporary) {
  std::error_code ec;
  const bool was_folder = fs::is_directory(fs::symlink_status(temporary, ec));
  fs::path aside = temporary;
  aside += ".interrupted";
  fs::rename(temporary, aside, ec);
  if (was_folder) {
    const int fd = ::open(temporary.c_str(), O_CREAT | O_EXCL | O_WRONLY, 0600);
    if (fd >= 0) ::close(fd);
  } else {
    fs::create_directory(temporary, ec);
  }
  return aside;
}

void removeUntilGone(const fs::path& path) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    removeQuietly(path);
    std::error_code ec;
    if (!fs::exists(fs::symlink_status(path, ec))) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // a write in flight lands
  }
}

[[noreturn]] void cleanUpAndExit(int signal_number) {
  TemporaryRegistry& table = registry();
  table.mutex.lock();  // held until exit: no commit, registration or unregistration after this
  std::vector<fs::path> aside;
  for (const fs::path& temporary : table.paths) aside.push_back(blockAndMoveAside(temporary));
  for (const fs::path& path : aside) removeUntilGone(path);
  for (const fs::path& temporary : table.paths) removeQuietly(temporary);  // the blockers
  std::_Exit(128 + signal_number);
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

}  // namespace

void registerTemporary(const fs::path& path) {
  TemporaryRegistry& table = registry();
  const std::lock_guard<std::recursive_mutex> lock(table.mutex);
  table.paths.push_back(path);
}

void unregisterTemporary(const fs::path& path) {
  TemporaryRegistry& table = registry();
  const std::lock_guard<std::recursive_mutex> lock(table.mutex);
  const auto found = std::find(table.paths.begin(), table.paths.end(), path);
  if (found != table.paths.end()) table.paths.erase(found);
}

std::unique_lock<std::recursive_mutex> holdInterruptCleanup() {
  return std::unique_lock<std::recursive_mutex>(registry().mutex);
}

void installInterruptCleanup() {
  static std::atomic<bool> installed{false};
  if (installed.exchange(true)) return;
  // Blocked here, in the main thread, before any worker exists: every thread started later
  // inherits the mask, so the signals reach only the sigwait below.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  ::pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::thread([signals] {
    int signal_number = 0;
    while (::sigwait(&signals, &signal_number) != 0) {
    }
    cleanUpAndExit(signal_number);
  }).detach();
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
      if (ec)
        throw std::runtime_error((entry.final_path / child.path().filename()).string() +
                                 ": cannot replace: " + ec.message());
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
  const auto hold = holdInterruptCleanup();  // an interrupt lands before or after, not during
  for (const Entry& entry : entries_) {
    std::error_code ec;
    if (!fs::exists(entry.temporary, ec)) throw std::runtime_error(entry.final_path.string() + ": was not written");
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
