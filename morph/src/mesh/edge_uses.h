// SPDX-License-Identifier: Apache-2.0
#pragma once
// Private to morph: the directed uses of every undirected edge of a mesh, sorted so that the uses
// of one edge lie together; what the topology report, the generator's clean-up and its repair
// all count open and non-manifold edges from.
#include <morph/mesh.h>

#include <cstdint>
#include <vector>

namespace morph::detail {

/// One use of the undirected edge `key` = (min << 32) | max by corner `corner` of `triangle`
/// (the edge from that corner to the next); `forward` when the triangle runs min -> max.
struct EdgeUse {
  std::uint64_t key;
  std::uint32_t triangle;
  std::uint8_t corner;
  bool forward;

  // Left unset when sized: buffers of millions are filled in parallel right after, and zeroing
  // them first would fault every fresh page in on one thread.
  EdgeUse() noexcept {}
  EdgeUse(std::uint64_t key_, std::uint32_t triangle_, std::uint8_t corner_, bool forward_) noexcept
      : key(key_), triangle(triangle_), corner(corner_), forward(forward_) {}
};

inline std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  const std::uint64_t lo = a < b ? a : b, hi = a < b ? b : a;
  return (lo << 32) | hi;
}

/// All three uses of every triangle (a collapsed triangle's too, (a, a) included), sorted by
/// (key, triangle, corner) in parallel: a unique order, whatever the thread count.
std::vector<EdgeUse> sorted_edge_uses(const TriangleMesh& mesh);
/// The same into `uses`, whose storage is reused (the mesh's clean-up asks several times).
void sorted_edge_uses(const TriangleMesh& mesh, std::vector<EdgeUse>& uses);

/// Components of `triangle_count` triangles joined by the edges with two distinct ends in
/// `uses` (sorted by key): component_of_triangle numbers them by their smallest triangle.
/// Returns the count.
std::size_t components_of_uses(std::size_t triangle_count, const std::vector<EdgeUse>& uses,
                               std::vector<std::uint32_t>& component_of_triangle);

}  // namespace morph::detail
