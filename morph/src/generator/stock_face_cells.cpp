// SPDX-License-Identifier: Apache-2.0
#include <morph/stock_face_cells.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace morph {
namespace {

constexpr int kDeepest = 20;
// Cell planes rank after the stock's own planes and before the helper box's (stock_polytope.cpp).
constexpr std::uint32_t kCellRank = 0xC0000000u;
// 2 - golden ratio: as far from every simple fraction of a cell as a number can be.
constexpr double kCellPhase = 0.3819660112501051;

struct Split {
  const std::vector<Eigen::AlignedBox3d>& boxes;
  const CellLattice& lattice;
  std::array<int, 2> axes;
  std::size_t sweeps_per_cell;
  std::vector<FaceCell>& out;

  // `piece`, within the cell [lo, hi) in finest steps along both axes, meeting `near`'s boxes
  // maybe.
  void operator()(ConvexPiece piece, std::array<std::int64_t, 2> lo, std::array<std::int64_t, 2> hi,
                  const std::vector<std::uint32_t>& near) const {
    const Eigen::AlignedBox3d reach = reach_of(piece);
    std::vector<std::uint32_t> meeting;
    for (std::uint32_t j : near)
      if (reach.intersects(boxes[j])) meeting.push_back(j);
    const int wide = hi[0] - lo[0] >= hi[1] - lo[1] ? 0 : 1;
    if (meeting.size() <= sweeps_per_cell || hi[wide] - lo[wide] <= 1) {
      out.push_back(FaceCell{std::move(piece), std::move(meeting)});
      return;
    }
    const std::int64_t middle = (lo[wide] + hi[wide]) / 2;
    const ExactPlane boundary = lattice.plane(axes[wide], middle);
    ConvexPiece below = clip(piece, boundary), above = clip(piece, flipped(boundary));
    std::array<std::int64_t, 2> split_hi = hi, split_lo = lo;
    split_hi[wide] = split_lo[wide] = middle;
    if (!below.empty()) (*this)(std::move(below), lo, split_hi, meeting);
    if (!above.empty()) (*this)(std::move(above), split_lo, hi, meeting);
  }
};

}  // namespace

CellLattice CellLattice::of(const Eigen::AlignedBox3d& bounds,
                            const std::vector<Eigen::AlignedBox3d>& sweep_boxes) {
  CellLattice lattice;
  const double extent = std::max(bounds.sizes().maxCoeff(), 1e-6);
  // The root cell, twice the power of two above the extent, holds the bounds from its origin.
  const double half = std::exp2(std::ceil(std::log2(extent)));
  lattice.root = 2.0 * half;
  lattice.origin = (bounds.min() / half).array().floor().matrix() * half;
  double smallest = lattice.root;
  for (const Eigen::AlignedBox3d& box : sweep_boxes)
    if (!box.isEmpty()) smallest = std::min(smallest, box.sizes().minCoeff());
  const double finest = std::max(0.25 * smallest, lattice.root * std::exp2(-kDeepest));
  lattice.depth = std::clamp(static_cast<int>(std::ceil(std::log2(lattice.root / finest))), 0, kDeepest);
  return lattice;
}

ExactPlane CellLattice::plane(int axis, std::int64_t index) const {
  const double step = std::ldexp(root, -depth);
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  normal[axis] = 1.0;
  // Off the lattice by a fraction of a finest cell that no power of two divides: stock faces and
  // sweep ends at round numbers of the job's units are neither on a cell plane nor a sliver's
  // width from one (a stock face on a lattice line would be cut into a strip that rounds flat).
  const double offset = origin[axis] + (static_cast<double>(index) + kCellPhase) * step;
  const auto rank = kCellRank + (static_cast<std::uint32_t>(axis) << 24) + static_cast<std::uint32_t>(index);
  return ExactPlane{normal, offset, stock_rank(rank), 1};
}

std::vector<FaceCell> stock_face_cells(const ConvexPiece& face, const std::vector<std::uint32_t>& near,
                                       const std::vector<Eigen::AlignedBox3d>& sweep_boxes,
                                       const CellLattice& lattice, std::size_t sweeps_per_cell) {
  std::vector<FaceCell> out;
  if (face.empty()) return out;
  // The cells run along the two axes nearest the face's plane.
  const Eigen::Vector3d n = face.support.normal.cwiseAbs();
  int normal_axis = 0;
  for (int a = 1; a < 3; ++a)
    if (n[a] > n[normal_axis]) normal_axis = a;
  const std::array<int, 2> axes = {normal_axis == 0 ? 1 : 0, normal_axis == 2 ? 1 : 2};
  const std::int64_t cells = std::int64_t{1} << lattice.depth;
  Split{sweep_boxes, lattice, axes, sweeps_per_cell, out}(face, {0, 0}, {cells, cells}, near);
  return out;
}

}  // namespace morph
