// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/job.h>

namespace morph {

const char* to_string(Units units) {
  return units == Units::Inch ? "inch" : "mm";
}

double millimetres_per_unit(Units units) {
  return units == Units::Inch ? 25.4 : 1.0;
}

std::vector<const Move*> Job::moves() const {
  std::vector<const Move*> all;
  all.reserve(move_count());
  for (const Path& path : paths)
    for (const Move& m : path.moves) all.push_back(&m);
  return all;
}

std::size_t Job::move_count() const {
  std::size_t n = 0;
  for (const Path& path : paths) n += path.moves.size();
  return n;
}

const Tool& Job::tool_of(const Move& move) const {
  auto it = tools.find(move.tool);
  if (it == tools.end())
    throw InputError("move at line " + std::to_string(move.line) + " uses tool " + std::to_string(move.tool) +
                     " which the job does not define");
  return it->second;
}

}  // namespace morph
