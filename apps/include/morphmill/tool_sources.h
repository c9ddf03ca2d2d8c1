// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file tool_sources.h
/// Jobs and tools from other programs' files: CAMotics projects (`.camotics`) read as whole jobs,
/// and LinuxCNC tool tables (`.tbl`) read as tools whose shape the job gives (docs/camotics.md,
/// docs/job-format.md "tool_table").
#include <morph/job.h>

#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace morphmill {

/// A CAMotics project as a job: its tool table (cylindrical, ballnose, conical, snubnose,
/// spheroid; each tool in its own units), its workpiece box (explicit, or `automatic`: the
/// bounds of the tool over the cutting moves, top at z = 0, at least 2 mm thick, grown by
/// `margin` percent, as CAMotics computes it) and its G-code files run in order on that stock.
/// The tool in the spindle at the start is the lowest-numbered tool. Throws morph::InputError
/// naming the project file and the JSON path ("heart.camotics: tools.2.shape: ...").
morph::Job load_camotics_project(const std::string& path);
morph::Job parse_camotics_project(const nlohmann::json& project, const std::string& file);

/// One row of a LinuxCNC tool table: `T1 P1 D6.0 Z+25 ;comment`, sizes in the table's units.
struct ToolTableRow {
  int number = 0;
  int line = 0;
  double diameter = 0.0;
  double z_offset = 0.0;
  std::string comment;
};

/// Reads a LinuxCNC tool table. Words T (required, integer >= 0), P, D (>= 0), X Y Z A B C U V W
/// I J Q; `;` starts a comment. Throws morph::InputError "tools.tbl:3: ..." naming the line.
std::map<int, ToolTableRow> read_tool_table(const std::string& path);

}  // namespace morphmill
