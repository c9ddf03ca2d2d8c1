// SPDX-License-Identifier: Apache-2.0
#include <morph/aabb_tree.h>

#include <algorithm>
#include <numeric>

namespace morph {

namespace {
constexpr std::uint32_t kLeafSize = 4;
}

AabbTree::AabbTree(std::vector<Eigen::AlignedBox3d> boxes) : boxes_(std::move(boxes)) {
  if (boxes_.empty()) return;
  order_.resize(boxes_.size());
  std::iota(order_.begin(), order_.end(), 0u);
  std::vector<Eigen::Vector3d> centres(boxes_.size());
  for (std::size_t i = 0; i < boxes_.size(); ++i) centres[i] = boxes_[i].center();
  nodes_.reserve(2 * boxes_.size() / kLeafSize + 2);
  nodes_.push_back(Node{});
  // Iterative median split on the longest axis of the centre bounds; the depth stays below 64
  // because each split halves the item count.
  struct Task {
    std::uint32_t node, first, count;
  };
  std::vector<Task> tasks{{0, 0, static_cast<std::uint32_t>(boxes_.size())}};
  while (!tasks.empty()) {
    const Task task = tasks.back();
    tasks.pop_back();
    Eigen::AlignedBox3d box, centre_box;
    for (std::uint32_t i = task.first; i < task.first + task.count; ++i) {
      box.extend(boxes_[order_[i]]);
      centre_box.extend(centres[order_[i]]);
    }
    nodes_[task.node].box = box;
    if (task.count <= kLeafSize) {
      nodes_[task.node].first = task.first;
      nodes_[task.node].count = task.count;
      continue;
    }
    int axis = 0;
    centre_box.sizes().maxCoeff(&axis);
    const std::uint32_t half = task.count / 2;
    auto begin = order_.begin() + task.first;
    std::nth_element(begin, begin + half, begin + task.count, [&](std::uint32_t a, std::uint32_t b) {
      if (centres[a][axis] != centres[b][axis]) return centres[a][axis] < centres[b][axis];
      return a < b;
    });
    const auto left = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back(Node{});
    nodes_.push_back(Node{});
    nodes_[task.node].first = left;
    nodes_[task.node].count = 0;
    tasks.push_back({left, task.first, half});
    tasks.push_back({left + 1, task.first + half, task.count - half});
  }
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
