// SPDX-License-Identifier: Apache-2.0
#include "mesh/edge_uses.h"

#include "mesh/huge_pages.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <numeric>
#include <tuple>

namespace morph::detail {

std::vector<EdgeUse> sorted_edge_uses(const TriangleMesh& mesh) {
  std::vector<EdgeUse> uses;
  sorted_edge_uses(mesh, uses);
  return uses;
}

void sorted_edge_uses(const TriangleMesh& mesh, std::vector<EdgeUse>& uses) {
  // A counting sort on the edge's lower vertex, then each (small) bucket by (key, triangle,
  // corner): far faster than comparison sorting millions. The buckets fill in parallel, in
  // whatever order; sorting each by the whole (unique) triple makes the order unique again.
  const std::size_t count = 3 * mesh.triangles.size();
  const std::size_t triangles = mesh.triangles.size();
  const std::uint32_t top = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, triangles, 16384), std::uint32_t{0},
      [&](const tbb::blocked_range<std::size_t>& range, std::uint32_t highest) {
        for (std::size_t t = range.begin(); t != range.end(); ++t)
          highest = std::max({highest, mesh.triangles[t][0], mesh.triangles[t][1], mesh.triangles[t][2]});
        return highest;
      },
      [](std::uint32_t a, std::uint32_t b) { return std::max(a, b); });
  const std::size_t buckets = count == 0 ? 0 : static_cast<std::size_t>(top) + 1;
  std::vector<std::atomic<std::uint32_t>> fill(buckets);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buckets, 16384),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t v = range.begin(); v != range.end(); ++v)
                        fill[v].store(0, std::memory_order_relaxed);
                    });
  auto for_each_use = [&](auto&& f) {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, triangles, 16384),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t t = range.begin(); t != range.end(); ++t)
                          for (int k = 0; k < 3; ++k)
                            f(t, k, mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3]);
                      });
  };
  for_each_use([&](std::size_t, int, std::uint32_t a, std::uint32_t b) {
    fill[std::min(a, b)].fetch_add(1, std::memory_order_relaxed);
  });
  std::vector<std::uint32_t> start(buckets + 1, 0);
  for (std::size_t v = 0; v < buckets; ++v) {
    start[v + 1] = start[v] + fill[v].load(std::memory_order_relaxed);
    fill[v].store(start[v], std::memory_order_relaxed);
  }
  if (uses.capacity() < count) {
    uses.clear();
    reserve_large(uses, count);
  }
  uses.resize(count);
  for_each_use([&](std::size_t t, int k, std::uint32_t a, std::uint32_t b) {
    uses[fill[std::min(a, b)].fetch_add(1, std::memory_order_relaxed)] = {
        edge_key(a, b), static_cast<std::uint32_t>(t), static_cast<std::uint8_t>(k), a < b};
  });
  auto before = [](const EdgeUse& x, const EdgeUse& y) {
    return std::tie(x.key, x.triangle, x.corner) < std::tie(y.key, y.triangle, y.corner);
  };
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, buckets, 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t v = range.begin(); v != range.end(); ++v) {
                        const auto first = uses.begin() + start[v], last = uses.begin() + start[v + 1];
                        if (last - first > 32) {
                          std::sort(first, last, before);
                          continue;
                        }
                        // Insertion sort: most buckets are a few uses each.
                        for (auto i = first + (first != last); i < last; ++i) {
                          const EdgeUse use = *i;
                          auto j = i;
                          for (; j != first && before(use, *(j - 1)); --j) *j = *(j - 1);
                          *j = use;
                        }
                      }
                    });
}

std::size_t components_of_uses(std::size_t triangle_count, const std::vector<EdgeUse>& uses,
                               std::vector<std::uint32_t>& component_of_triangle) {
  // Union-find in which the smaller root wins, so a root is the smallest triangle of its set.
  std::vector<std::uint32_t> parent(triangle_count);
  std::iota(parent.begin(), parent.end(), std::uint32_t{0});
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (std::size_t i = 1; i < uses.size(); ++i) {
    const std::uint64_t key = uses[i].key;
    if (key != uses[i - 1].key || (key >> 32) == (key & 0xffffffffu)) continue;
    const std::uint32_t a = find(uses[i].triangle), b = find(uses[i - 1].triangle);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
  // Numbering roots in triangle order numbers components by their smallest triangle.
  constexpr std::uint32_t kUnset = ~std::uint32_t{0};
  std::vector<std::uint32_t> component_of_root(triangle_count, kUnset);
  component_of_triangle.assign(triangle_count, 0);
  std::uint32_t count = 0;
  for (std::uint32_t t = 0; t < triangle_count; ++t) {
    const std::uint32_t root = find(t);
    if (component_of_root[root] == kUnset) component_of_root[root] = count++;
    component_of_triangle[t] = component_of_root[root];
  }
  return count;
}

}  // namespace morph::detail
