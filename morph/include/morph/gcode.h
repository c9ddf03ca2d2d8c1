#pragma once
/// \file gcode.h
/// Reader for the RS-274/NGC subset CAM post-processors emit for 3-axis milling.
#include <morph/job.h>

#include <Eigen/Core>
#include <iosfwd>
#include <map>
#include <optional>
#include <set>
#include <string>

namespace morph {

struct GcodeOptions {
  /// Coordinates are converted from the program's G20/G21 units into these.
  Units job_units = Units::Millimetre;
  /// Tool in the spindle before the first T.. M6 (the job path's "tool").
  int initial_tool = 0;
  /// Where the tool is before the first move. Unset: a move is emitted only once X, Y and Z
  /// are all known; earlier motions just establish the position.
  std::optional<Eigen::Vector3d> start;
};

struct GcodeResult {
  Path path;                               ///< moves in program order, each with its 1-based line
  std::vector<Warning> warnings;           ///< unknown words, ignored codes, with their line
  std::set<int> tools_used;                ///< T numbers selected by M6 (and initial_tool if it cut)
  std::map<std::string, int> word_counts;  ///< "G1", "M3", "F", ... as recorded
  std::size_t line_count = 0;
};

/// Reads a G-code file. Throws IoError if it cannot be read and InputError naming
/// "file:line: problem" for malformed input (a word without a number, an arc without centre,
/// an arc whose end is not on its circle within tolerance, ...).
GcodeResult read_gcode(const std::string& path, const GcodeOptions& options = {});
/// Same from a stream; `name` is used in messages.
GcodeResult parse_gcode(std::istream& in, const std::string& name, const GcodeOptions& options = {});

}  // namespace morph
