// SPDX-License-Identifier: Apache-2.0
#include "generator/tool_facet_sectors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <optional>
#include <utility>

namespace morph {

namespace {

using Eigen::AlignedBox3d;

// The diamond angle of (x, y) ≠ 0: 0 on +x, 1 on +y, 2 on -x, 3 on -y, monotone in atan2 between,
// and exactly 2 more at the opposite point. Its rounding is a few ulps of numbers below 4.
double diamond_angle(double x, double y) {
  if (y >= 0) return x >= 0 ? y / (x + y) : 1.0 - x / (y - x);
  return x < 0 ? 2.0 - y / (-x - y) : 3.0 + x / (x - y);
}

// Far above the diamond angles' rounding (1e-15), far below a cell (1e-3 and more).
constexpr double kAngleMargin = 1e-9;

// The diamond angles a box reaches about the axis, as [low, high] with high - low < 2 (a box
// apart from the axis subtends less than half a turn; its extreme directions are corners);
// nothing for a box that holds a point of the axis.
std::optional<std::pair<double, double>> angles_of(const AlignedBox3d& box) {
  const double x0 = box.min().x(), x1 = box.max().x(), y0 = box.min().y(), y1 = box.max().y();
  if (x0 <= 0 && x1 >= 0 && y0 <= 0 && y1 >= 0) return std::nullopt;
  const double centre = diamond_angle(0.5 * (x0 + x1), 0.5 * (y0 + y1));
  double low = centre, high = centre;
  const std::array<std::pair<double, double>, 4> corners{{{x0, y0}, {x1, y0}, {x0, y1}, {x1, y1}}};
  for (const auto& [x, y] : corners) {
    if (x == 0 && y == 0) return std::nullopt;
    double delta = diamond_angle(x, y) - centre;
    if (delta > 2.0) delta -= 4.0;
    if (delta < -2.0) delta += 4.0;
    low = std::min(low, centre + delta);
    high = std::max(high, centre + delta);
  }
  return std::pair{low - kAngleMargin, high + kAngleMargin};
}

// The cell of an unwrapped diamond angle, not yet taken mod M.
long cell_of(double angle, int cells) {
  return static_cast<long>(std::floor(angle * cells / 4.0));
}

}  // namespace

ToolFacetSectors::ToolFacetSectors(const std::vector<AlignedBox3d>& boxes) {
  // Rings: the facets of one box z range. M: the most facets one ring has (a ring of the tool's
  // sectors), so a side facet's box reaches about two cells.
  std::map<std::pair<double, double>, std::vector<std::uint32_t>> by_z;
  for (std::size_t k = 0; k < boxes.size(); ++k)
    by_z[{boxes[k].min().z(), boxes[k].max().z()}].push_back(static_cast<std::uint32_t>(k));
  std::size_t largest = 1;
  for (const auto& [z, members] : by_z) largest = std::max(largest, members.size());
  cells_ = static_cast<int>(std::min<std::size_t>(largest, 1 << 16));

  // Each facet's first cell and span; about the axis or over a quarter turn: every query's.
  std::vector<long> first_cell(boxes.size(), -1), span(boxes.size(), 1);
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    const auto angles = angles_of(boxes[k]);
    if (!angles || angles->second - angles->first >= 1.0) {
      everywhere_.push_back(static_cast<std::uint32_t>(k));
      continue;
    }
    const long low = cell_of(angles->first, cells_), high = cell_of(angles->second, cells_);
    first_cell[k] = ((low % cells_) + cells_) % cells_;
    span[k] = high - low + 1;
  }

  for (const auto& [z, members] : by_z) {
    Ring ring{z.first, z.second, 1};
    std::vector<std::vector<std::uint32_t>> in_cell(static_cast<std::size_t>(cells_));
    for (std::uint32_t k : members)
      if (first_cell[k] >= 0) {
        in_cell[static_cast<std::size_t>(first_cell[k])].push_back(k);
        ring.span = std::max(ring.span, static_cast<int>(span[k]));
      }
    rings_.push_back(ring);
    for (const std::vector<std::uint32_t>& cell : in_cell) {
      cell_start_.push_back(static_cast<std::uint32_t>(facets_.size()));
      facets_.insert(facets_.end(), cell.begin(), cell.end());
    }
  }
  cell_start_.push_back(static_cast<std::uint32_t>(facets_.size()));
  for (std::size_t r = 1; r < rings_.size(); ++r) z_max_sorted_ &= rings_[r - 1].z_max <= rings_[r].z_max;
}

int ToolFacetSectors::span() const {
  int largest = 1;
  for (const Ring& r : rings_) largest = std::max(largest, r.span);
  return largest;
}

ToolFacetSectors::QueryCells ToolFacetSectors::cells_of(const AlignedBox3d& query) const {
  const auto angles = angles_of(query);
  if (!angles) return {true, 0, 0};
  const long low = cell_of(angles->first, cells_), high = cell_of(angles->second, cells_);
  if (high - low + 1 >= cells_) return {true, 0, 0};
  return {false, static_cast<int>(((low % cells_) + cells_) % cells_), static_cast<int>(high - low + 1)};
}

std::size_t ToolFacetSectors::first_ring_reaching(double z) const {
  if (!z_max_sorted_) return 0;
  return static_cast<std::size_t>(
      std::partition_point(rings_.begin(), rings_.end(), [&](const Ring& r) { return r.z_max < z; }) -
      rings_.begin());
}

}  // namespace morph
