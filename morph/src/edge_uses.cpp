#include "edge_uses.h"

#include "huge_pages.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <atomic>
#include <tuple>

namespace morph::detail {

std::vector<EdgeUse> sorted_edge_uses(const TriangleMesh& mesh) {
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
  std::vector<EdgeUse> uses = large_vector<EdgeUse>(count);
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
  return uses;
}

}  // namespace morph::detail
