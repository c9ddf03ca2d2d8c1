// SPDX-License-Identifier: Apache-2.0
#include "verify/soundness.h"

#include <tbb/task_group.h>
#include <CLI/CLI.hpp>

#include <sstream>

namespace morphmill {

std::string SurfaceSoundness::describe() const {
  if (sound()) return "sound";
  std::ostringstream text;
  if (!topology.closed_manifold())
    text << "not a closed manifold (" << topology.boundary_edges << " boundary, "
         << topology.non_manifold_edges << " non-manifold edges, " << topology.non_manifold_vertices
         << " non-manifold vertices)";
  if (crossings.pairs > 0)
    text << (topology.closed_manifold() ? "" : " and ") << crossings.pairs << " intersecting triangle pairs";
  return text.str();
}

SurfaceSoundness check_soundness(const morph::TriangleMesh& mesh) {
  SurfaceSoundness soundness;
  tbb::task_group checks;
  checks.run([&] { soundness.topology = morph::topology_report(mesh); });
  checks.run([&] { soundness.crossings = find_self_intersections(mesh); });
  checks.wait();
  return soundness;
}

void add_retired_generator_option(CLI::App& command) {
  const CLI::Validator only_two(
      [](std::string& value) {
        if (value == "2") return std::string();
        if (value == "1" || value == "auto")
          return "generator " + value +
                 " was removed: the one generator left (formerly generator 2) builds every tool of "
                 "revolution and every job generator 1 built, closed by construction; drop --generator";
        return "the only generator is 2 (drop --generator), not '" + value + "'";
      },
      "", "generator");
  command.add_option("--generator", "retired: the only generator is 2")->check(only_two)->group("");
}

}  // namespace morphmill
