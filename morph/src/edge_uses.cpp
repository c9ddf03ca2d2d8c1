#include "edge_uses.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace morph::detail {

std::vector<EdgeUse> sorted_edge_uses(const TriangleMesh& mesh) {
  // A counting sort on the edge's lower vertex, then each (small) bucket by the higher one:
  // the uses enter their buckets in (triangle, corner) order and the buckets are sorted stably,
  // which gives the (key, triangle, corner) order, far faster than comparison sorting millions.
  const std::size_t count = 3 * mesh.triangles.size();
  std::uint32_t top = 0;
  for (const Triangle& tri : mesh.triangles) top = std::max({top, tri[0], tri[1], tri[2]});
  std::vector<std::uint32_t> start(count == 0 ? 1 : static_cast<std::size_t>(top) + 2, 0);
  for (const Triangle& tri : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++start[std::min(tri[k], tri[(k + 1) % 3]) + 1];
  for (std::size_t v = 1; v < start.size(); ++v) start[v] += start[v - 1];
  std::vector<EdgeUse> uses(count);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
        uses[fill[std::min(a, b)]++] = {edge_key(a, b), static_cast<std::uint32_t>(t),
                                        static_cast<std::uint8_t>(k), a < b};
      }
    }
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, start.size() - 1, 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t v = range.begin(); v != range.end(); ++v) {
                        const auto first = uses.begin() + start[v], last = uses.begin() + start[v + 1];
                        if (last - first > 32) {
                          std::stable_sort(first, last,
                                           [](const EdgeUse& x, const EdgeUse& y) { return x.key < y.key; });
                          continue;
                        }
                        // Insertion sort by key: stable, and most buckets are a few uses each.
                        for (auto i = first + (first != last); i < last; ++i) {
                          const EdgeUse use = *i;
                          auto j = i;
                          for (; j != first && (j - 1)->key > use.key; --j) *j = *(j - 1);
                          *j = use;
                        }
                      }
                    });
  return uses;
}

}  // namespace morph::detail
