// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file degenerate_collapse.h
/// The generator's limit step, between conform (conform.h) and emit (emit.h). The perturbed
/// arrangement is in general position, so where four or more planes meet in one exact point (a
/// tool polytope's pole inside the stock, coinciding planes of retraces and near-reversals) the
/// perturbation splits that point into several plane-triple vertices joined by ε-edges and
/// ε-faces. Rounded to doubles they become zero-area or folded triangles. This step takes the
/// limit ε → 0 exactly, by construction, with no distance threshold:
///
/// 1. Two vertices are the same point iff the unperturbed point of one lies exactly on the three
///    planes of the other (same_limit_point()); such classes are merged into one vertex.
/// 2. Every polygon keeps its edges between distinct points (ε-edges vanish); a polygon left with
///    fewer than three edges (an ε-face, or a segment traversed both ways) vanishes.
/// 3. A polygon whose limit is a segment with three or more distinct points (an ε-thin sliver) is
///    zipped shut: its two chains are merged along the line, each neighbour across the sliver
///    takes the other chain's points on its edge, and the sliver vanishes.
/// 4. Where the limit is truly non-manifold (two sheets touching along a curve or at a point: an
///    edge used by more than two polygons, or a vertex whose polygons form more than one fan) the
///    classes involved are kept apart (each vertex stays its own point), so the output stays a
///    2-manifold; their vertices round to the same doubles, which the exact self-intersection
///    check then reports. Counted.
#include <morph/conform.h>

#include <array>
#include <cstdint>
#include <vector>

namespace morph {

/// One plane of the surface's vertices, named by its index in their table of planes
/// (VertexPlanes::planes). A polygon names its planes so rather than copying them: bear.nc at
/// 0.01 has 5 million corners, and a 112-byte copy of each edge's plane (twice, for the loops and
/// the limit polygons) was a gigabyte of memory and a tenth of the run in page faults.
using PlaneRef = std::uint32_t;

/// The plane `ref` names in `vertices`.
inline const ExactPlane& plane_at(const VertexPlanes& vertices, PlaneRef ref) {
  return vertices.planes[ref];
}

/// A convex polygon of the limit surface: distinct points, counter-clockwise seen from outside.
struct LimitPolygon {
  std::vector<std::uint32_t> loop;
  /// Edge k (loop[k] to loop[k+1]) lies on the line of `support` and plane edge_planes[k].
  std::vector<PlaneRef> edge_planes;
  /// The polygon's plane, as a vertex holds it: turned over (flipped()) when `support_turned`.
  PlaneRef support = 0;
  bool support_turned = false;
  /// The outside is on the side the support's normal points to (a stock face) or on the other
  /// (a sweep facet), the support turned back where `support_turned` (outward_normal()).
  bool faces_out = true;
  /// The positions in `loop` of the straight corners: those whose point lies on the line of the
  /// edge before it (a neighbour's corner on this polygon's edge). A fan from a corner with no
  /// straight neighbour has no flat triangle, exactly.
  std::vector<std::uint32_t> straight_corners;
  bool strictly_convex() const { return straight_corners.empty(); }
  std::int32_t move = -1;  ///< as ConformedPolygon
  std::int32_t face = 0;
};

struct LimitCounts {
  std::size_t merged_vertices = 0;     ///< vertices merged into another of the same exact point
  std::size_t removed_polygons = 0;    ///< ε-faces and segments traversed both ways
  std::size_t zipped_slivers = 0;      ///< ε-thin polygons zipped shut (step 3)
  std::size_t kept_apart = 0;          ///< classes left unmerged where the limit is non-manifold
  std::size_t flat_polygons_left = 0;  ///< zero-area polygons the zip could not close (target 0)
  std::size_t unsettled = 0;           ///< 1 when no merging kept a 2-manifold: none was done (target 0)
};

struct LimitSurface {
  /// Each vertex's planes (conform's; vertices merged away are no longer in a loop, but their
  /// planes may still be named by a PlaneRef).
  VertexPlanes vertices;
  /// vertex_point() of each vertex, as the limit step found them; emit() finds them itself when
  /// this is empty.
  std::vector<Eigen::Vector3d> points;
  std::vector<LimitPolygon> polygons;
  LimitCounts counts;
  /// The normal of `polygon`'s plane, pointing out of the solid.
  Eigen::Vector3d outward_normal(const LimitPolygon& polygon) const;
};

/// The limit of the conformed surface as ε → 0 (steps 1-4 above). Its vertices are moved into
/// the result: pass the surface with std::move when it is no longer needed.
LimitSurface collapse_degenerates(ConformedSurface surface,
                                  ExecutionPolicy policy = ExecutionPolicy::Parallel);

}  // namespace morph
