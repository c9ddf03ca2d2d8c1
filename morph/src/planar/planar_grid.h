// SPDX-License-Identifier: Apache-2.0
#pragma once
// A uniform grid over bounding boxes: each box is listed in every cell it overlaps, so pairs of
// overlapping boxes are found cell by cell instead of all against all.
#include <morph/planar_curve.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace morph::planar {

class UniformGrid {
 public:
  /// Cells of about `cell` job units over `extent` (at most `max_cells` of them).
  UniformGrid(const std::vector<Box2>& boxes, const Box2& extent, double cell,
              std::size_t max_cells = 1u << 22)
      : origin_(extent.min()) {
    const Vec2 size = extent.sizes().cwiseMax(1e-300);
    cell = std::max(cell, std::sqrt(size.x() * size.y() / static_cast<double>(max_cells)));
    cell = std::max({cell, size.x() / 65536.0, size.y() / 65536.0});
    inv_cell_ = 1.0 / cell;
    nx_ = static_cast<int>(std::floor(size.x() * inv_cell_)) + 1;
    ny_ = static_cast<int>(std::floor(size.y() * inv_cell_)) + 1;
    start_.assign(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
    for (const Box2& box : boxes) visit_cells(box, [&](std::size_t c) { ++start_[c + 1]; });
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    items_.resize(start_.back());
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    for (std::uint32_t i = 0; i < boxes.size(); ++i)
      if (!boxes[i].isEmpty()) visit_cells(boxes[i], [&](std::size_t c) { items_[fill[c]++] = i; });
  }

  std::size_t cell_count() const { return start_.size() - 1; }
  int columns() const { return nx_; }
  int rows() const { return ny_; }
  /// Items listed in cell c (row-major).
  const std::uint32_t* begin(std::size_t c) const { return items_.data() + start_[c]; }
  const std::uint32_t* end(std::size_t c) const { return items_.data() + start_[c + 1]; }
  int column_of(double x) const {
    return std::clamp(static_cast<int>(std::floor((x - origin_.x()) * inv_cell_)), 0, nx_ - 1);
  }
  int row_of(double y) const {
    return std::clamp(static_cast<int>(std::floor((y - origin_.y()) * inv_cell_)), 0, ny_ - 1);
  }
  std::size_t cell_of(const Vec2& p) const {
    return static_cast<std::size_t>(row_of(p.y())) * nx_ + static_cast<std::size_t>(column_of(p.x()));
  }
  /// The first cell (lowest row, then column) that both boxes overlap: a pair is handled there only.
  std::size_t first_common_cell(const Box2& a, const Box2& b) const {
    const int cx = column_of(std::max(a.min().x(), b.min().x()));
    const int cy = row_of(std::max(a.min().y(), b.min().y()));
    return static_cast<std::size_t>(cy) * nx_ + static_cast<std::size_t>(cx);
  }

  template <class F>
  void visit_cells(const Box2& box, F&& f) const {
    if (box.isEmpty()) return;
    const int x0 = column_of(box.min().x()), x1 = column_of(box.max().x());
    const int y0 = row_of(box.min().y()), y1 = row_of(box.max().y());
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) f(static_cast<std::size_t>(y) * nx_ + static_cast<std::size_t>(x));
  }

 private:
  Vec2 origin_;
  double inv_cell_ = 1.0;
  int nx_ = 1, ny_ = 1;
  std::vector<std::size_t> start_;
  std::vector<std::uint32_t> items_;
};

}  // namespace morph::planar
