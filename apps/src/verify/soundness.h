// SPDX-License-Identifier: Apache-2.0
#pragma once
// Whether the generator's surface is what erode promises (a closed, oriented 2-manifold free of
// self-intersections), and the retired --generator option: generator 1 and auto were removed
// (issue 18); generator 2 builds every job they built, closed by construction.
#include <morph/mesh.h>
#include <morph/topology.h>
#include <morphmill/self_intersections.h>

#include <string>

namespace CLI {
class App;
}  // namespace CLI

namespace morphmill {

/// Whether a surface is what erode promises: a closed, oriented 2-manifold free of
/// self-intersections (exact predicates).
struct SurfaceSoundness {
  morph::TopologyReport topology;
  SelfIntersections crossings;
  bool sound() const { return topology.closed_manifold() && crossings.pairs == 0; }
  /// What is wrong, e.g. "open (12 boundary edges) with 3 intersecting pairs" ("sound" if nothing).
  std::string describe() const;
};

/// Checks `mesh` (topology and exact self-intersections, side by side on all cores).
SurfaceSoundness check_soundness(const morph::TriangleMesh& mesh);

/// Adds the retired `--generator` to `command`, hidden from its help: `2` is accepted (scripts
/// that name it keep running), `1` and `auto` are refused with what replaced them (exit 2).
void add_retired_generator_option(CLI::App& command);

}  // namespace morphmill
