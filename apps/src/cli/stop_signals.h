// SPDX-License-Identifier: Apache-2.0
#pragma once
// Clean stops of long commands (stress, study): while a StopOnSignals lives, SIGINT and SIGTERM
// only record the signal; the command polls stop_signal() between units of work (cases,
// settings), lets the ones in flight finish, writes what ran and exits 4. A second signal takes
// its default action (kills at once).
#include <atomic>

namespace morphmill {

/// 0 while no stop was requested, else the signal's number.
const std::atomic<int>& stop_signal();

/// "SIGINT", "SIGTERM" or "signal N".
const char* signal_name(int signal);

class StopOnSignals {
 public:
  StopOnSignals();   ///< clears any earlier request and installs the handlers
  ~StopOnSignals();  ///< restores the handlers there were before
  StopOnSignals(const StopOnSignals&) = delete;
  StopOnSignals& operator=(const StopOnSignals&) = delete;

 private:
  struct Saved;
  Saved* saved_;
};

}  // namespace morphmill
