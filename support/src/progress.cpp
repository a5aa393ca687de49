#include "mire/support/progress.hpp"

#include <unistd.h>

#include <cstdio>

namespace mire::support {

Progress::Progress(std::string label, std::size_t total)
    : label_(std::move(label)),
      total_(total),
      enabled_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {
  draw(true);
}

Progress::~Progress() { finish(); }

void Progress::advance(std::size_t count) {
  const std::lock_guard<std::mutex> lock(mutex_);
  done_ += count;
  draw(done_ >= total_);
}

void Progress::finish() {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  finished_ = true;
  if (enabled_) std::fprintf(stderr, "\r\033[K");
}

void Progress::draw(bool force) {
  if (!enabled_ || finished_) return;
  const auto now = std::chrono::steady_clock::now();
  if (!force && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  constexpr int kWidth = 30;
  const double fraction = total_ == 0 ? 1.0 : static_cast<double>(done_) / static_cast<double>(total_);
  const int filled = static_cast<int>(fraction * kWidth);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  std::fprintf(stderr, "\r\033[K%s [%.*s%*s] %zu/%zu  %.1f s", label_.c_str(), filled, "##############################",
               kWidth - filled, "", done_, total_, elapsed);
  std::fflush(stderr);
}

}  // namespace mire::support
