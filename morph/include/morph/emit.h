// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file emit.h
/// The generator's output: the limit polygons (degenerate_collapse.h) as a triangle mesh. Vertices
/// are rounded to doubles; each polygon is fanned from its first corner that has no straight
/// neighbour (so no triangle is flat in exact arithmetic) and makes no triangle flat in doubles
/// either; a polygon without one from its centroid (a vertex of its own), or from its first
/// corner when it is strictly convex. What the rounding still flattened or turned over is
/// settled on the doubles taken as exact (rounding.h: collapses, flips, re-rounding; design §5).
/// Provenance per triangle: the stock face, or the move (its global index and G-code line) and
/// whether the face is swept along it (SideSweep, the paper's arches) or the tool's own surface at
/// an end of it (FrontSweep, the caps at path ends and turns).
#include <morph/degenerate_collapse.h>
#include <morph/mesh.h>
#include <morph/parallel.h>
#include <morph/sweep_polytope.h>

#include <cstdint>
#include <functional>
#include <vector>

namespace morph {

/// What the rounding did (rounding.h: collapsed, flipped, re-rounded, left).
struct EmitCounts {
  std::size_t collapsed_edges = 0, flipped_edges = 0, rerounded_vertices = 0;
  std::size_t misoriented_left = 0;  ///< triangles still flat or turned the wrong way (target 0)
};

/// Whether facet `facet` of sweep `sweep` (in the sweep's facet order, sweep_polytope.h) is the
/// tool's own surface at an end of the move, not swept along it.
using CapTest = std::function<bool(std::int32_t sweep, std::int32_t facet)>;

/// Whether facet `facet` of the sweep of `tool` from `from` to `to` is a cap: a tool facet placed
/// at an end (motion_side() not 0), or any tool facet of a move too short to sweep (the tool
/// itself); not a silhouette parallelogram nor a tool facet swept whole along the motion.
bool is_cap(const SweepPolytopeBuilder& tool, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
            std::int32_t facet);

/// `move_index[m]` and `move_line[m]` give the global move index and G-code line of sweep m;
/// `caps` tells its caps (FrontSweep) from its swept faces (SideSweep; every face when empty).
/// The points and triangles are made in parallel under `policy` (the output does not depend on it).
TriangleMesh emit(const LimitSurface& surface, const std::vector<std::int32_t>& move_index,
                  const std::vector<std::int32_t>& move_line, EmitCounts* counts = nullptr,
                  ExecutionPolicy policy = ExecutionPolicy::Parallel, const CapTest& caps = {});

/// The same from the conformed surface: its limit (collapse_degenerates()) emitted.
TriangleMesh emit(const ConformedSurface& surface, const std::vector<std::int32_t>& move_index,
                  const std::vector<std::int32_t>& move_line, EmitCounts* counts = nullptr);

}  // namespace morph
