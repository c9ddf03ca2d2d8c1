// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file emit.h
/// The generator's output: the limit polygons (degenerate_collapse.h) as a triangle mesh. Vertices
/// are rounded to doubles; each polygon is fanned from its first corner that has no straight
/// neighbour (so no triangle is flat in exact arithmetic) and makes no triangle flat in doubles
/// either; a polygon without one from its centroid (a vertex of its own), or from its first
/// corner when it is strictly convex. What the rounding still flattened or turned over is
/// settled on the doubles taken as exact (rounding.h: collapses, flips, re-rounding; design §5).
/// Provenance per triangle: the stock face, or the move (its global index and G-code line).
#include <morph/degenerate_collapse.h>
#include <morph/mesh.h>
#include <morph/parallel.h>

#include <vector>

namespace morph {

/// What the rounding did (rounding.h: collapsed, flipped, re-rounded, left).
struct EmitCounts {
  std::size_t collapsed_edges = 0, flipped_edges = 0, rerounded_vertices = 0;
  std::size_t misoriented_left = 0;  ///< triangles still flat or turned the wrong way (target 0)
};

/// `move_index[m]` and `move_line[m]` give the global move index and G-code line of sweep m.
/// The points and triangles are made in parallel under `policy` (the output does not depend on it).
TriangleMesh emit(const LimitSurface& surface, const std::vector<std::int32_t>& move_index,
                  const std::vector<std::int32_t>& move_line, EmitCounts* counts = nullptr,
                  ExecutionPolicy policy = ExecutionPolicy::Parallel);

/// The same from the conformed surface: its limit (collapse_degenerates()) emitted.
TriangleMesh emit(const ConformedSurface& surface, const std::vector<std::int32_t>& move_index,
                  const std::vector<std::int32_t>& move_line, EmitCounts* counts = nullptr);

}  // namespace morph
