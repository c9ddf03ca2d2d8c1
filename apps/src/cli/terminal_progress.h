// SPDX-License-Identifier: Apache-2.0
#pragma once
// Progress on a terminal for long stages, with the time left at the pace so far; when stderr is
// not a terminal (logs, CI, pipes), plain timestamped lines: every ten seconds of a stage, and its
// end when it took a second or more. -q/--quiet silences both.
#include <morph/progress.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace morphmill {

class TerminalProgress : public morph::Progress {
 public:
  /// `enabled` (the bar) defaults to whether stderr is a terminal and --quiet was not given.
  TerminalProgress();
  explicit TerminalProgress(bool enabled);
  ~TerminalProgress() override;

  void begin(const std::string& stage, std::size_t total) override;
  void advance(std::size_t done) override;
  void end() override;

 private:
  void draw(bool final_line);
  void log_line(bool finished);

  bool enabled_;
  bool log_lines_ = false;
  std::mutex mutex_;
  std::string stage_;
  std::size_t total_ = 0;
  std::atomic<std::size_t> done_{0};
  std::chrono::steady_clock::time_point started_, last_draw_;
};

}  // namespace morphmill
