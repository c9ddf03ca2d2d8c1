// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file facet_clipping.h
/// The generator's facet BSP: convex pieces of planes cut by planes, every decision by the exact
/// perturbed predicates of plane_predicates.h. A piece is its support plane and the cyclic list of
/// planes bounding it; its corners are plane triples (support, edge k-1, edge k), so two pieces
/// meeting along a line name the same corners by the same planes. Used for a sweep facet within
/// the stock and its own polytope, minus the union of the other sweeps, and for a stock face
/// minus the sweeps that reach it.
#include <morph/plane_predicates.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

namespace morph {

/// A convex part of `support`'s plane: where every edge plane's value is negative. Edges run
/// counter-clockwise seen from the side `support.normal` points to; corner k is the vertex of
/// (support, edges[k-1], edges[k]).
struct ConvexPiece {
  ExactPlane support;
  std::vector<ExactPlane> edges;
  bool empty() const { return edges.size() < 3; }
};

/// The same plane facing the other way: its halfspace's closure's complement, with the
/// perturbation turned over too, so side_at_vertex() of it is exactly minus that of `p`.
ExactPlane flipped(const ExactPlane& p);

/// The six planes of a box stock, outward, contracting, ranked stock_rank(0..5) in the order
/// -x, +x, -y, +y, -z, +z.
std::array<ExactPlane, 6> box_planes(const Eigen::AlignedBox3d& box);

/// `support`'s plane within the box of `box` (box_planes()); empty when they miss.
ConvexPiece piece_in_box(const ExactPlane& support, const std::array<ExactPlane, 6>& box);

/// The part of `piece` inside `plane` (value negative). A plane of the same rank as the support
/// counts as holding the piece inside it; one of an edge, by that edge's orientation.
ConvexPiece clip(const ConvexPiece& piece, const ExactPlane& plane);

/// The part of `piece` inside every plane of `planes` (clip() by each; planes clearly apart
/// from the piece's corners are skipped by a float look that cannot change the answer).
ConvexPiece intersect(ConvexPiece piece, const std::vector<ExactPlane>& planes);

/// Appends to `out` the parts of `piece` outside the convex polytope that is the intersection of
/// `cutter`'s halfspaces: `piece` itself when the polytope misses it, else one convex piece per
/// plane of the cutter bounding the part inside, in rank order. The pieces depend only on that
/// part, so any list of the cutter's planes that gives the same part gives the same pieces.
/// Returns false when the polytope misses `piece` (then `piece` is appended whole).
bool subtract(const ConvexPiece& piece, const std::vector<ExactPlane>& cutter, std::vector<ConvexPiece>& out);

/// The float look at the vertex of three planes, as RoughCorners takes each corner of a piece
/// (below): a point near the exact vertex, and where the planes are close to parallel a bound of
/// its distance from it.
struct CornerLook {
  Eigen::Vector3d point;
  double length = 0.0;  ///< of point
  double error = 0.0;   ///< a bound of point's distance from the exact corner (0: well conditioned)
  double slack = 0.0;   ///< 1e-9·length + error: the corner's part of look_side()'s margin, per unit normal
};
/// The look at the vertex of s, a, b; nothing when no bound of its error holds.
std::optional<CornerLook> corner_look(const ExactPlane& s, const ExactPlane& a, const ExactPlane& b);
/// side_at_vertex()'s sign of `plane` at the looked-at vertex when the look is sure of it (with
/// RoughCorners' margin, 1e-9·(1 + |offset| + length·|corner|) + length·error), else 0.
/// `length`: of plane.normal. Inline: the clipping asks it of every corner for every plane.
inline int look_side(const CornerLook& corner, const ExactPlane& plane, double length) {
  const double value = plane.normal.dot(corner.point) - plane.offset;
  const double margin = 1e-9 * (1 + std::abs(plane.offset)) + length * corner.slack;
  return value < -margin ? -1 : (value > margin ? 1 : 0);
}

/// A float look at a piece, to skip planes that are clearly apart from it (all corners below, or
/// all above, by far more than the rounding of the corners): the exact predicates would decide
/// the same, so nothing depends on it but speed. For corners whose normals' determinant is above
/// 1e-3 of the product of their lengths, the looks' Cramer in double (look_vertex_point()), and
/// above 1e-7, Cramer's rule in long double (vertex_point()), err by less than about
/// 1e-11·(|offset| + |corner|), a hundredth of the margin below; for the others
/// (planes close to parallel, as a facet nearly along the motion and its silhouette plane) the
/// margin adds the corner's forward error bound (bounded_vertex_point()).
/// Made once for a piece that many cutters meet (a stock face's part, a kept facet's piece), it
/// saves rounding its corners again for each: that was a tenth of a job's time.
class RoughCorners {
 public:
  explicit RoughCorners(const ConvexPiece& piece) : RoughCorners(piece, nullptr, {}) {}
  /// No look (every side() undecided): storage for remake().
  RoughCorners() : usable_(false) {}
  /// The look at `piece`, taking from `old` the corners that were its corners: from_old[k] is the
  /// index in `old` of corner k, or -1 for a new corner (the same three planes give the same point).
  RoughCorners(const ConvexPiece& piece, const RoughCorners* old, const std::vector<int>& from_old);
  /// This look made again, as that constructor makes it, of `piece` from `old` (not this one),
  /// in the storage this one has: a clip's next look without an allocation.
  void remake(const ConvexPiece& piece, const RoughCorners& old, const std::vector<int>& from_old);
  /// -1: every corner clearly inside `plane`; +1: every corner clearly outside; 0: undecided,
  /// and then corner(k) is -1 or +1 for a corner clearly inside or outside, 0 for one too close.
  int side(const ExactPlane& plane);
  /// side() without keeping the corners' looks.
  int peek(const ExactPlane& plane) const;
  /// True when every corner is clearly outside `plane` (side() would be +1), then the piece is.
  bool outside(const ExactPlane& plane) const;
  /// The last side()'s look at corner k (0 when unusable).
  int corner(std::size_t k) const { return usable_ ? corners_[k].look : 0; }
  /// side_at_vertex() of corner k of `piece` (the piece this look is of) and `plane`: where the
  /// corner is a point of the grid its planes and `plane` are exact on, side_at_grid_vertex()
  /// from that point, found once per corner and kept as the piece is clipped.
  int exact_side(const ConvexPiece& piece, std::size_t k, const ExactPlane& plane) const;

