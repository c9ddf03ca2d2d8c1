// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file job.h
/// A milling job: stock, tools, ordered paths and the tolerance, all in the job's units.
#include <morph/path.h>
#include <morph/stock.h>
#include <morph/tool.h>

#include <map>
#include <string>
#include <vector>

namespace morph {

enum class Units { Millimetre, Inch };
const char* to_string(Units units);
/// Length of one unit in millimetres (1 or 25.4).
double millimetres_per_unit(Units units);

/// A non-fatal remark on the input: an unknown G-code word, a move that never touches the stock.
struct Warning {
  std::string file;
  int line = 0;
  std::string message;
};

struct Job {
  std::string name;
  std::string file;  ///< the job file this came from ("" if built in code)
  Units units = Units::Millimetre;
  Stock stock;
  std::map<int, Tool> tools;
  std::vector<Path> paths;
  double tolerance = 0.01;  ///< largest allowed distance from the exact surface, job units
  std::vector<Warning> warnings;
  std::string description;  ///< optional free text from the job file ("description")

  /// All moves of all paths in order; the index into this is the "global move index" of FaceTag.
  std::vector<const Move*> moves() const;
  std::size_t move_count() const;
  /// The tool of a move; throws InputError if the move names a tool the job lacks.
  const Tool& tool_of(const Move& move) const;
};

}  // namespace morph
