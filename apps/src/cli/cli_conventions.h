// SPDX-License-Identifier: Apache-2.0
#pragma once
// What every morphmill command shares on its command line: -q/--quiet, -v/--verbose, --threads,
// the -o/--output spelling, suggestions for mistyped commands and options, and the bash
// completion generated from the same definitions (docs/cli.md).
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <memory>
#include <string>
#include <vector>

namespace morphmill {

/// The options every command accepts (given before or after the command's name).
struct GlobalOptions {
  bool quiet = false;    ///< no progress and no notes on stderr; errors and warnings still print
  bool verbose = false;  ///< a line per finished stage with its time, also on a terminal
  int threads = 0;       ///< worker threads for every parallel stage; 0 means all cores
};
GlobalOptions& global_options();

/// Adds -q/--quiet, -v/--verbose and --threads to `app` and to each of its subcommands that does not
/// define them itself (a command's own --threads keeps its meaning), so they show in every --help.
void add_global_options(CLI::App& app);

/// Caps TBB's parallelism at global_options().threads for the rest of the process (0: no cap).
/// Throws morph::InputError for a negative count.
void apply_global_thread_limit();

/// argv with the deprecated spelling `--out` (and `--out=X`) replaced by `--output`, which every
/// command now uses.
std::vector<std::string> normalized_arguments(int argc, const char* const* argv);

/// The candidate closest to `word` by edit distance, if it is close enough to be a likely typo
/// (at most a third of the word's length, and at least 1, edits); empty otherwise.
std::string nearest_name(const std::string& word, const std::vector<std::string>& candidates);

/// "Did you mean ...?" for the first command or option of `arguments` that `app` does not know;
/// empty when every word is known or nothing is close.
std::string suggestion_for(const CLI::App& app, const std::vector<std::string>& arguments);

/// `--json [FILE]`: write `what` as JSON to FILE (no value or '-': standard output).
CLI::Option* add_json_option(CLI::App& command, std::string& path, const std::string& what);

/// True when a `--json` value names standard output (no FILE, or '-').
bool is_standard_output(const std::string& json_path);

/// Writes `document` to `path` whole or not at all (morph::write_file_atomically), or to standard
/// output when `path` is empty or '-'.
void write_json(const nlohmann::json& document, const std::string& path);

/// A bash completion script for `app`: its commands, each command's options, and file names for
/// the rest.
std::string bash_completion_script(const CLI::App& app, const std::string& program = "morphmill");

/// `morphmill completion bash`: prints bash_completion_script(app).
void register_completion_command(CLI::App& app);

}  // namespace morphmill
