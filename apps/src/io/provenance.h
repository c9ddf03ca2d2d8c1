// SPDX-License-Identifier: Apache-2.0
#pragma once
// Where an output came from: which morphmill, which inputs (with their SHA-256), which options,
// on which machine and when. Every file verify, compare and deviation write carries it, so a
// result found on disk months later can be traced and reproduced.
#include <morph/job.h>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace morphmill {

/// One input file: its path as given and the SHA-256 of its bytes (lowercase hex).
struct InputFile {
  std::string path;
  std::string sha256;
  std::uintmax_t bytes = 0;
};

struct Provenance {
  std::string program = "morphmill";
  std::string version;       ///< `git describe --always --dirty` at build time, else the project version
  std::string commit;        ///< full source commit (build_info.h)
  std::string command_line;  ///< as the shell passed it, arguments quoted where needed
  std::vector<InputFile> inputs;
  nlohmann::json options;  ///< the options that shaped the result, with their values
  std::string units;       ///< length unit of every coordinate and deviation in the file
  std::string machine;     ///< host name
  unsigned threads = 0;    ///< threads the run could use (the --threads limit, else the machine's)
  std::string date_utc;    ///< ISO 8601; from SOURCE_DATE_EPOCH when set (reproducible outputs)
};

/// Records the command line of this process (main calls it once, before parsing).
void record_command_line(int argc, const char* const* argv);

/// SHA-256 of a file's bytes as lowercase hex (OpenSSL's libcrypto). Throws morph::IoError naming
/// the file when it cannot be read.
std::string sha256_of_file(const std::string& path);

/// The job file and every file it reads (G-code programs, the stock mesh), each once, in that order.
std::vector<std::string> job_input_files(const morph::Job& job);

/// Provenance of this run: build identity, recorded command line, the inputs hashed now.
Provenance make_provenance(const std::vector<std::string>& input_paths, nlohmann::json options,
                           const std::string& units);

nlohmann::json to_json(const Provenance& provenance);

/// The provenance as short "key: value" lines (one per input), for PLY comments, VTK files and
/// OpenVDB metadata. No line holds a newline.
std::vector<std::string> provenance_lines(const Provenance& provenance);

}  // namespace morphmill
