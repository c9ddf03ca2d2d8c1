// SPDX-License-Identifier: Apache-2.0
#include "cli/cli_conventions.h"

#include "cli/edit_distance.h"

#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cctype>
#include <iostream>
#include <optional>
#include <sstream>

namespace morphmill {

GlobalOptions& global_options() {
  static GlobalOptions options;
  return options;
}

namespace {

bool has_long_name(const CLI::App& command, const std::string& name) {
  return command.get_option_no_throw("--" + name) != nullptr;
}

void add_to(CLI::App& command) {
  GlobalOptions& options = global_options();
  if (!has_long_name(command, "quiet"))
    command.add_flag("-q,--quiet", options.quiet,
                     "No progress and no notes on stderr (errors and warnings still print)");
  if (!has_long_name(command, "verbose"))
    command.add_flag("-v,--verbose", options.verbose, "A line per finished stage with its time");
  if (!has_long_name(command, "threads"))
    command.add_option("--threads", options.threads, "Worker threads (default 0: all cores)");
}

std::vector<std::string> command_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
    if (!command->get_name().empty() && !command->get_group().empty()) names.push_back(command->get_name());
  return names;
}

std::vector<std::string> long_option_names(const CLI::App& command) {
  std::vector<std::string> names;
  for (const CLI::Option* option : command.get_options())
    if (!option->get_group().empty())
      for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
  return names;
}

const CLI::App* find_command(const CLI::App& app, const std::string& name) {
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
    if (command->get_name() == name) return command;
  return nullptr;
}

bool takes_value(const CLI::App& app, const CLI::App* command, const std::string& token) {
  if (token.rfind("--", 0) != 0 || token.find('=') != std::string::npos) return false;
  for (const CLI::App* scope : {command, &app}) {
    if (!scope) continue;
    if (const CLI::Option* option = scope->get_option_no_throw(token)) return option->get_expected_min() > 0;
  }
  return false;
}

}  // namespace

void add_global_options(CLI::App& app) {
  add_to(app);
  for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) add_to(*command);
}

void apply_global_thread_limit() {
  static std::optional<tbb::global_control> limit;
  const int threads = global_options().threads;
  if (threads < 0)
    throw morph::InputError("--threads: must be >= 1 (or 0 for all cores), not " + std::to_string(threads));
  if (threads > 0)
    limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
}

std::vector<std::string> normalized_arguments(int argc, const char* const* argv) {
  std::vector<std::string> arguments;
  for (int i = 1; i < argc; ++i) {
    std::string word = argv[i];
    if (word == "--out")
      word = "--output";
    else if (word.rfind("--out=", 0) == 0)
      word = "--output=" + word.substr(6);
    arguments.push_back(word);
  }
  return arguments;
}

std::string nearest_name(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::string::npos;
  for (const std::string& candidate : candidates) {
    const std::size_t distance = edit_distance(word, candidate);
    if (distance < best_distance || (distance == best_distance && candidate < best)) {
      best = candidate;
      best_distance = distance;
    }
  }
  return best_distance <= std::max<std::size_t>(1, word.size() / 3) ? best : "";
}

std::string suggestion_for(const CLI::App& app, const std::vector<std::string>& arguments) {
  const CLI::App* command = nullptr;
  bool skip_value = false;
  for (const std::string& word : arguments) {
    if (skip_value) {
      skip_value = false;
      continue;
    }
    const bool negative_number = word.size() > 1 && word[0] == '-' &&
                                 (std::isdigit(static_cast<unsigned char>(word[1])) || word[1] == '.');
    if (word.rfind("--", 0) == 0 && word.size() > 2) {
      const std::string name = word.substr(0, word.find('='));
      if ((command && command->get_option_no_throw(name)) || app.get_option_no_throw(name)) {
        skip_value = takes_value(app, command, word);
        continue;
      }
      std::vector<std::string> candidates = long_option_names(app);
      if (command)
        for (const std::string& n : long_option_names(*command)) candidates.push_back(n);
      const std::string nearest = nearest_name(name, candidates);
      if (!nearest.empty())
        return "unknown option '" + name + "'" + (command ? " for '" + command->get_name() + "'" : "") +
               ": did you mean '" + nearest + "'?";
      continue;
    }
    if (word.empty() || word[0] == '-' || negative_number || command) continue;
    command = find_command(app, word);
    if (!command) {
      const std::string nearest = nearest_name(word, command_names(app));
      return nearest.empty() ? "" : "unknown command '" + word + "': did you mean '" + nearest + "'?";
    }
  }
  return "";
}

