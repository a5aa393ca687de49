#pragma once
// A thread-safe progress bar on stderr, drawn only when stderr is a terminal.
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace mire::support {

class Progress {
 public:
  Progress(std::string label, std::size_t total);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Marks `count` more items done; safe to call from worker threads.
  void advance(std::size_t count = 1);
  // Erases the bar (also done by the destructor).
  void finish();

 private:
  void draw(bool force);

  std::string label_;
  std::size_t total_;
  std::size_t done_ = 0;
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
  std::mutex mutex_;
};

}  // namespace mire::support
