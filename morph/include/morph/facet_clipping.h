// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file facet_clipping.h
/// Generator 2's facet BSP: convex pieces of planes cut by planes, every decision by the exact
/// perturbed predicates of plane_predicates.h. A piece is its support plane and the cyclic list of
/// planes bounding it; its corners are plane triples (support, edge k-1, edge k), so two pieces
/// meeting along a line name the same corners by the same planes. Used for a sweep facet within
/// the stock and its own polytope, minus the union of the other sweeps, and for a stock face
/// minus the sweeps that reach it.
#include <morph/plane_predicates.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
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

/// The same piece with its edges rotated to start at the lowest rank: a convex piece's edge
/// cycle is unique, so two pieces of the same planes compare equal after this whatever order
/// they were clipped in (the fan of emit.h starts at corner 0).
ConvexPiece canonical(ConvexPiece piece);

/// The corners, rounded to doubles (vertex_point()).
std::vector<Eigen::Vector3d> corners(const ConvexPiece& piece);

/// Area times the support's unit normal direction, from the rounded corners (square units).
Eigen::Vector3d area_vector(const ConvexPiece& piece);

}  // namespace morph
