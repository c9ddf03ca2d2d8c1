// SPDX-License-Identifier: Apache-2.0
#include <morph/carve.h>
#include <morph/stock_face_cells.h>

#include <algorithm>
#include <cstddef>

namespace morph {
namespace {

Eigen::AlignedBox3d piece_box(const ConvexPiece& piece) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& p : corners(piece)) box.extend(p);
  return box;
}

// `pieces` minus every sweep of `order` but `skip` whose box meets theirs.
std::vector<ConvexPiece> minus_sweeps(std::vector<ConvexPiece> pieces, std::int32_t skip,
                                      const std::vector<std::uint32_t>& order,
                                      const std::vector<std::vector<ExactPlane>>& sweeps,
                                      const std::vector<Eigen::AlignedBox3d>& sweep_boxes,
                                      CarveCounts& counts) {
  for (std::size_t k = 0; k < order.size() && !pieces.empty(); ++k) {
    const std::uint32_t j = order[k];
    if (static_cast<std::int32_t>(j) == skip) continue;
    Eigen::AlignedBox3d reach;
    for (const ConvexPiece& p : pieces) reach.extend(piece_box(p));
    reach = grown_for_rounding(reach);
    if (!reach.intersects(sweep_boxes[j])) continue;
    ++counts.cutters;
    std::vector<ConvexPiece> next;
    for (const ConvexPiece& p : pieces) subtract(p, sweeps[j], next);
    pieces = std::move(next);
  }
  return pieces;
}

}  // namespace

void sort_pieces(std::vector<ConvexPiece>& pieces) {
  for (ConvexPiece& p : pieces) p = canonical(std::move(p));
  std::sort(pieces.begin(), pieces.end(), [](const ConvexPiece& x, const ConvexPiece& y) {
    return std::lexicographical_compare(
        x.edges.begin(), x.edges.end(), y.edges.begin(), y.edges.end(),
        [](const ExactPlane& a, const ExactPlane& b) { return a.rank < b.rank; });
  });
}

ExactPlane sweep_plane(const Halfspace& halfspace, std::uint32_t move, std::uint32_t k) {
  return ExactPlane{halfspace.normal, halfspace.offset, sweep_rank(move, k), 1, halfspace.exact};
}

std::vector<ExactPlane> sweep_planes(const std::vector<Halfspace>& halfspaces, std::uint32_t move) {
  std::vector<ExactPlane> planes;
  planes.reserve(halfspaces.size());
  for (std::size_t k = 0; k < halfspaces.size(); ++k)
    planes.push_back(sweep_plane(halfspaces[k], move, static_cast<std::uint32_t>(k)));
  return planes;
}

std::vector<CarvedPiece> carve_box(const Eigen::AlignedBox3d& box,
                                   const std::vector<std::vector<ExactPlane>>& sweeps,
                                   const std::vector<Eigen::AlignedBox3d>& sweep_boxes, CarveCounts* counts,
                                   const CuttingOrders* orders) {
  CarveCounts local;
  CarveCounts& c = counts ? *counts : local;
  const std::array<ExactPlane, 6> stock = box_planes(box);
  std::vector<std::uint32_t> every(sweeps.size());
  for (std::size_t j = 0; j < sweeps.size(); ++j) every[j] = static_cast<std::uint32_t>(j);
  const CellLattice lattice = CellLattice::of(box, sweep_boxes);
  std::vector<CarvedPiece> out;
  auto keep = [&](std::vector<ConvexPiece> pieces, std::int32_t move, std::int32_t face) {
    for (ConvexPiece& p : pieces) out.push_back(CarvedPiece{canonical(std::move(p)), move, face});
  };
  for (std::int32_t f = 0; f < 6; ++f) {
    ++c.facets;
    std::vector<ConvexPiece> pieces;
    for (FaceCell& cell : stock_face_cells(piece_in_box(stock[f], stock), every, sweep_boxes, lattice))
      for (ConvexPiece& p : minus_sweeps({std::move(cell.piece)}, -1, cell.sweeps, sweeps, sweep_boxes, c))
        pieces.push_back(std::move(p));
    sort_pieces(pieces);
    keep(std::move(pieces), -1, f);
  }
  for (std::size_t i = 0; i < sweeps.size(); ++i) {
    if (!sweep_boxes[i].intersects(box)) continue;
    for (std::size_t f = 0; f < sweeps[i].size(); ++f) {
      ++c.facets;
      const ConvexPiece facet = intersect(piece_in_box(sweeps[i][f], stock), sweeps[i]);
      if (facet.empty()) continue;
      // The listed sweeps first, in their order, then the others in move order.
      std::vector<std::uint32_t> order = every;
      if (orders) {
        const auto listed = orders->find({static_cast<std::int32_t>(i), static_cast<std::int32_t>(f)});
        if (listed != orders->end()) {
          const std::vector<std::uint32_t>& first = listed->second;
          std::stable_partition(order.begin(), order.end(), [&](std::uint32_t j) {
            return std::find(first.begin(), first.end(), j) != first.end();
          });
          std::copy(first.begin(), first.end(), order.begin());
        }
      }
      keep(minus_sweeps({facet}, static_cast<std::int32_t>(i), order, sweeps, sweep_boxes, c),
           static_cast<std::int32_t>(i), static_cast<std::int32_t>(f));
    }
  }
  c.pieces += static_cast<double>(out.size());
  return out;
}

}  // namespace morph
