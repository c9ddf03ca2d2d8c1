// SPDX-License-Identifier: Apache-2.0
#include "io/provenance.h"

#include <fmt/format.h>
#include <morph/exceptions.h>
#include <openssl/evp.h>
#include <tbb/global_control.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <memory>

#include "io/build_info.h"

namespace morphmill {

namespace {

std::string& recorded_command_line() {
  static std::string text;
  return text;
}

// Quotes an argument the way a POSIX shell reads it back, only when it needs quoting.
std::string shell_quoted(const std::string& argument) {
  const bool plain = !argument.empty() && argument.find_first_not_of(
                                              "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                              "0123456789_-+=/.,:@%") == std::string::npos;
  if (plain) return argument;
  std::string quoted = "'";
  for (char c : argument) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string utc_now_iso8601() {
  std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  // SOURCE_DATE_EPOCH (reproducible-builds.org) makes two runs write the same bytes.
  if (const char* epoch = std::getenv("SOURCE_DATE_EPOCH")) {
    char* end = nullptr;
    const long long value = std::strtoll(epoch, &end, 10);
    if (end != epoch && *end == '\0' && value >= 0) now = static_cast<std::time_t>(value);
  }
  std::tm parts{};
  gmtime_r(&now, &parts);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &parts);
  return text;
}

std::string host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return "unknown";
  return name;
}

}  // namespace

void record_command_line(int argc, const char* const* argv) {
  std::string text;
  for (int i = 0; i < argc; ++i) text += (i ? " " : "") + shell_quoted(argv[i] ? argv[i] : "");
  recorded_command_line() = text;
}

std::string sha256_of_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw morph::IoError(path + ": cannot be read to compute its SHA-256");
  std::unique_ptr<EVP_MD_CTX, decltype(&EVP_MD_CTX_free)> context(EVP_MD_CTX_new(), &EVP_MD_CTX_free);
  if (!context || EVP_DigestInit_ex(context.get(), EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("OpenSSL: cannot start a SHA-256 digest");
  std::array<char, 1 << 16> buffer;
  while (in) {
    in.read(buffer.data(), buffer.size());
    if (in.gcount() > 0 && EVP_DigestUpdate(context.get(), buffer.data(), std::size_t(in.gcount())) != 1)
      throw std::runtime_error("OpenSSL: SHA-256 update failed");
  }
  if (in.bad()) throw morph::IoError(path + ": read error while computing its SHA-256");
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_DigestFinal_ex(context.get(), digest, &length) != 1)
    throw std::runtime_error("OpenSSL: SHA-256 final failed");
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) hex += fmt::format("{:02x}", digest[i]);
  return hex;
}

std::vector<std::string> job_input_files(const morph::Job& job) {
  std::vector<std::string> files;
  auto add = [&](const std::string& path) {
    std::error_code error;
    if (path.empty() || !std::filesystem::is_regular_file(path, error)) return;
    for (const auto& f : files)
      if (f == path) return;
    files.push_back(path);
  };
  add(job.file);
  for (const morph::Path& p : job.paths) add(p.source);
  add(job.stock.mesh_path);
  return files;
}

Provenance make_provenance(const std::vector<std::string>& input_paths, nlohmann::json options,
                           const std::string& units) {
  Provenance p;
  p.version = git_describe();
  p.commit = source_commit();
  p.command_line = recorded_command_line();
  for (const std::string& path : input_paths) {
    std::error_code error;
    const auto bytes = std::filesystem::file_size(path, error);
    p.inputs.push_back({path, sha256_of_file(path), error ? 0 : bytes});
  }
  p.options = std::move(options);
  p.units = units;
  p.machine = host_name();
  // The limit --threads set, else the machine's.
  p.threads =
      static_cast<unsigned>(tbb::global_control::active_value(tbb::global_control::max_allowed_parallelism));
  p.date_utc = utc_now_iso8601();
  return p;
}

nlohmann::json to_json(const Provenance& p) {
  nlohmann::json inputs = nlohmann::json::array();
  for (const InputFile& f : p.inputs)
    inputs.push_back({{"path", f.path}, {"sha256", f.sha256}, {"bytes", f.bytes}});
  return {
      {"program", p.program}, {"version", p.version},  {"commit", p.commit}, {"command_line", p.command_line},
      {"inputs", inputs},     {"options", p.options},  {"units", p.units},   {"machine", p.machine},
      {"threads", p.threads}, {"date_utc", p.date_utc}};
}

std::vector<std::string> provenance_lines(const Provenance& p) {
  auto one_line = [](std::string text) {
    for (char& c : text)
      if (c == '\n' || c == '\r') c = ' ';
    return text;
  };
  std::vector<std::string> lines = {
      "program: " + p.program + " " + p.version,
      "commit: " + p.commit,
      "command_line: " + one_line(p.command_line),
      "units: " + p.units,
  };
  for (const InputFile& f : p.inputs) lines.push_back("input: " + one_line(f.path) + " sha256 " + f.sha256);
  lines.push_back("options: " + one_line(p.options.dump()));
  lines.push_back(fmt::format("machine: {} threads {}", one_line(p.machine), p.threads));
  lines.push_back("date_utc: " + p.date_utc);
  return lines;
}

}  // namespace morphmill
