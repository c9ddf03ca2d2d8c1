// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file job_io.h
/// Jobs as JSON files (docs/job-format.md): parsing with messages that name the file and the
/// JSON path, and the job as understood, for `morphmill info --json`.
#include <morph/job.h>

#include <nlohmann/json.hpp>
#include <string>

namespace morphmill {

/// Reads and validates a job file; G-code and stock mesh paths are relative to the job file.
/// Throws morph::InputError ("slots.json: paths[2].polyline[5]: expected 3 numbers") or
/// morph::IoError.
morph::Job load_job(const std::string& path);
/// Same from JSON text already in memory (nesting past 64 levels and numbers a double cannot
/// hold are InputErrors naming `file` and the JSON path).
morph::Job parse_job_text(const std::string& text, const std::string& file);
/// Parses JSON text with the same guards and messages (file:line:column for syntax errors).
nlohmann::json parse_json_text(const std::string& text, const std::string& file);
/// Same from parsed JSON; `file` is used in messages and to resolve paths.
morph::Job parse_job(const nlohmann::json& json, const std::string& file);

/// The design model a job names (key "design", docs/job-format.md): the part its program was
/// written for, and the signed band a comparison allows (job units, low <= 0 <= high).
struct DesignSpec {
  std::string path;              ///< the mesh, resolved against the job file; empty when the job names none
  double low = 0.0, high = 0.0;  ///< 0, 0 when the job gives no band
};

/// The "design" entry of a parsed job file's JSON (validated by parse_job as well). Throws
/// morph::InputError naming the file and key for a bad entry or a missing mesh file.
DesignSpec parse_design(const nlohmann::json& json, const std::string& file);
/// Same from the job file.
DesignSpec load_design(const std::string& path);

/// Summary of the job as understood: stock, tools, moves by kind, path length, bounds.
nlohmann::json describe_job(const morph::Job& job);

}  // namespace morphmill
