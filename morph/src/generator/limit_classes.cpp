// SPDX-License-Identifier: Apache-2.0
#include "generator/limit_classes.h"

#include <morph/union_find.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>
#include <utility>

namespace morph {
// Candidates are vertices whose rounded points fall in neighbouring cells of a grid much coarser
// than any rounding error; whether they are one point is decided exactly. Each pair of candidates
// is tested once, in any order: the classes are the connected parts of the pairs found to be one
// point, each represented by its smallest vertex (UnionFind), whatever the order. The points are
// found in parallel, and the cells sorted, so each occupied cell holding a vertex near its faces
// looks up its 13 neighbours after it among the sorted runs (bear.nc at 0.01: 778k vertices, 27
// hash look-ups each took a second; 13 each still took most of this step's 1 s).
std::vector<std::uint32_t> limit_classes(const VertexPlanes& vertices, ExecutionPolicy policy,
                                         std::vector<Eigen::Vector3d>* points) {
  constexpr double kCell = 1e-6;
  using Cell = std::array<std::int64_t, 3>;
  std::vector<std::pair<Cell, std::uint32_t>> cells;
  resize_faulted_in(cells, vertices.size(), policy);
  // Per vertex: its rounded point lies near a face of its cell. vertex_point() is within 1e-12 of
  // its size of the exact point, so two vertices of one exact point in different cells are both
  // within a millionth of that of the face between: only cells holding such a vertex look at
  // their neighbours.
  std::vector<char> near_face(vertices.size(), 0);
  std::vector<Eigen::Vector3d> own_points;
  std::vector<Eigen::Vector3d>& point = points ? *points : own_points;
  resize_faulted_in(point, vertices.size(), policy);
  for_each_index(policy, 0, vertices.size(), [&](std::size_t v) {
    const Eigen::Vector3d x = vertex_point(vertices[v][0], vertices[v][1], vertices[v][2]);
    point[v] = x;
    const double reach = 1e-9 * std::max(1.0, x.cwiseAbs().maxCoeff()) / kCell;
    Cell c{};
    for (int i = 0; i < 3; ++i) {
      const double at = x[i] / kCell, below = std::floor(at);
      c[i] = static_cast<std::int64_t>(below);
      if (at - below <= reach || below + 1.0 - at <= reach) near_face[v] = 1;
    }
    cells[v] = {c, static_cast<std::uint32_t>(v)};
  });
  sort_under(policy, cells.begin(), cells.end(), std::less<std::pair<Cell, std::uint32_t>>());

  // Each occupied cell's pairs, in parallel: the pairs found to be one point that join two parts
  // not yet joined by the cell's earlier pairs (a forest of them, with the same connected parts).
  std::vector<std::size_t> starts;  // of each cell's run in `cells`, and last the end
  for (std::size_t k = 0; k < cells.size(); ++k)
    if (k == 0 || cells[k].first != cells[k - 1].first) starts.push_back(k);
  starts.push_back(cells.size());
  const std::size_t runs = starts.size() - 1;
  // A cell's run in `cells`, by binary search over the runs (the few cells near a face look up
  // their neighbours; a hash table of every run was built by one thread).
  auto find_run = [&](const Cell& cell) -> std::optional<std::pair<std::size_t, std::size_t>> {
    const auto last = starts.end() - 1;
    const auto run = std::lower_bound(
        starts.begin(), last, cell, [&](std::size_t start, const Cell& c) { return cells[start].first < c; });
    if (run == last || cells[*run].first != cell) return std::nullopt;
    return std::pair{*run, *(run + 1)};
  };
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> joined(runs);
  for_each_index(policy, 0, runs, [&](std::size_t r) {
    const std::size_t k = starts[r], end = starts[r + 1];
    const Cell& c = cells[k].first;
    std::vector<std::pair<std::size_t, std::size_t>> others;  // the neighbour cells' ranges
    const bool near = std::any_of(cells.begin() + static_cast<std::ptrdiff_t>(k),
                                  cells.begin() + static_cast<std::ptrdiff_t>(end),
                                  [&](const auto& cell) { return near_face[cell.second] != 0; });
    for (std::int64_t dx = 0; near && dx <= 1; ++dx)
      for (std::int64_t dy = dx == 0 ? 0 : -1; dy <= 1; ++dy)
        for (std::int64_t dz = dx == 0 && dy == 0 ? 1 : -1; dz <= 1; ++dz) {
          if (const auto run = find_run({c[0] + dx, c[1] + dy, c[2] + dz})) others.push_back(*run);
        }
    if (end - k == 1 && others.empty()) return;
    std::vector<std::uint32_t> members;
    for (std::size_t i = k; i < end; ++i) members.push_back(cells[i].second);
    for (const auto& [from, to] : others)
      for (std::size_t j = from; j < to; ++j) members.push_back(cells[j].second);
    std::sort(members.begin(), members.end());
    UnionFind local(members.size());
    auto local_index = [&](std::uint32_t v) {
      return static_cast<std::uint32_t>(std::lower_bound(members.begin(), members.end(), v) -
                                        members.begin());
    };
    auto test = [&](std::uint32_t u, std::uint32_t v) {
      const std::uint32_t a = local_index(u), b = local_index(v);
      if (local.find(a) != local.find(b) && same_limit_point(vertices[u], vertices[v], point[u])) {
        local.unite(a, b);
        joined[r].emplace_back(u, v);
      }
    };
    for (std::size_t i = k; i < end; ++i)
      for (std::size_t j = i + 1; j < end; ++j) test(cells[i].second, cells[j].second);
    for (const auto& [from, to] : others)
      for (std::size_t i = k; i < end; ++i)
        for (std::size_t j = from; j < to; ++j) test(cells[i].second, cells[j].second);
  });
  UnionFind classes(vertices.size());
  for (const auto& pairs : joined)
    for (const auto& [u, v] : pairs) classes.unite(u, v);
  std::vector<std::uint32_t> root(vertices.size());
  for (std::uint32_t v = 0; v < vertices.size(); ++v) root[v] = classes.find(v);
  return root;
}

}  // namespace morph
