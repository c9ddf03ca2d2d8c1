// SPDX-License-Identifier: Apache-2.0
#include <morph/aabb_tree.h>

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <map>
#include <numeric>

namespace morph {

namespace {

constexpr std::uint32_t kLeafSize = 4;
// Subtrees over at least this many items are built in parallel with their siblings.
constexpr std::uint32_t kParallelItems = 1u << 14;

// How many nodes the tree over `count` items has (a leaf holds at most kLeafSize, an inner node
// splits its items at half), for every count the splits of `count` reach.
std::uint32_t count_nodes(std::uint32_t count, std::map<std::uint32_t, std::uint32_t>& nodes_of) {
  const auto found = nodes_of.find(count);
  if (found != nodes_of.end()) return found->second;
  const std::uint32_t n =
      count <= kLeafSize ? 1
                         : 1 + count_nodes(count / 2, nodes_of) + count_nodes(count - count / 2, nodes_of);
  nodes_of.emplace(count, n);
  return n;
}

}  // namespace

// Median split on the longest axis of the centre bounds; the depth stays below 64 because each
// split halves the item count. Nodes are numbered as a depth-first walk that splits a node, numbers
// its two children next to each other, then goes down the right one first: each subtree's numbers
// follow from its item count alone, so large subtrees are built in parallel into the same layout.
AabbTree::AabbTree(std::vector<Eigen::AlignedBox3d> boxes) : boxes_(std::move(boxes)) {
  if (boxes_.empty()) return;
  order_.resize(boxes_.size());
  std::iota(order_.begin(), order_.end(), 0u);
  std::vector<Eigen::Vector3d> centres(boxes_.size());
  for (std::size_t i = 0; i < boxes_.size(); ++i) centres[i] = boxes_[i].center();
  std::map<std::uint32_t, std::uint32_t> nodes_of;
  nodes_.resize(count_nodes(static_cast<std::uint32_t>(boxes_.size()), nodes_of));
  // Node `node` over order_[first, first + count); its descendants numbered from `next`.
  auto build = [&](auto&& self, std::uint32_t node, std::uint32_t first, std::uint32_t count,
                   std::uint32_t next) -> void {
    Eigen::AlignedBox3d box, centre_box;
    for (std::uint32_t i = first; i < first + count; ++i) {
      box.extend(boxes_[order_[i]]);
      centre_box.extend(centres[order_[i]]);
    }
    nodes_[node].box = box;
    if (count <= kLeafSize) {
      nodes_[node].first = first;
      nodes_[node].count = count;
      return;
    }
    int axis = 0;
    centre_box.sizes().maxCoeff(&axis);
    const std::uint32_t half = count / 2;
    auto begin = order_.begin() + first;
    std::nth_element(begin, begin + half, begin + count, [&](std::uint32_t a, std::uint32_t b) {
      if (centres[a][axis] != centres[b][axis]) return centres[a][axis] < centres[b][axis];
      return a < b;
    });
    nodes_[node].first = next;
    nodes_[node].count = 0;
    const std::uint32_t right_next = next + 2;
    const std::uint32_t left_next = right_next + nodes_of.at(count - half) - 1;
    auto right = [&] { self(self, next + 1, first + half, count - half, right_next); };
    auto left = [&] { self(self, next, first, half, left_next); };
    if (count >= kParallelItems) {
      tbb::parallel_invoke(right, left);
    } else {
      right();
      left();
    }
  };
  build(build, 0, 0, static_cast<std::uint32_t>(boxes_.size()), 1);
}

bool AabbTree::split(const PairWalk& w, std::vector<PairWalk>& out) const {
  const Node &a = nodes_[w[0]], &b = nodes_[w[1]];
  if (w[0] == w[1]) {
    if (a.count > 0) return false;
    out.push_back({a.first, a.first});
    out.push_back({a.first + 1, a.first + 1});
    out.push_back({a.first, a.first + 1});
    return true;
  }
  if (!boxes_meet(a.box, b.box)) return true;  // nothing under it
  if (a.count > 0 && b.count > 0) return false;
  // Down the inner node, the larger one when both are.
  if (a.count > 0 || (b.count == 0 && b.box.volume() > a.box.volume())) {
    out.push_back({w[0], b.first});
    out.push_back({w[0], b.first + 1});
  } else {
    out.push_back({a.first, w[1]});
    out.push_back({a.first + 1, w[1]});
  }
  return true;
}

std::vector<AabbTree::PairWalk> AabbTree::pair_walks(std::size_t parts) const {
  std::vector<PairWalk> walks;
  if (nodes_.empty()) return walks;
  walks.push_back({0, 0});
  // Breadth first: each round splits every walk that can be split, as the walk itself would.
  for (bool any = true; any && walks.size() < parts;) {
    any = false;
    std::vector<PairWalk> next;
    for (const PairWalk& w : walks) {
      if (split(w, next))
        any = true;
      else
        next.push_back(w);
    }
    walks.swap(next);
  }
  return walks;
}

}  // namespace morph
