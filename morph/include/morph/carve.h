// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file carve.h
/// The boundary of box stock minus the union of convex sweep polytopes, as convex pieces
/// (facet_clipping.h): each stock face, in cells (stock_face_cells.h), minus every sweep that
/// reaches the cell, and each sweep facet
/// within the stock and its own polytope minus every other sweep. Every decision is an exact
/// perturbed predicate, so the pieces bound a closed, oriented solid; the tie order makes a
/// retraced move's coinciding facets the earlier move's alone.
#include <morph/facet_clipping.h>
#include <morph/sweep_polytope.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

namespace morph {

/// Halfspace k of sweep `move` as an exact plane, ranked sweep_rank(move, k).
ExactPlane sweep_plane(const Halfspace& halfspace, std::uint32_t move, std::uint32_t k);

/// One sweep polytope's halfspaces as exact planes, ranked sweep_rank(move, k) in their order.
std::vector<ExactPlane> sweep_planes(const std::vector<Halfspace>& halfspaces, std::uint32_t move);

/// A piece of the carved boundary. For a stock face the piece faces out of the solid; for a
/// sweep facet it faces into the solid (its support is the sweep's outward plane).
struct CarvedPiece {
  ConvexPiece piece;
  std::int32_t move = -1;  ///< the sweep's move, or -1 for a stock face
  std::int32_t face = 0;   ///< the stock face (box_planes() order) or the sweep's facet index
  bool faces_out() const { return move < 0; }
};

/// Sorts a stock face's pieces (each canonical()) by their edge planes' ranks: the order the two
/// carvings give them in differs, and later stages (emit's rounding) may depend on the order.
void sort_pieces(std::vector<ConvexPiece>& pieces);

/// Counts of the carving, for benches.
struct CarveCounts {
  double facets = 0, cutters = 0, pieces = 0;
};

/// The order in which sweeps cut a sweep facet, by (move, facet): the pieces of a facet depend on
/// it (the part left is the same set in any order), so a carving that chooses its own order can
/// give it to carve_box() to be checked piece for piece.
using CuttingOrders = std::map<std::pair<std::int32_t, std::int32_t>, std::vector<std::uint32_t>>;

/// The pieces of box \ ∪ sweeps[i] (each sweep the planes of sweep_planes(), move order = tie
/// order), each canonical(). All pairs of sweeps whose boxes meet are tried: the reference for
/// small jobs; carve_culled.h gives the same pieces at the scale of real jobs. A sweep facet is
/// cut by the sweeps in move order, or, when `orders` lists it, first by those listed in their
/// order and then by every other in move order.
std::vector<CarvedPiece> carve_box(const Eigen::AlignedBox3d& box,
                                   const std::vector<std::vector<ExactPlane>>& sweeps,
                                   const std::vector<Eigen::AlignedBox3d>& sweep_boxes,
                                   CarveCounts* counts = nullptr, const CuttingOrders* orders = nullptr);

}  // namespace morph
