// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file self_intersections.h
/// Pairs of triangles of a mesh that intersect beyond the vertices and edges they share, decided
/// with exact predicates (CGAL's filtered exact kernel): whether two triangles touch is a sign, and
/// a sign decided in floating point could differ from one pair to the next.
#include <morph/mesh.h>

#include <cstdint>
#include <utility>
#include <vector>

namespace morphmill {

struct SelfIntersections {
  /// Number of intersecting triangle pairs.
  std::size_t pairs = 0;
  /// The first intersecting pairs in (smaller index, larger index) order, at most the `keep` asked for.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> first_pairs;
};

/// Every pair of triangles that intersect other than along what they share by index: two
/// triangles with a common vertex index may meet there only; with a common edge (two indices),
/// along that edge only (they intersect when folded flat onto each other). Triangles with a
/// repeated vertex index are left out (topology_report counts them). Coordinates are taken as
/// exact doubles; the decision for each pair is exact. `threaded`: the candidate pairs are
/// searched and tested on all cores. Throws std::invalid_argument on an out-of-range index.
SelfIntersections find_self_intersections(const morph::TriangleMesh& mesh, std::size_t keep = 10,
                                          bool threaded = true);

}  // namespace morphmill
