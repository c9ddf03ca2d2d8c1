// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file tool_facet_groups.h
/// The tool's facets in groups of like normals, each with a bound of its planes' values: which of
/// a sweep's ~700 (at tolerance 1e-3, ~20,000) facet planes can reach a point or a small ball
/// without evaluating them all. A sweep places tool facet k at one end `at` of its segment
/// (a or b), giving the plane value n_k·(x - at) - o_k. For a group with unit mean normal m,
/// spread δ = max |n_k - m|, reference point r and e = max (n_k·r - o_k), every member's value
/// at a point x of the ball (c, ρ) is at most
///     N·ρ + m·w + δ·|w| + e,   w = c - at - r,   N = max |n_k|,
/// taken at both ends. So when that bound (plus a float slack far above the rounding of the
/// values) is below a threshold, no member's value reaches it, and a test "some value at least
/// t" may skip the group: the answer of every test that uses it is the one of the full loop.
/// It assumes the sweep's planes are SweepPolytopeBuilder::halfspaces()' tool facet planes
/// n_k·x <= o_k + n_k·at (tool_facet_groups_test checks the bound against them).
#include <morph/convex_polytope.h>

#include <Eigen/Core>
#include <algorithm>
#include <cstddef>
#include <vector>

namespace morph {

class ToolFacetGroups {
 public:
  /// Groups of the facets of `tool`, by a cube map of their normals (about 16 facets a group).
  explicit ToolFacetGroups(const ConvexPolytope& tool);

  /// Calls f(k) for every tool facet k whose plane, placed at `a` or at `b`, may have a value of
  /// at least `threshold` somewhere in the ball (centre, radius) (job units); other facets' values
  /// there are certainly below it, also as doubles compute them. Facets come group by group;
  /// f returns false to stop, and then so does this.
  template <class F>
  bool for_each_reaching(const Eigen::Vector3d& centre, double radius, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b, double threshold, F&& f) const {
    return for_each_reaching(
        centre, radius, a, b, threshold, [](std::size_t) { return true; }, f);
  }
  /// The same over the groups g with asked(g) only.
  template <class A, class F>
  bool for_each_reaching(const Eigen::Vector3d& centre, double radius, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b, double threshold, A&& asked, F&& f) const {
    const Eigen::Vector3d wa = centre - a, wb = centre - b;
    const double cut = threshold - slack(centre, radius, a, b) - max_norm_ * radius;
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      if (!asked(g)) continue;
      const Group& group = groups_[g];
      // m·u + δ|u| < cut at both ends, without a square root: cut - m·u > 0 and δ²|u|² below its square.
      const Eigen::Vector3d ua = wa - group.reference, ub = wb - group.reference;
      const double da = cut - group.excess - group.mean.dot(ua), db = cut - group.excess - group.mean.dot(ub);
      if (da > 0.0 && db > 0.0 && group.spread_squared * ua.squaredNorm() < da * da &&
          group.spread_squared * ub.squaredNorm() < db * db)
        continue;
      for (std::size_t i = group.begin; i < group.end; ++i)
        if (!f(members_[i])) return false;
    }
    return true;
  }

  std::size_t size() const { return groups_.size(); }
  /// The tool facets of group g.
  std::vector<int> members(std::size_t g) const {
    return {members_.begin() + static_cast<std::ptrdiff_t>(groups_[g].begin),
            members_.begin() + static_cast<std::ptrdiff_t>(groups_[g].end)};
  }

 private:
  struct Group {
    Eigen::Vector3d mean, reference;
    double spread_squared = 0.0, excess = 0.0;
    std::size_t begin = 0, end = 0;  ///< in members_
  };
  // Bounds the rounding of the plane values and of the bound itself (a thousand times over),
  // for normals of any length (the values scale with them).
  double slack(const Eigen::Vector3d& centre, double radius, const Eigen::Vector3d& a,
               const Eigen::Vector3d& b) const {
    return 1e-12 *
           (1.0 + std::max(1.0, max_norm_) * (centre.norm() + radius + a.norm() + b.norm()) + max_offset_);
  }

  std::vector<Group> groups_;
  std::vector<int> members_;
  double max_norm_ = 0.0, max_offset_ = 0.0;
};

}  // namespace morph