CLI::Option* add_json_option(CLI::App& command, std::string& path, const std::string& what) {
  return command
      .add_option("--json", path, "Write " + what + " as JSON to FILE (no FILE or '-': standard output)")
      ->expected(0, 1)
      ->type_name("[FILE]");
}

bool is_standard_output(const std::string& json_path) {
  return json_path.empty() || json_path == "-";
}

void write_json(const nlohmann::json& document, const std::string& path) {
  const std::string text = document.dump(2) + "\n";
  if (is_standard_output(path))
    std::cout << text << std::flush;
  else
    morph::write_file_atomically(path, text);
}

std::string bash_completion_script(const CLI::App& app, const std::string& program) {
  std::string function = "_" + program;
  std::replace(function.begin(), function.end(), '-', '_');
  const auto join = [](const std::vector<std::string>& words) {
    std::string line;
    for (const std::string& w : words) line += (line.empty() ? "" : " ") + w;
    return line;
  };
  const auto option_words = [](const CLI::App& command) {
    std::vector<std::string> words;
    for (const CLI::Option* option : command.get_options()) {
      if (option->get_group().empty()) continue;
      for (const std::string& s : option->get_snames()) words.push_back("-" + s);
      for (const std::string& l : option->get_lnames()) words.push_back("--" + l);
    }
    return words;
  };
  std::ostringstream out;
  out << "# bash completion for " << program << ", generated by '" << program << " completion bash'.\n"
      << "# Source it, or install it as share/bash-completion/completions/" << program << ".\n"
      << function << "() {\n"
      << "  local cur=\"${COMP_WORDS[COMP_CWORD]}\" command=\"\" i\n"
      << "  for ((i = 1; i < COMP_CWORD; i++)); do\n"
      << "    case \"${COMP_WORDS[i]}\" in -*) ;; *) command=\"${COMP_WORDS[i]}\"; break ;; esac\n"
      << "  done\n"
      << "  local words\n"
      << "  case \"$command\" in\n"
      << "    \"\") words=\"" << join(command_names(app)) << " " << join(option_words(app)) << "\" ;;\n";
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (command->get_name().empty() || command->get_group().empty()) continue;
    out << "    " << command->get_name() << ") words=\"" << join(option_words(*command)) << "\" ;;\n";
  }
  out << "  esac\n"
      << "  if [[ -z \"$command\" || \"$cur\" == -* ]]; then\n"
      << "    COMPREPLY=($(compgen -W \"$words\" -- \"$cur\"))\n"
      << "  else\n"
      << "    COMPREPLY=($(compgen -f -- \"$cur\"))\n"
      << "  fi\n"
      << "}\n"
      << "complete -o filenames -o bashdefault -F " << function << " " << program << "\n";
  return out.str();
}

void register_completion_command(CLI::App& app) {
  CLI::App* completion =
      app.add_subcommand("completion",
                         "Print a shell completion script generated from these very commands and options.\n"
                         "Example: source <(morphmill completion bash)");
  auto shell = std::make_shared<std::string>("bash");
  completion->add_option("shell", *shell, "Shell (bash)")
      ->check(CLI::IsMember({"bash"}))
      ->capture_default_str();
  completion->callback([&app, shell] { std::cout << bash_completion_script(app); });
}

}  // namespace morphmill
