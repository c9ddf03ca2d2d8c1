// SPDX-License-Identifier: Apache-2.0
// Numbered and named parameters with LinuxCNC's scoping rules (docs/gcode.md, "Parameters").
#include "gcode/gcode_parameters.h"

#include <morph/exceptions.h>
#include <morph/file_io.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>

namespace morph::gcode {

void fail(const std::string& problem) {
  throw BlockError(problem);
}

Parameters::Parameters(Live live) : live_(std::move(live)), numbered_(param::kLast + 1, 0.0), frames_(1) {}

double Parameters::numbered(int number) const {
  if (number < 1 || number > param::kLast)
    fail("parameter #" + std::to_string(number) + " does not exist (numbered parameters are #1-#5602)");
  if (read_only(number))
    if (const std::optional<double> v = live_(number, {})) return *v;
  return numbered_[static_cast<std::size_t>(number)];
}

void Parameters::set_numbered(int number, double value) {
  if (number < 1 || number > param::kLast)
    fail("parameter #" + std::to_string(number) + " does not exist (numbered parameters are #1-#5602)");
  if (read_only(number)) fail("parameter #" + std::to_string(number) + " is read-only");
  numbered_[static_cast<std::size_t>(number)] = value;
}

std::optional<double> Parameters::named(std::string_view name) const {
  if (!name.empty() && name[0] == '_') {
    if (const std::optional<double> v = live_(0, name)) return v;
    const auto it = globals_.find(name);
    if (it == globals_.end()) return std::nullopt;
    return it->second;
  }
  const auto& locals = frames_.back().locals;
  const auto it = locals.find(name);
  if (it == locals.end()) return std::nullopt;
  return it->second;
}

void Parameters::set_named(std::string_view name, double value) {
  if (!name.empty() && name[0] == '_') {
    if (live_(0, name)) fail("parameter #<" + std::string(name) + "> is predefined and read-only");
    globals_.insert_or_assign(std::string(name), value);
    return;
  }
  frames_.back().locals.insert_or_assign(std::string(name), value);
}

void Parameters::push_call(const std::vector<double>& args) {
  Frame frame;
  for (int k = 0; k < 30; ++k) {
    frame.saved[static_cast<std::size_t>(k)] = numbered_[static_cast<std::size_t>(k + 1)];
    numbered_[static_cast<std::size_t>(k + 1)] = k < static_cast<int>(args.size()) ? args[k] : 0.0;
  }
  frames_.push_back(std::move(frame));
}

void Parameters::pop_call() {
  const Frame& frame = frames_.back();
  for (int k = 0; k < 30; ++k)
    numbered_[static_cast<std::size_t>(k + 1)] = frame.saved[static_cast<std::size_t>(k)];
  frames_.pop_back();
}

std::map<int, double> read_var_file(const std::string& path) {
  std::istringstream in(read_regular_file(path, "parameter file"));
  std::map<int, double> values;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#' || line[first] == ';') continue;
    const char* p = line.data() + first;
    const char* end = line.data() + line.size();
    int number = 0;
    auto parsed = std::from_chars(p, end, number);
    if (parsed.ec != std::errc() || number < 1 || number > param::kLast)
      throw InputError(path + ":" + std::to_string(line_number) + ": expected a parameter number 1-5602");
    p = parsed.ptr;
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
    double value = 0.0;
    parsed = std::from_chars(p, end, value);
    if (parsed.ec != std::errc())
      throw InputError(path + ":" + std::to_string(line_number) + ": expected a value after parameter " +
                       std::to_string(number));
    values[number] = value;
  }
  if (in.bad()) throw IoError(path + ": read error");
  return values;
}

}  // namespace morph::gcode
