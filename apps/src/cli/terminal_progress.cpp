// SPDX-License-Identifier: Apache-2.0
#include "cli/terminal_progress.h"

#include <unistd.h>

#include <cstdio>
#include <ctime>

#include "cli/cli_conventions.h"

namespace morphmill {

namespace {

// "2026-11-26T14:03:07Z": log lines from several runs and machines sort and compare.
std::string utc_timestamp() {
  const std::time_t now = std::time(nullptr);
  std::tm parts{};
  gmtime_r(&now, &parts);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &parts);
  return text;
}

// The time left if the rest goes at the pace so far; negative when there is no estimate yet
// (nothing done, or too early for the pace to mean anything).
double seconds_left(double elapsed, std::size_t done, std::size_t total) {
  if (done == 0 || total == 0 || done >= total || elapsed < 1.0) return -1.0;
  return elapsed * static_cast<double>(total - done) / static_cast<double>(done);
}

}  // namespace

TerminalProgress::TerminalProgress()
    : TerminalProgress(isatty(STDERR_FILENO) != 0 && !global_options().quiet) {
  // Not a terminal (a log, a pipe, a batch system): a plain timestamped line every ten seconds
  // and one when a stage of a second or more ends, so a long run is never silent, and nothing at
  // all for the short runs that are the rule.
  log_lines_ = isatty(STDERR_FILENO) == 0 && !global_options().quiet;
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
  if (!enabled_ && !log_lines_) return;
  // try_lock so worker threads never wait on the terminal.
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  const auto now = std::chrono::steady_clock::now();
  if (log_lines_) {
    if (now - last_draw_ < std::chrono::seconds(10)) return;
    last_draw_ = now;
    log_line(false);
    return;
  }
  if (now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  draw(false);
}

void TerminalProgress::end() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (enabled_) draw(true);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  if (log_lines_ && (seconds >= 1.0 || global_options().verbose)) log_line(true);
}

void TerminalProgress::log_line(bool finished) {
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  if (finished) {
    std::fprintf(stderr, "%s %s: 100%% done in %.1f s\n", utc_timestamp().c_str(), stage_.c_str(), seconds);
  } else {
    const std::size_t so_far = std::min<std::size_t>(done_, total_);
    const double left = seconds_left(seconds, so_far, total_);
    std::fprintf(stderr, "%s %s: %d%% (%zu / %zu) after %.0f s", utc_timestamp().c_str(), stage_.c_str(),
                 total_ > 0 ? static_cast<int>(100.0 * double(so_far) / double(total_)) : 100, so_far, total_,
                 seconds);
    if (left >= 0.0) std::fprintf(stderr, ", about %.0f s left", left);
    std::fputc('\n', stderr);
  }
  std::fflush(stderr);
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
  const double left = final_line ? -1.0 : seconds_left(seconds, done, total_);
  // Fixed width, so a shorter estimate leaves no stale characters behind.
  if (left >= 0.0)
    std::fprintf(stderr, ", %6.0f s left", left);
  else
    std::fprintf(stderr, "%14s", "");
  if (final_line) std::fputc('\n', stderr);
  std::fflush(stderr);
}

}  // namespace morphmill
