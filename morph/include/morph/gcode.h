// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file gcode.h
/// Reader for RS-274/NGC G-code as LinuxCNC's interpreter runs it (3-axis milling): expressions
/// and parameters, O-word control flow and subroutines, coordinate systems and offsets, tool
/// length offsets, canned cycles. What is supported and where it differs: docs/gcode.md.
#include <morph/job.h>

#include <Eigen/Core>
#include <iosfwd>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace morph {

/// What the controller's tool table says about one tool (LinuxCNC .tbl), in job units.
struct GcodeTool {
  double length_offset =
      0.0;  ///< Z length offset: G43 H<n> applies it; the tip is this far below the gauge line
  double diameter = 0.0;
};

struct GcodeOptions {
  /// Coordinates are converted from the program's G20/G21 units into these.
  Units job_units = Units::Millimetre;
  /// Tool in the spindle before the first T.. M6 (the job path's "tool").
  int initial_tool = 0;
  /// Where the tool is before the first move. Unset: a move is emitted only once X, Y and Z
  /// are all known; earlier motions just establish the position.
  std::optional<Eigen::Vector3d> start;

  // ---- machine set-up (LinuxCNC's "user" units are the job's units here) ----
  /// The controller's tool table. Empty: no table (G43 H then applies offset 0, with a warning,
  /// and any T is accepted); otherwise a T or H naming a tool not in it is refused or warned.
  std::map<int, GcodeTool> tools;
  /// Work offsets of G54 (1) .. G59.3 (9) in job units; override the var file's.
  std::map<int, Eigen::Vector3d> work_offsets;
  /// A LinuxCNC parameter (.var) file read before the program ("" for none): work offsets
  /// #5221.., the active system #5220, G28/G30 positions #5161../#5181.., G92 #5210-#5213.
  std::string var_file;
  /// Numbered parameters set before the program (after the var file), e.g. {5161, 0.0}.
  std::map<int, double> parameters;
  /// Controllers that change tools on T alone (no M6), as some Fanuc-style machines do.
  bool tool_change_on_t = false;
  /// Block delete switch: on (true), lines starting with '/' are skipped.
  bool block_delete = true;

  // ---- bounds that keep a runaway program from hanging or exhausting memory ----
  int max_call_depth = 10;                      ///< nested O-word calls (LinuxCNC's limit)
  std::size_t max_loop_iterations = 1'000'000;  ///< per while/do/repeat loop entry
  std::size_t max_blocks = 100'000'000;         ///< lines run again by loops, calls and jumps
  std::size_t max_moves = 20'000'000;           ///< moves produced in all
};

struct GcodeResult {
  Path path;                               ///< moves in program order, each with its 1-based line
  std::vector<Warning> warnings;           ///< unknown words, ignored codes, with their line
  std::set<int> tools_used;                ///< T numbers selected by M6 (and initial_tool if it cut)
  std::vector<Warning> messages;           ///< (MSG,...), (DEBUG,...), (PRINT,...) in execution order
  std::map<std::string, int> word_counts;  ///< "G1", "M3", "F", ... as executed
  std::size_t line_count = 0;
};

/// Reads a G-code file. Throws IoError if it cannot be read and InputError naming
/// "file:line: problem" for malformed input (a word without a number, an arc without centre,
/// an arc whose end is not on its circle within tolerance, ...) and for every word or code that
/// is not supported.
GcodeResult read_gcode(const std::string& path, const GcodeOptions& options = {});
/// Same from a stream; `name` is used in messages.
GcodeResult parse_gcode(std::istream& in, const std::string& name, const GcodeOptions& options = {});

}  // namespace morph
