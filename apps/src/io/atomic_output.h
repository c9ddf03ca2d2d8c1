// SPDX-License-Identifier: Apache-2.0
#pragma once
// An output file that appears whole or not at all: the text is collected in memory and commit()
// hands it to morph::write_file_atomically (temporary file in the same directory, fsync, rename).
// A writer that throws, or a process killed before commit(), leaves the previous file untouched
// instead of a truncated one.
#include <morph/file_io.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <utility>

namespace morphmill {

class AtomicOutput : public std::ostringstream {
 public:
  explicit AtomicOutput(std::filesystem::path path) : path_(std::move(path)) {}
  void commit() { morph::write_file_atomically(path_.string(), str()); }

 private:
  std::filesystem::path path_;
};

}  // namespace morphmill
