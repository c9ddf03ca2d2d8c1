// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file own_facet.h
/// A kept sweep facet within the stock and its own sweep polytope: the piece the culled carving
/// then cuts by the facet's cutters (carve_culled.h). Of a sweep's planes (a tool facet's at each
/// end, a silhouette edge's along the move), only those that may reach the facet are clipped by:
/// first those through its vertices (what meets at its tool vertices), which alone bound it when
/// every plane of the sweep is exact (own_facet.cpp says why); otherwise then any other that the
/// tool's facet groups (tool_facet_groups.h), bounding a group's planes over balls holding the
/// piece's corners, cannot show below every ball: such a plane holds the piece strictly inside,
/// so clipping by it would change nothing. The planes are made as they are asked for. Balls about exact
/// corners also serve the stock pieces' tests.
#include <morph/carve.h>
#include <morph/facet_clipping.h>
#include <morph/stock_polytope.h>
#include <morph/sweep_polytope.h>

#include "generator/tool_facet_groups.h"

#include <Eigen/Core>
#include <optional>
#include <utility>
#include <vector>

namespace morph {

using Ball = std::pair<Eigen::Vector3d, double>;  ///< centre, radius (job units)

/// What meets at each tool vertex: the planes through a sweep facet's vertices are those of the
/// tool facets and silhouette edges there.
struct ToolIncidence {
  std::vector<std::vector<int>> facets_at_vertex;  ///< tool facets (joint_culling.h's facets_at_vertices())
  std::vector<std::vector<int>> edges_at_vertex;   ///< tool edges (indices in SweepPolytopeBuilder::edges())
};
ToolIncidence tool_incidence(const SweepPolytopeBuilder& builder);

/// A sweep's own planes (sweep_planes() of its halfspaces) with what finds the ones that reach a
/// region without testing them all: the tool's facet groups and the sweep's ordered ends.
struct OwnPlanes {
  explicit OwnPlanes(SweepPolytopeBuilder::Planes sweep) : made(std::move(sweep)) {}
  /// Plane k (sweep_planes()' plane k of the sweep, bit for bit), made when first asked for: a
  /// move's kept facets ask for the planes through their vertices, a few of its ~700.
  const ExactPlane& plane(std::size_t k);
  double length(std::size_t k);  ///< of plane(k)'s normal
  std::size_t plane_count() const { return made.size(); }

  SweepPolytopeBuilder::Planes made;
  std::uint32_t move = 0;
  std::vector<ExactPlane> planes;  ///< planes[k] is plane(k) once have[k]
  std::vector<double> lengths;     ///< of planes[k]'s normal
  std::vector<char> have;
  const SweepPolytopeBuilder* builder = nullptr;
  const ToolIncidence* incidence = nullptr;
  std::vector<int> silhouette_plane;  ///< per tool edge: the index of its silhouette plane, or -1
  const ToolFacetGroups* groups = nullptr;
  Eigen::Vector3d a, b;
  std::size_t tool_facets = 0;  ///< planes[k] for k below this is tool facet k placed at a or b
  std::vector<char>
      group_ends;  ///< per facet group: 1 if a member is placed at a, 2 at b, 3 both (not exact only)
  /// Every plane of the sweep exact (SweepPolytopeBuilder::exact()): then a facet is bounded by
  /// the planes through its vertices alone (own_facet()).
  bool exact = false;
};

/// The own planes of the sweep of `builder`'s tool from `from` to `to`, ranked as move `move`'s
/// (sweep_planes()); `members[g]`: the tool facets of facet group g of `groups`; `incidence`:
/// tool_incidence() of `builder`.
OwnPlanes own_planes(const SweepPolytopeBuilder& builder, const ToolFacetGroups& groups,
                     const std::vector<std::vector<int>>& members, const ToolIncidence& incidence,
                     const Eigen::Vector3d& from, const Eigen::Vector3d& to, std::uint32_t move);

/// own_facet()'s working memory, one per thread.
struct OwnFacetScratch {
  std::vector<char> marks;  ///< flags of the planes reached, all clear between calls
  std::vector<double> lengths;
  std::vector<char> applied;  ///< per own plane: clipped by in the first loop
  std::vector<std::size_t> applied_index;
  std::vector<std::size_t> incident;  ///< the planes through a facet's vertices
  std::vector<ExactPlane> near, reaching;
};

/// The points of sweep facet `f` as the builder places it (tool vertices at the ordered ends),
/// for choosing which of the sweep's planes can bound it; the exact facet is decided by all.
std::vector<Eigen::Vector3d> facet_points(const SweepPolytopeBuilder& builder, const OwnPlanes& own, int f);

/// Facet f of the sweep (`points`: facet_points()) within the stock and its own polytope, exact.
ConvexPiece own_facet(OwnPlanes& own, int f, const std::vector<Eigen::Vector3d>& points,
                      const StockPolytope& stock, OwnFacetScratch& scratch);

/// A ball holding the exact corners of `piece`; none when the corners cannot be bounded.
std::optional<Ball> corner_ball(const ConvexPiece& piece);

/// True when `plane`'s value is below -threshold everywhere in every ball, with room for the
/// rounding of this test and of any point's value in them (a millionth of the thresholds used).
/// `length`: the plane's normal's.
bool below_in_balls(const ExactPlane& plane, double length, const std::vector<Ball>& balls, double threshold);

}  // namespace morph