 private:
  void make(const ConvexPiece& piece, const RoughCorners* old, const std::vector<int>& from_old);
  // side() and peek(): the corners' looks at `plane`, each given to keep(corner, look).
  template <class Corners, class Keep>
  static int sides(Corners& corners, const ExactPlane& plane, Keep&& keep);
  struct Corner : CornerLook {
    int look = 0;  ///< the last side()'s look at it
    /// The corner as a grid point, once looked for (side_at_vertex_near()).
    mutable VertexGrid grid;
  };
  std::vector<Corner> corners_;
  bool usable_ = true;
};

/// subtract() with the look of `piece` made beforehand (the same pieces). When `looks` is given
/// and the cutter reaches `piece`, it receives the look of each piece appended to `out`, made
/// from `look`'s corners where they are the piece's (its corners off the cutter's planes).
bool subtract(const ConvexPiece& piece, const RoughCorners& look, const std::vector<ExactPlane>& cutter,
              std::vector<ConvexPiece>& out, std::vector<RoughCorners>* looks = nullptr);

/// The same piece with its edges rotated to start at the lowest rank: a convex piece's edge
/// cycle is unique, so two pieces of the same planes compare equal after this whatever order
/// they were clipped in (the fan of emit.h starts at corner 0).
ConvexPiece canonical(ConvexPiece piece);

/// The corners, rounded to doubles (vertex_point()).
std::vector<Eigen::Vector3d> corners(const ConvexPiece& piece);

/// Area times the support's unit normal direction, from the rounded corners (square units).
Eigen::Vector3d area_vector(const ConvexPiece& piece);

/// `box` grown by 1e-7 of its coordinates' size (job units): a box of rounded corners then holds
/// the exact ones, and boxes that only touch the exact piece meet it (touching counts wherever
/// the carvings ask which sweeps reach a piece).
Eigen::AlignedBox3d grown_for_rounding(Eigen::AlignedBox3d box);

/// The box of the piece's rounded corners, grown_for_rounding(): what may reach the piece meets it.
Eigen::AlignedBox3d reach_of(const ConvexPiece& piece);

}  // namespace morph
