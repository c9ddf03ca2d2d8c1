// SPDX-License-Identifier: Apache-2.0
#pragma once
// A region's curves in a uniform grid: the nearest boundary point and inside/outside for many
// query points.
#include <morph/planar_region.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "planar/planar_grid.h"

namespace morph::planar {

class RegionIndex {
 public:
  explicit RegionIndex(const Region& region)
      : curves_(collect(region)),
        boxes_(boxes_of(curves_)),
        extent_(extent_of(boxes_)),
        grid_(boxes_, extent_, cell_size(extent_, curves_.size())),
        cell_(std::max(extent_.sizes().maxCoeff(), 1e-300) / std::max(grid_.columns(), grid_.rows())) {}

  bool empty() const { return curves_.empty(); }
  const std::vector<Curve>& curves() const { return curves_; }

  /// The nearest point of the region's boundary to p (distance +infinity for an empty region).
  ClosestPoint nearest(const Vec2& p, std::size_t* curve = nullptr) const {
    ClosestPoint best;
    best.distance = std::numeric_limits<double>::infinity();
    if (curves_.empty()) return best;
    const double far = (extent_.center() - p).norm() + extent_.sizes().norm();
    for (double reach = cell_;; reach *= 2.0) {
      const Box2 window(p - Vec2::Constant(reach), p + Vec2::Constant(reach));
      grid_.visit_cells(window.intersection(extent_).isEmpty() ? extent_ : window, [&](std::size_t c) {
        for (const std::uint32_t* it = grid_.begin(c); it != grid_.end(c); ++it) {
          if (boxes_[*it].exteriorDistance(p) >= best.distance) continue;
          const ClosestPoint cp = closest_point(curves_[*it], p);
          if (cp.distance < best.distance) {
            best = cp;
            if (curve) *curve = *it;
          }
        }
      });
      if (best.distance <= reach || reach > far) return best;
    }
  }

  /// True if p is inside the region (even-odd over the crossings of a ray towards +x).
  bool contains(const Vec2& p) const {
    if (curves_.empty() || p.y() < extent_.min().y() || p.y() > extent_.max().y() ||
        p.x() > extent_.max().x())
      return false;
    const int row = grid_.row_of(p.y());
    std::vector<std::uint32_t> seen;
    for (int col = grid_.column_of(p.x()); col < grid_.columns(); ++col) {
      const std::size_t c = static_cast<std::size_t>(row) * grid_.columns() + col;
      seen.insert(seen.end(), grid_.begin(c), grid_.end(c));
    }
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    int n = 0;
    for (const std::uint32_t i : seen) n += crossings(curves_[i], p);
    return (n & 1) != 0;
  }

 private:
  static std::vector<Curve> collect(const Region& region) {
    std::vector<Curve> out;
    for (const Loop& loop : region.loops) out.insert(out.end(), loop.curves.begin(), loop.curves.end());
    return out;
  }
  static std::vector<Box2> boxes_of(const std::vector<Curve>& curves) {
    std::vector<Box2> boxes;
    for (const Curve& c : curves) boxes.push_back(bounds(c));
    return boxes;
  }
  static Box2 extent_of(const std::vector<Box2>& boxes) {
    Box2 box;
    for (const Box2& b : boxes) box.extend(b);
    if (box.isEmpty()) box = Box2(Vec2::Zero(), Vec2::Zero());
    return box;
  }
  static double cell_size(const Box2& extent, std::size_t n) {
    return std::max(extent.sizes().maxCoeff(), 1e-300) / std::max(1.0, std::sqrt(static_cast<double>(n)));
  }

  std::vector<Curve> curves_;
  std::vector<Box2> boxes_;
  Box2 extent_;
  UniformGrid grid_;
  double cell_;
};

}  // namespace morph::planar
