// SPDX-License-Identifier: Apache-2.0
#include "terminal_progress.h"

#include <unistd.h>

#include <cstdio>

namespace morphmill {

TerminalProgress::TerminalProgress() : TerminalProgress(isatty(STDERR_FILENO) != 0) {
  // Not a terminal (a log, a pipe, a batch system): a plain line every ten seconds, so a long
  // run is never silent, and nothing at all for the short runs that are the rule.
  log_lines_ = !enabled_;
}
TerminalProgress::TerminalProgress(bool enabled) : enabled_(enabled) {}
TerminalProgress::~TerminalProgress() = default;

void TerminalProgress::begin(const std::string& stage, std::size_t total) {
  std::lock_guard<std::mutex> lock(mutex_);
  stage_ = stage;
  total_ = total;
  done_ = 0;
  started_ = last_draw_ = std::chrono::steady_clock::now();
  if (enabled_) draw(false);
}

void TerminalProgress::advance(std::size_t done) {
  done_ += done;
  if (log_lines_) {
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    if (!lock.owns_lock()) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_draw_ < std::chrono::seconds(10)) return;
    last_draw_ = now;
    const double seconds = std::chrono::duration<double>(now - started_).count();
    const std::size_t so_far = std::min<std::size_t>(done_, total_);
    std::fprintf(stderr, "%s: %d%% (%zu / %zu) after %.0f s\n", stage_.c_str(),
                 total_ > 0 ? static_cast<int>(100.0 * double(so_far) / double(total_)) : 100, so_far, total_,
                 seconds);
    std::fflush(stderr);
    return;
  }
  if (!enabled_) return;
  // Redraw at most ten times a second; try_lock so worker threads never wait on the terminal.
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  draw(false);
}

void TerminalProgress::end() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (enabled_) draw(true);
}

void TerminalProgress::draw(bool final_line) {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  const std::size_t done = final_line ? total_ : std::min<std::size_t>(done_, total_);
  const double share = total_ > 0 ? static_cast<double>(done) / static_cast<double>(total_) : 1.0;
  constexpr int kWidth = 30;
  const int filled = static_cast<int>(share * kWidth + 0.5);
  std::fprintf(stderr, "\r%-28.28s [%.*s%*s] %3d%% %7.1f s", stage_.c_str(), filled,
               "##############################", kWidth - filled, "", static_cast<int>(share * 100 + 0.5),
               seconds);
  if (final_line) std::fputc('\n', stderr);
  std::fflush(stderr);
}

}  // namespace morphmill
