// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file sweep_polytope.h
/// The volume a convex tool polytope sweeps along a straight move: the convex polytope
/// tool ⊕ segment, given by its facets (and so its halfspaces). With v the motion, its facets are
/// - the tool's facets facing back (n·v < 0) at the start, and facing forward (n·v > 0) at the end;
/// - a parallelogram e × v on every silhouette edge e (between a back and a forward facet);
/// - every facet parallel to the motion (n·v = 0) swept whole into one planar face, the hull of
///   it at the start and at the end: a level move's flat bottom, a plunging cylinder's sides.
/// The segment is taken unordered (its ends sorted), so a move and its retrace give the same
/// polytope, bit for bit.
///
/// Exact planes (quantize.h): when the tool's facets carry exact planes and both ends lie on the
/// tool's grid, every facet of the sweep carries one too: the tool's, translated by the end it is
/// placed at, and on silhouette edge e the plane of normal e × (b - a) (both reduced to coprime
/// integers) exactly through both ends of e at both placements. A sweep with an end off the grid
/// has the doubles alone, every facet (one sweep is exact or not as a whole).
///
/// Facet order (later stages name facets by it): facet f < tool.facets.size() is the tool's facet
/// f, placed at the start, at the end or swept by motion_side(); then one parallelogram per
/// silhouette edge, in the order of edges().
#include <morph/convex_polytope.h>

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

namespace morph {

/// Where a tool facet of outward unit normal `normal` goes in the sweep along `motion`: -1 at the
/// start (n·v < 0), +1 at the end (n·v > 0), 0 swept whole (|n·v| within 1e-12·|v|). Exactly
/// antisymmetric: motion_side(n, -v) == -motion_side(n, v), so the side does not depend on which
/// end of the segment the builder takes first.
int motion_side(const Eigen::Vector3d& normal, const Eigen::Vector3d& motion);

/// motion_side() of every facet of `tool` for one motion, into `sides` (the same values; the
/// motion's length is taken once, not per facet).
void motion_sides(const ConvexPolytope& tool, const Eigen::Vector3d& motion, std::vector<signed char>& sides);

/// A halfspace normal·x <= offset.
/// `exact`, when set, is the same plane on the grid (quantize.h): the predicates decide on it,
/// normal (unit) and offset are its rounded look.
struct Halfspace {
  Eigen::Vector3d normal;
  double offset;
  IntegerPlane exact{};
};

/// Builds sweeps of one tool polytope; the tool's edge adjacency is found once.
class SweepPolytopeBuilder {
 public:
  /// `tool`: a closed convex polytope about the tool point (tool_polytope.h).
  explicit SweepPolytopeBuilder(ConvexPolytope tool);

  /// The polytope swept as the tool point moves from `start` to `end` (job units). A move
  /// shorter than 1e-12 of the tool's size gives the tool itself at `start`.
  ConvexPolytope operator()(const Eigen::Vector3d& start, const Eigen::Vector3d& end) const;

  /// The facets' halfspaces of operator()(start, end), in its facet order and bit for bit the
  /// same values, without building the facets' loops (a few microseconds instead of ~100).
  std::vector<Halfspace> halfspaces(const Eigen::Vector3d& start, const Eigen::Vector3d& end) const;

  /// One sweep's halfspaces made one at a time, for a caller that needs a few of them: the
  /// facets' sides and the silhouette edges are found once (one dot product per tool facet),
  /// each plane when asked for, bit for bit halfspaces(start, end)[k].
  class Planes {
   public:
    Planes(const SweepPolytopeBuilder& builder, const Eigen::Vector3d& start, const Eigen::Vector3d& end);
    std::size_t size() const { return side_.size() + silhouette_.size(); }
    Halfspace operator[](std::size_t k) const;
    /// motion_side() of each tool facet (-1 for a degenerate move): where each is placed.
    const std::vector<signed char>& sides() const { return side_; }
    /// The silhouette edges (indices in edges()), in order: plane side_.size() + i is edge i's.
    const std::vector<int>& silhouette() const { return silhouette_; }

