// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file planar_erosion.h
/// The paper's regularized partial erosion in two dimensions, exact: X \ (T (+) B) for a stock
/// region X, a planar trajectory T and a disc B of radius r, as closed loops of segments and arcs
/// with provenance. The candidate curves (the stock's boundary and every move's dilation boundary,
/// see planar_dilation.h) are split at all their mutual intersections (found cell by cell in a
/// uniform grid), each piece is kept or dropped by the exact distances of its midpoint to the moves
/// and its position in the stock, and the kept pieces are linked into loops.
///
/// Ties are decided by one rule: a piece lying on other candidate curves (a retraced move, a pass
/// along a stock edge, two passes exactly 2r apart) is kept only if the result is on exactly one
/// side of it, judged from the outward normals of every coincident curve, and only once (stock
/// first, then the lowest move). Points closer than 1e-9 of the job's extent are one point.
#include <morph/parallel.h>
#include <morph/planar_dilation.h>
#include <morph/planar_region.h>
#include <morph/progress.h>

#include <cstddef>

namespace morph::planar {

struct PlanarOptions {
  ExecutionPolicy policy = ExecutionPolicy::Parallel;  ///< the output does not depend on it
  Progress* progress = nullptr;                        ///< stages "planar: split", "planar: classify"
};

struct PlanarStats {
  std::size_t moves = 0;              ///< moves of the trajectory
  std::size_t moves_near_stock = 0;   ///< moves whose dilation's bounds meet the stock's
  std::size_t candidate_curves = 0;   ///< stock curves + dilation boundary curves
  std::size_t intersections = 0;      ///< points where two candidate curves meet
  std::size_t vertices = 0;           ///< distinct points after merging
  std::size_t pieces = 0;             ///< sub-curves classified
  std::size_t pieces_kept = 0;        ///< sub-curves on the result's boundary (after removing copies)
  std::size_t coincident_copies = 0;  ///< kept pieces dropped as copies of another
  double seconds = 0.0;
};

struct PlanarResult {
  Region region;  ///< outer loops counter-clockwise, holes clockwise, pieces grouped
  PlanarStats stats;
};

/// X \ (T (+) B), the regularized partial erosion (paper eq. 9). Throws InputError for a radius
/// that is not positive, GeometryError if the kept pieces do not close into loops.
PlanarResult erode(const Region& stock, const Trajectory& moves, double radius,
                   const PlanarOptions& options = {});
/// T (+) B: the union of the moves' dilations (paper figure 12 b).
PlanarResult dilate(const Trajectory& moves, double radius, const PlanarOptions& options = {});
/// The classical erosion X (-) B = {y : B_y inside X} (paper eq. 2), whose boundary is
/// Fr(X (-) B) of eq. 3: the contour the tool centre follows to finish the stock's profile from
/// inside. Computed as X \ (Fr(X) (+) B); its curves have Origin::Offset (source = stock element).
PlanarResult classical_erosion(const Region& stock, double radius, const PlanarOptions& options = {});

}  // namespace morph::planar
