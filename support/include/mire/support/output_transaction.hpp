#pragma once
// All-or-nothing outputs for commands that write several files or folders: every output is
// first written to a temporary beside its final path, then all temporaries are renamed in the
// order they were staged, and only after every one of them was written (doc/robustness.md).
// Temporaries not committed are removed by the destructor, and by the SIGINT/SIGTERM cleanup
// of installInterruptCleanup() when the run is interrupted.
#include <filesystem>
#include <mutex>
#include <string>
#include <vector>

namespace mire::support {

class OutputTransaction {
 public:
  OutputTransaction() = default;
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;

  // A temporary file path beside `final_path` (same folder, same extension) to write into.
  std::filesystem::path stageFile(const std::filesystem::path& final_path);
  // How a staged folder lands on an existing final folder: its files moved in one by one
  // (other files there are kept: report folders), or the whole folder replaced (datasets).
  enum class FolderCommit { MergeFiles, ReplaceWhole };
  // A fresh empty temporary folder beside `final_path`, to fill.
  std::filesystem::path stageFolder(const std::filesystem::path& final_path,
                                    FolderCommit mode = FolderCommit::MergeFiles);
  // Renames every temporary onto its final path, in staging order. Throws std::runtime_error
  // naming the path on failure.
  void commit();

 private:
  struct Entry {
    std::filesystem::path temporary, final_path;
    bool folder = false;
    FolderCommit mode = FolderCommit::MergeFiles;
  };
  void commitFolder(const Entry& entry);
  std::vector<Entry> entries_;
  bool committed_ = false;
};

// Installs (once per process; call it from the main thread before starting any other thread)
// the SIGINT/SIGTERM cleanup: the signals are blocked in every thread and received by one
// thread of their own, which removes the temporaries of every live OutputTransaction and of
// writeAtomically — even while workers still write into them — then exits with 128 + the
// signal number.
void installInterruptCleanup();

// Registers / unregisters a temporary path for the interrupt cleanup (used by the writers above).
void registerTemporary(const std::filesystem::path& path);
void unregisterTemporary(const std::filesystem::path& path);

// Holds the interrupt cleanup off while temporaries are renamed onto their final paths: an
// interrupt then lands before the renames or after them, never between two.
[[nodiscard]] std::unique_lock<std::recursive_mutex> holdInterruptCleanup();

}  // namespace mire::support
