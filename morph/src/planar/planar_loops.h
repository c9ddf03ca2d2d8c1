// SPDX-License-Identifier: Apache-2.0
#pragma once
// Linking the kept pieces of the planar arrangement into closed loops.
#include <morph/planar_region.h>

#include <cstdint>
#include <vector>

namespace morph::planar {

/// Links directed pieces (pieces[i] runs from vertex from[i] to vertex to[i], result on its left)
/// into closed loops. Where several pieces leave a vertex (regions touching at a point), the loop
/// takes the one turning most to the right, so touching pieces become separate loops; `probe` is
/// the short length (job units) over which curvature separates tangent pieces. Throws
/// GeometryError naming the vertex where a loop cannot be closed.
std::vector<Loop> link_loops(const std::vector<Curve>& pieces, const std::vector<std::uint32_t>& from,
                             const std::vector<std::uint32_t>& to, std::size_t vertex_count, double probe);

}  // namespace morph::planar
