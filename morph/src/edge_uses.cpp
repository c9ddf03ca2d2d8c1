#include "edge_uses.h"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <tuple>

namespace morph::detail {

std::vector<EdgeUse> sorted_edge_uses(const TriangleMesh& mesh) {
  std::vector<EdgeUse> uses(3 * mesh.triangles.size());
  tbb::parallel_for(std::size_t{0}, mesh.triangles.size(), [&](std::size_t t) {
    const Triangle& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
      uses[3 * t + k] = {edge_key(a, b), static_cast<std::uint32_t>(t), static_cast<std::uint8_t>(k), a < b};
    }
  });
  tbb::parallel_sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return std::tie(x.key, x.triangle, x.corner) < std::tie(y.key, y.triangle, y.corner);
  });
  return uses;
}

}  // namespace morph::detail
