// SPDX-License-Identifier: Apache-2.0
// Every command that reads a job says what the job's warnings are (a misspelt key is never
// silently ignored), and `--strict` makes any warning a refusal.
#include <morph/exceptions.h>

#include <iostream>

#include "cli/commands.h"

namespace morphmill {

bool& strict_warnings() {
  static bool strict = false;
  return strict;
}

void report_job_warnings(const morph::Job& job, bool print) {
  if (print)
    for (const morph::Warning& w : job.warnings)
      std::cerr << "morphmill: warning: " << w.file
                << (w.line > 0 ? ":" + std::to_string(w.line) : std::string()) << ": " << w.message << '\n';
  if (strict_warnings() && !job.warnings.empty())
    throw morph::InputError(job.file + ": " + std::to_string(job.warnings.size()) +
                            " warning(s), refused under --strict" + (print ? " (listed above)" : ""));
}

}  // namespace morphmill
