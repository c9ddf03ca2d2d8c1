// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file progress.h
/// Progress reporting and interruption for long computations (the OpenVDB interrupter idea).
/// Library code reports through this and never prints; apps/ shows it on a terminal.
#include <atomic>
#include <cstddef>
#include <string>

namespace morph {

class Progress {
 public:
  virtual ~Progress() = default;
  /// A new stage of `total` work units begins.
  virtual void begin(const std::string& stage, std::size_t total) {
    (void)stage;
    (void)total;
  }
  /// `done` more units finished (may be called from several threads).
  virtual void advance(std::size_t done) { (void)done; }
  /// The current stage ended.
  virtual void end() {}
  /// True if the caller wants the computation to stop; the library then throws Interrupted.
  virtual bool interrupted() const { return false; }
};

/// A Progress that ignores everything.
inline Progress& null_progress() {
  static Progress instance;
  return instance;
}

}  // namespace morph
