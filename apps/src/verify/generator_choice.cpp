// SPDX-License-Identifier: Apache-2.0
#include "verify/generator_choice.h"

#include <morph/erode2.h>
#include <morph/exceptions.h>
#include <morph/tool.h>

namespace morphmill {

const char* const kGeneratorOptionHelp =
    "1: today's generator (default; sphere and ball-end tools); 2: generator 2, the union of exact\n"
    "sweep polytopes (closed by construction; every tool of revolution, every stock)";

void check_generator(int generator) {
  if (generator != 1 && generator != 2)
    throw morph::InputError("--generator: must be 1 (today's) or 2 (exact plane-based), got " +
                            std::to_string(generator));
}

std::string why_generator_cannot_build(const morph::Job& job, int generator) {
  check_generator(generator);
  if (generator == 2) {
    return "";
  }
  for (const morph::Path& path : job.paths)
    for (const morph::Move& move : path.moves) {
      const morph::Tool& tool = job.tool_of(move);
      if (!tool.generator_builds())
        return "the move at line " + std::to_string(move.line) + " of " + path.source + " uses tool " +
               std::to_string(move.tool) + " (" + morph::describe(tool) +
               "), which the generator cannot build yet (--generator 2 can)";
    }
  return "";
}

morph::ErodeResult run_generator(const morph::Job& job, const morph::ErodeOptions& options, int generator) {
  check_generator(generator);
  return generator == 2 ? morph::erode2(job, options) : morph::erode(job, options);
}

}  // namespace morphmill
