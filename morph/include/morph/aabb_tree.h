// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file aabb_tree.h
/// A static bounding-volume hierarchy over axis-aligned boxes: the spatial index that keeps
/// move-against-move and point-against-move work near-linear in the number of moves.
#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

namespace morph {

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
    if (nodes_.empty()) return;
    std::uint32_t stack[64];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (!node.box.intersects(query)) continue;
      if (node.count > 0) {
        for (std::uint32_t i = 0; i < node.count; ++i) {
          const std::uint32_t item = order_[node.first + i];
          if (boxes_[item].intersects(query)) visit(item);
        }
      } else {
        stack[top++] = node.first;
        stack[top++] = node.first + 1;
      }
    }
  }

  /// Best-first search for the item minimising `distance(item)`. The search prunes with a lower
  /// bound: the box's exterior distance when p is outside the box, and -max_depth inside it, so
  /// `distance` may be signed as long as it never goes below -max_depth (e.g. the tool radius
  /// for swept-volume distances; 0 for unsigned ones). Returns -1 if empty.
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
            const double d = distance(item);
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
