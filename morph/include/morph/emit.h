// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file emit.h
/// Generator 2's output: the limit polygons (degenerate_collapse.h) as a triangle mesh. A
/// strictly convex polygon is fanned from its first corner, one with points on its edges' lines
/// from its centroid (a vertex of its own), so no triangle is flat in exact arithmetic. Vertices
/// are rounded to doubles, and then checked exactly (design §5): a triangle whose rounded
/// corners do not turn the way its polygon faces (zero area or flipped) has a corner moved to a
/// neighbouring double that keeps every incident triangle's orientation (re-rounding, counted).
/// Provenance per triangle: the stock face, or the move (its global index and G-code line).
#include <morph/degenerate_collapse.h>
#include <morph/mesh.h>

#include <vector>

namespace morph {

struct EmitCounts {
  std::size_t rerounded_vertices = 0;  ///< vertices moved to a neighbouring double
  std::size_t misoriented_left = 0;    ///< triangles still flat or flipped after that (target 0)
};

/// `move_index[m]` and `move_line[m]` give the global move index and G-code line of sweep m.
TriangleMesh emit(const LimitSurface& surface, const std::vector<std::int32_t>& move_index,
                  const std::vector<std::int32_t>& move_line, EmitCounts* counts = nullptr);

/// Sign of normal · ((b - a) × (c - a)), the doubles taken as exact (filter, then exact rationals).
int oriented_area_sign(const Eigen::Vector3d& normal, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       const Eigen::Vector3d& c);

}  // namespace morph