   private:
    const SweepPolytopeBuilder* builder_;
    Eigen::Vector3d a_, b_, motion_;  ///< the ordered ends (both the start for a degenerate move)
    std::optional<GridPoint> grid_a_, grid_b_;
    bool exact_ = false, exact_silhouettes_ = false;
    GridPoint step_{};               ///< the reduced motion on the grid
    std::vector<signed char> side_;  ///< motion_side() of each tool facet (-1 for a degenerate move)
    std::vector<int> silhouette_;    ///< the silhouette edges, in edges() order
  };

  /// True when the move is too short to have a direction: its sweep is the tool at `start`.
  bool degenerate(const Eigen::Vector3d& start, const Eigen::Vector3d& end) const;

  /// True when every facet of the sweep from `start` to `end` carries its exact plane (see
  /// above): the tool's facets have them, both ends lie on the tool's grid, and (a sufficient
  /// bound) every silhouette normal fits kMaxIntegerNormal and every offset the predicates' range.
  /// False may also be said of a sweep whose planes happen to be exact.
  bool exact(const Eigen::Vector3d& start, const Eigen::Vector3d& end) const;

  /// The largest component (grid steps) of a motion reduced to coprime integers whose silhouette
  /// planes exact() holds exact: kMaxIntegerNormal / (2 × the largest tool edge component); 0
  /// when the tool is not on a grid. A long move in a general direction passes it
  /// (settle_segment_ends() in sweep_segments.h moves the ends so that none does).
  std::int64_t largest_exact_step() const;

  const ConvexPolytope& tool() const { return tool_; }

  struct Edge {
    int from, to;     ///< vertices, as they run in facet `left`
    int left, right;  ///< the facet holding from->to, and the one holding to->from
  };
  /// The tool's edges, sorted by (from, to): the order of the silhouette parallelograms.
  const std::vector<Edge>& edges() const { return edges_; }

  /// The motion's ends in the builder's order (lexicographically smaller first): facets at the
  /// start are placed at .first, those at the end at .second.
  static std::pair<Eigen::Vector3d, Eigen::Vector3d> ordered(const Eigen::Vector3d& start,
                                                             const Eigen::Vector3d& end);

  /// The halfspace of the parallelogram on silhouette edge `e` along `motion` from the ordered
  /// start `a` (as operator() computes it), with its exact plane when `a` and `motion` are on the
  /// grid.
  Halfspace silhouette_plane(const Edge& e, const Eigen::Vector3d& a, const Eigen::Vector3d& motion) const;
  /// silhouette_plane()'s rounded look alone (normal and offset bit for bit the same; no exact
  /// plane): what the culling compares and tests by.
  Halfspace silhouette_look(const Edge& e, const Eigen::Vector3d& a, const Eigen::Vector3d& motion) const;

 private:
  // The tool's facet f placed at `at`, with its exact plane when `grid_at` (`at` on the grid).
  Halfspace placed(int f, const Eigen::Vector3d& at, const GridPoint* grid_at) const;
  // silhouette_plane() with `a` on the grid at `start` and the motion reduced to `step`.
  Halfspace silhouette_plane(const Edge& e, const Eigen::Vector3d& a, const Eigen::Vector3d& motion,
                             const GridPoint& start, const GridPoint& step) const;
  std::optional<GridPoint> on_grid(const Eigen::Vector3d& x) const;

  ConvexPolytope tool_;
  std::vector<Edge> edges_;
  double size_ = 0.0;
  std::optional<int> grid_;               // when every tool facet has an exact plane on this grid
  std::vector<GridPoint> grid_vertices_;  // the tool's vertices on it
  std::int64_t largest_edge_ = 0;         // the largest |component| of a tool edge on the grid
  std::int64_t largest_vertex_ = 0;       // the largest |component| of a tool vertex on the grid
};

/// One-off form of SweepPolytopeBuilder.
ConvexPolytope sweep_polytope(const ConvexPolytope& tool, const Eigen::Vector3d& start,
                              const Eigen::Vector3d& end);

}  // namespace morph
