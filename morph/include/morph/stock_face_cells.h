// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file stock_face_cells.h
/// A stock face cut into cells before it is carved. Carving a face by every sweep that reaches it
/// splits it along each sweep's planes into wedges as wide as the face, and each wedge goes on to
/// meet every later sweep: bear.nc's top face, which the sweeps remove whole, made 105,000 pieces
/// and took a quarter of the generator's time. A cell meets only the sweeps near it, and most cells
/// of a machined face lie wholly inside one sweep (the carving drops them at once).
///
/// The cells are those of a quadtree on one lattice for the whole job, so a cell plane is the same
/// plane, with the same rank, on every face and in every cell it bounds: both sides of a cell edge
/// name their corners by the same planes (conform.h). A cell is split while its part of the face
/// meets more than `sweeps_per_cell` sweeps' boxes and it is larger than the lattice's finest
/// cell, a quarter of the smallest sweep box's side: a point that many sweeps cover needs no
/// finer cells to drop them. The cell planes lie off the lattice lines by 0.382 of a finest cell
/// (2 minus the golden ratio), so no grid vertex of quantize.h and no round stock face lies on
/// them or a sliver's width from them.
#include <morph/facet_clipping.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

namespace morph {

/// The quadtree's lattice: cells of side root·2^-d (d ≤ depth) at multiples from `origin`.
struct CellLattice {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double root = 0.0;  ///< the side of the root cell, a power of two (job units)
  int depth = 0;      ///< the finest cells' side is root·2^-depth

  /// The lattice holding `bounds` (the stock's) whose finest side is at most a quarter of the
  /// smallest side of any of `sweep_boxes`, and at least 2^-20 of the root.
  static CellLattice of(const Eigen::AlignedBox3d& bounds,
                        const std::vector<Eigen::AlignedBox3d>& sweep_boxes);
  /// The plane x[axis] <= the cell boundary at root·2^-depth·index from the origin (plus the
  /// offset), ranked by (axis, index) among the stock's ranks, expanding.
  ExactPlane plane(int axis, std::int64_t index) const;
};

/// A cell's part of a stock face and the sweeps (indices into the boxes, ascending) whose boxes
/// meet it.
struct FaceCell {
  ConvexPiece piece;
  std::vector<std::uint32_t> sweeps;
};

/// Sweeps per cell above which a cell is split.
constexpr std::size_t kSweepsPerCell = 24;

/// `face` (a stock face's piece) cut into the lattice's cells, each with the sweeps of `near`
/// (ascending indices into `sweep_boxes`) whose boxes meet the cell's part. Empty parts are left
/// out; the parts' union is `face`. The same cells whatever the thread.
std::vector<FaceCell> stock_face_cells(const ConvexPiece& face, const std::vector<std::uint32_t>& near,
                                       const std::vector<Eigen::AlignedBox3d>& sweep_boxes,
                                       const CellLattice& lattice,
                                       std::size_t sweeps_per_cell = kSweepsPerCell);

}  // namespace morph
