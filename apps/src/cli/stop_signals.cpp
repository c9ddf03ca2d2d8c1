// SPDX-License-Identifier: Apache-2.0
#include "cli/stop_signals.h"

#include <unistd.h>

#include <csignal>

namespace morphmill {

namespace {

std::atomic<int> requested{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler stores into it");

extern "C" void request_stop(int signal) {
  requested.store(signal);
  static const char message[] =
      "\nmorphmill: stopping: the work in flight finishes, then what ran is written (a second signal "
      "kills at once)\n";
  const ssize_t ignored = ::write(STDERR_FILENO, message, sizeof(message) - 1);
  (void)ignored;
  std::signal(signal, SIG_DFL);
}

}  // namespace

struct StopOnSignals::Saved {
  struct sigaction interrupt {};
  struct sigaction terminate {};
};

const std::atomic<int>& stop_signal() {
  return requested;
}

const char* signal_name(int signal) {
  if (signal == SIGINT) return "SIGINT";
  if (signal == SIGTERM) return "SIGTERM";
  return "a signal";
}

StopOnSignals::StopOnSignals() : saved_(new Saved) {
  requested.store(0);
  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, &saved_->interrupt);
  sigaction(SIGTERM, &action, &saved_->terminate);
}

StopOnSignals::~StopOnSignals() {
  sigaction(SIGINT, &saved_->interrupt, nullptr);
  sigaction(SIGTERM, &saved_->terminate, nullptr);
  delete saved_;
}

}  // namespace morphmill
