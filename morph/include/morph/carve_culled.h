// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file carve_culled.h
/// The carving of carve.h at the scale of real jobs: the same pieces as carve_box() (the same
/// exact sets, split the same way), with the work cut down by the culling stage
/// (sweep_culling.h). Only the facets the culling keeps are carved, each minus the moves it lists
/// with the planes of theirs that cross it (a cutter's other planes leave the facet's part inside
/// it unchanged, and subtract() splits by that part alone); each stock face cut into cells
/// (stock_face_cells.h), each cell minus the sweeps whose boxes meet it (AabbTree), a piece that
/// a later sweep's inscribed capsule holds dropped at once. A job with several tools is culled
/// tool by tool: another tool's sweeps are cutters of a kept facet whenever their boxes meet it,
/// with all their planes.
/// Facets are independent and carved in parallel; the pieces come out in a fixed order.
#include <morph/carve.h>
#include <morph/carved_pieces.h>
#include <morph/parallel.h>
#include <morph/progress.h>
#include <morph/stock_polytope.h>
#include <morph/sweep_culling.h>

#include <Eigen/Geometry>

#include <vector>

namespace morph {

/// One straight move of one tool, in job order (the tie order).
struct CarveSweep {
  const SweepPolytopeBuilder* tool = nullptr;  ///< the tool's sweeps; moves of one tool share it
  Eigen::Vector3d from = Eigen::Vector3d::Zero(), to = Eigen::Vector3d::Zero();
};

/// What the stages did and cost: CPU seconds summed over the threads.
struct CarveStages {
  CullingCounts culling;
  CarveCounts carve;
  double seconds_setup = 0.0;   ///< the culling's trees and the sweeps' boxes
  double seconds_cull = 0.0;    ///< SweepCulling::cull over every move
  double seconds_facets = 0.0;  ///< the kept facets within the stock and their own sweep, minus their cutters
  double seconds_stock = 0.0;   ///< the stock faces minus the sweeps meeting them
  /// Of seconds_facets: the kept facets within the stock and their own sweep (the rest is cutting).
  double seconds_own_facets = 0.0;
  /// Exact predicate calls and how many the float filter left to exact arithmetic: building the
  /// kept facets (own) and cutting them (cut).
  double predicates_own = 0.0, exact_own = 0.0, predicates_cut = 0.0, exact_cut = 0.0;
  /// Of those, the exact zeros settled by the tie order (building and cutting the kept facets).
  double ties = 0.0;
  /// Decided by the double-word filter, not counted in exact_* (building and cutting).
  double refined = 0.0;
};

/// The pieces of box \ ∪ sweeps, as carve_box() gives them for the same moves and cutting orders
/// (up to the order of the pieces; expanded() gives them as values), with their planes in one
/// table (carved_pieces.h): stock faces first (box_planes() order), then each move's kept facets
/// in facet order. A kept facet is cut by the sweeps that may reach it, those that may
/// hold the most of it first: the most of its points below all of their faces near it, then the
/// fewest planes crossing it, then move order (a sweep that takes most of a facet first leaves
/// few pieces for the others); that order is written to `orders` when given. `policy` chooses
/// one thread or TBB; the output does not depend on it.
CarvedPieces carve_culled(const Eigen::AlignedBox3d& box, const std::vector<CarveSweep>& sweeps,
                          ExecutionPolicy policy = ExecutionPolicy::Parallel, CarveStages* stages = nullptr,
                          Progress* progress = nullptr, CuttingOrders* orders = nullptr);

/// The same for a convex stock (stock_polytope.h): its faces take the place of the box's, in the
/// order of its planes; for box_stock_polytope(box) the pieces are those of the box overload.
/// `progress`, when given, sees the stage "erode: carve" with one unit per stock face and per
/// move, and may stop it: carve_culled() then throws Interrupted.
CarvedPieces carve_culled(const StockPolytope& stock, const std::vector<CarveSweep>& sweeps,
                          ExecutionPolicy policy = ExecutionPolicy::Parallel, CarveStages* stages = nullptr,
                          Progress* progress = nullptr, CuttingOrders* orders = nullptr);

/// The sweeps' boxes: the tool polytope's box at both ends, grown by a rounding margin.
std::vector<Eigen::AlignedBox3d> sweep_boxes(const std::vector<CarveSweep>& sweeps);

}  // namespace morph
