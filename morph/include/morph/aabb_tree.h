// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file aabb_tree.h
/// A static bounding-volume hierarchy over axis-aligned boxes: the spatial index that keeps
/// move-against-move and point-against-move work near-linear in the number of moves.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

namespace morph {

/// True when the closed boxes meet: AlignedBox3d::intersects(), one coordinate at a time with an
/// early out (the queries mostly miss on the first axis they test).
inline bool boxes_meet(const Eigen::AlignedBox3d& a, const Eigen::AlignedBox3d& b) {
  return a.min().x() <= b.max().x() && b.min().x() <= a.max().x() && a.min().y() <= b.max().y() &&
         b.min().y() <= a.max().y() && a.min().z() <= b.max().z() && b.min().z() <= a.max().z();
}

class AabbTree {
 public:
  AabbTree() = default;
  /// Builds over `boxes`; item i of every query is boxes[i]. Deterministic.
  explicit AabbTree(std::vector<Eigen::AlignedBox3d> boxes);

  std::size_t size() const { return boxes_.size(); }
  const Eigen::AlignedBox3d& box(std::size_t item) const { return boxes_[item]; }

  /// Calls visit(item) for every item whose box intersects `query` (closed boxes).
  template <class Visit>
  void for_each_overlapping(const Eigen::AlignedBox3d& query, Visit&& visit) const {
    for_each_overlapping_while(query, [&](std::uint32_t item) {
      visit(item);
      return true;
    });
  }

  /// As for_each_overlapping(), in the same order, until visit(item) returns false (a query
  /// decided by what it met first). Returns whether the walk ran to its end.
  template <class Visit>
  bool for_each_overlapping_while(const Eigen::AlignedBox3d& query, Visit&& visit) const {
    if (nodes_.empty()) return true;
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!boxes_meet(node.box, query)) continue;
      if (node.count > 0) {
        for (std::uint32_t i = 0; i < node.count; ++i) {
          const std::uint32_t item = order_[node.first + i];
          if (boxes_meet(boxes_[item], query) && !visit(item)) return false;
        }
      } else {
        stack[top++] = node.first;
        stack[top++] = node.first + 1;
      }
    }
    return true;
  }

  /// A node pair whose subtrees' overlapping item pairs for_each_overlapping_pair() walks.
  using PairWalk = std::array<std::uint32_t, 2>;

  /// The walk over every pair of items whose boxes intersect, cut into independent parts (at
  /// least `parts` where the tree allows): each unordered pair lies under exactly one of them, so
  /// the parts may be walked in parallel. One tree walked against itself meets each pair of
  /// overlapping nodes once, where a query per item meets it from both sides and from the root.
  std::vector<PairWalk> pair_walks(std::size_t parts) const;

  /// Calls visit(a, b), a < b, for every pair of distinct items under `walk` whose boxes
  /// intersect (closed boxes).
  template <class Visit>
  void for_each_overlapping_pair(const PairWalk& walk, Visit&& visit) const {
    std::vector<PairWalk> stack{walk};
    while (!stack.empty()) {
      const PairWalk w = stack.back();
      stack.pop_back();
      if (split(w, stack)) continue;
      const Node &a = nodes_[w[0]], &b = nodes_[w[1]];
      for (std::uint32_t i = 0; i < a.count; ++i)
        for (std::uint32_t j = w[0] == w[1] ? i + 1 : 0; j < b.count; ++j)
          visit_if_overlapping(a.first + i, b.first + j, visit);
    }
  }

  /// Best-first search for the item minimising `distance(item)`. The search prunes with a lower
  /// bound: the box's exterior distance when p is outside the box, and -max_depth inside it, so
  /// `distance` may be signed as long as it never goes below -max_depth (e.g. the tool radius
  /// for swept-volume distances; 0 for unsigned ones). `distance` may take the nearest value so
  /// far as a second argument, and then needs to be exact only below it (a value no less than it
  /// otherwise). Returns -1 if empty.
  template <class Distance>
  std::int64_t nearest(const Eigen::Vector3d& p, Distance&& distance, double* best_out,
                       double max_depth = 0.0) const {
    auto lower_bound = [&](const Eigen::AlignedBox3d& b) {
      const double outside = b.exteriorDistance(p);
      return outside > 0.0 ? outside : -max_depth;
    };
    double best = std::numeric_limits<double>::infinity();
    std::int64_t best_item = -1;
    if (!nodes_.empty()) {
      struct Entry {
        double bound;
        std::uint32_t node;
      };
      std::vector<Entry> heap;
      heap.push_back({lower_bound(nodes_[0].box), 0});
      auto cmp = [](const Entry& a, const Entry& b) { return a.bound > b.bound; };
      while (!heap.empty()) {
        std::pop_heap(heap.begin(), heap.end(), cmp);
        const Entry e = heap.back();
        heap.pop_back();
        if (e.bound >= best) break;
        const Node& node = nodes_[e.node];
        if (node.count > 0) {
          for (std::uint32_t i = 0; i < node.count; ++i) {
            const std::uint32_t item = order_[node.first + i];
            if (lower_bound(boxes_[item]) >= best) continue;
            double d = 0.0;
            if constexpr (std::is_invocable_v<Distance&, std::size_t, double>)
              d = distance(static_cast<std::size_t>(item), best);
            else
              d = distance(item);
            if (d < best) {
              best = d;
              best_item = item;
            }
          }
        } else {
          for (std::uint32_t c = 0; c < 2; ++c) {
            const double b = lower_bound(nodes_[node.first + c].box);
            if (b < best) {
              heap.push_back({b, node.first + c});
              std::push_heap(heap.begin(), heap.end(), cmp);
            }
          }
        }
      }
    }
    if (best_out) *best_out = best;
    return best_item;
  }

 private:
  // One step of the walk of `w`: appends its parts to `out` (none when its boxes are apart) and
  // returns true, or returns false when `w` is two leaves, or one leaf with itself, whose items
  // are compared directly.
  bool split(const PairWalk& w, std::vector<PairWalk>& out) const;

  // Items at positions p and q of order_, visited as (smaller, larger) when their boxes meet.
  template <class Visit>
  void visit_if_overlapping(std::uint32_t p, std::uint32_t q, Visit& visit) const {
    const std::uint32_t a = order_[p], b = order_[q];
    if (boxes_meet(boxes_[a], boxes_[b])) visit(std::min(a, b), std::max(a, b));
  }

  struct Node {
    Eigen::AlignedBox3d box;
    std::uint32_t first = 0;  ///< leaf: first index into order_; inner: index of left child
    std::uint32_t count = 0;  ///< leaf: item count; inner: 0
  };
  std::vector<Eigen::AlignedBox3d> boxes_;
  std::vector<std::uint32_t> order_;
  std::vector<Node> nodes_;
};

}  // namespace morph
