// SPDX-License-Identifier: Apache-2.0
// Joining trimmed patches: both sides of a trimming curve carry vertices lying on the exact curve
// (placed by root finding), but each side samples it at its own grid edges. Splitting every
// boundary edge at the other side's vertices makes the two vertex sequences identical, as in a
// B-rep where adjacent faces share their edge's vertices; the small holes where three patches
// meet are closed around the exact corner point.
#include <Eigen/Dense>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include "generator/erode_seams.h"
#include "mesh/huge_pages.h"

namespace morph::detail {

namespace {

using Eigen::Vector3d;

struct CellKey {
  std::int64_t x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
  // Mixed so that the low bits, which pick the slot, depend on every bit of the cell: the plain
  // products clustered the cells of a seam (longer probes).
  std::size_t operator()(const CellKey& k) const {
    std::uint64_t h = static_cast<std::uint64_t>(k.x) * 0x9E3779B97F4A7C15ull ^
                      static_cast<std::uint64_t>(k.y) * 0xC2B2AE3D27D4EB4Full ^
                      static_cast<std::uint64_t>(k.z) * 0x165667B19E3779F9ull;
    h ^= h >> 32;
    h *= 0xD6E8FEB86659FD93ull;
    h ^= h >> 32;
    return static_cast<std::size_t>(h);
  }
};
CellKey cell_of(const Vector3d& p, double cell) {
  return {static_cast<std::int64_t>(std::floor(p.x() / cell)),
          static_cast<std::int64_t>(std::floor(p.y() / cell)),
          static_cast<std::int64_t>(std::floor(p.z() / cell))};
}

/// Points bucketed by grid cell, built once: the points of a cell lie together in increasing
/// index, and a flat hash table (linear probing) finds a cell's range. Far cheaper than a map of
/// vectors over hundreds of thousands of points.
class CellIndex {
 public:
  CellIndex(const std::vector<Vector3d>& points, const std::vector<std::uint32_t>& members, double cell)
      : cell_(cell), entries_(large_vector<Entry>(members.size())) {
    tbb::parallel_for(std::size_t{0}, members.size(), [&](std::size_t i) {
      entries_[i] = {cell_of(points[members[i]], cell), members[i]};
    });
    // (cell, point) is unique, so the order does not depend on how the sort is split up.
    tbb::parallel_sort(entries_.begin(), entries_.end(), [](const Entry& a, const Entry& b) {
      return std::tie(a.cell.x, a.cell.y, a.cell.z, a.point) <
             std::tie(b.cell.x, b.cell.y, b.cell.z, b.point);
    });
    std::size_t cells = 0;
    for (std::size_t i = 0; i < entries_.size(); ++i)
      cells += i == 0 || !(entries_[i].cell == entries_[i - 1].cell);
    std::size_t size = 16;
    while (size < 2 * cells) size *= 2;
    slots_.assign(size, Slot{});
    for (std::size_t begin = 0; begin < entries_.size();) {
      std::size_t end = begin + 1;
      while (end < entries_.size() && entries_[end].cell == entries_[begin].cell) ++end;
      std::size_t slot = CellHash()(entries_[begin].cell) & (size - 1);
      while (slots_[slot].end != 0) slot = (slot + 1) & (size - 1);
      slots_[slot] = {static_cast<std::uint32_t>(begin), static_cast<std::uint32_t>(end)};
      begin = end;
    }
  }

  double cell() const { return cell_; }

  /// Calls f(point) for the points in cell c, in increasing index.
  template <class F>
  void for_each_in(const CellKey& c, F&& f) const {
    if (slots_.empty()) return;
    for (std::size_t slot = CellHash()(c) & (slots_.size() - 1); slots_[slot].end != 0;
         slot = (slot + 1) & (slots_.size() - 1))
      if (entries_[slots_[slot].begin].cell == c) {
        for (std::uint32_t i = slots_[slot].begin; i < slots_[slot].end; ++i) f(entries_[i].point);
        return;
      }
  }

 private:
  struct Entry {
    CellKey cell;
    std::uint32_t point;
  };
  struct Slot {
    std::uint32_t begin = 0, end = 0;  // the cell's entries (its key: entries_[begin].cell); end 0: empty
  };
  double cell_;
  std::vector<Entry> entries_;
  std::vector<Slot> slots_;
};

/// Cells of a search index for points within `distance` of each other: far wider than the
/// distance, so that a search nearly always looks in one cell only (a cell per distance made
/// every search probe 27 cells of a table far larger than the caches).
constexpr double kCellsPerSearch = 64.0;

/// Calls f(point) for the points of `index` in the cells that the box of half-width `reach`
/// about p overlaps.
template <class F>
void for_each_in_reach(const CellIndex& index, const Vector3d& p, double reach, F&& f) {
  const CellKey lo = cell_of(Vector3d(p.array() - reach), index.cell()),
                hi = cell_of(Vector3d(p.array() + reach), index.cell());
  for (std::int64_t x = lo.x; x <= hi.x; ++x)
    for (std::int64_t y = lo.y; y <= hi.y; ++y)
      for (std::int64_t z = lo.z; z <= hi.z; ++z) index.for_each_in({x, y, z}, f);
}

/// The first point of `index` within `distance` of p that is `present` (already entered, in the
/// order the caller enters points) and that `accept`s, in the order of a search of the 27 cells
/// of edge `distance` around p (x, then y, then z offset from -1 to 1), each cell in increasing
/// index: the first point a grid of such cells filled in increasing index would give. `none` if
/// there is none.
template <class Present, class Accept>
std::uint32_t find_near(const CellIndex& index, const std::vector<Vector3d>& points, const Vector3d& p,
                        double distance, std::uint32_t none, Present&& present, Accept&& accept) {
  const CellKey c = cell_of(p, distance);
  // (search order of its cell of edge `distance`, point)
  std::vector<std::pair<std::int64_t, std::uint32_t>> candidates;
  for_each_in_reach(index, p, 1.001 * distance, [&](std::uint32_t u) {
    if (!present(u) || !((points[u] - p).norm() <= distance)) return;
    const CellKey cu = cell_of(points[u], distance);
    candidates.push_back({((cu.x - c.x + 1) * 3 + (cu.y - c.y + 1)) * 3 + (cu.z - c.z + 1), u});
  });
  std::sort(candidates.begin(), candidates.end());
  for (const auto& [order, u] : candidates)
    if (accept(u)) return u;
  return none;
}

/// For each of `members` (the points `index` holds), whether another of them lies within
/// `distance` of it: a necessary condition of find_near finding one, checked in parallel.
std::vector<std::uint8_t> has_near(const CellIndex& index, const std::vector<Vector3d>& points,
                                   const std::vector<std::uint32_t>& members, double distance) {
  std::vector<std::uint8_t> result(members.size(), 0);
  // A little wider than the ball, so that no rounding of the distance test can reach past it.
  const double reach = 1.001 * distance;
  tbb::parallel_for(std::size_t{0}, members.size(), [&](std::size_t i) {
    const std::uint32_t v = members[i];
    const Vector3d& p = points[v];
    bool found = false;
    for_each_in_reach(index, p, reach,
                      [&](std::uint32_t u) { found = found || (u != v && (points[u] - p).norm() <= reach); });
    result[i] = found;
  });
  return result;
}

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

/// Merges vertices closer than `distance` into the first of them, drops collapsed triangles and
/// unreferenced vertices. Returns the number of merged vertices.
std::size_t weld(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of, double distance) {
  std::vector<std::uint32_t> target = large_vector<std::uint32_t>(mesh.vertices.size());
  std::vector<bool> on_border(mesh.vertices.size(), false);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (patch_of[t].border & (1u << k))
        on_border[mesh.triangles[t][k]] = on_border[mesh.triangles[t][(k + 1) % 3]] = true;
  // Interior vertices of a patch are never shared.
  std::vector<std::uint32_t> border_vertices;
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v)
    if (on_border[v]) border_vertices.push_back(v);
  const CellIndex index(mesh.vertices, border_vertices, kCellsPerSearch * distance);
  std::size_t merged = 0;
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) target[v] = v;
  // In increasing index, each vertex merges into the first earlier one kept; most have no other
  // vertex near at all, which the parallel check rules out first.
  const std::vector<std::uint8_t> near = has_near(index, mesh.vertices, border_vertices, distance);
  for (std::size_t i = 0; i < border_vertices.size(); ++i) {
    if (!near[i]) continue;
    const std::uint32_t v = border_vertices[i];
    const std::uint32_t found = find_near(
        index, mesh.vertices, mesh.vertices[v], distance, v,
        [&](std::uint32_t u) { return u < v && target[u] == u; }, [](std::uint32_t) { return true; });
    target[v] = found;
    merged += found != v;
  }
  // Compact: the triangles in place (each moves only down), the vertices in first-use order.
  std::vector<std::uint32_t> new_index = large_vector<std::uint32_t>(mesh.vertices.size(), UINT32_MAX);
  std::vector<Vector3d> vertices;
  reserve_large(vertices, mesh.vertices.size());
  std::vector<std::uint32_t> collapsed_patches;
  keep_triangles(mesh, patch_of, [&](std::size_t t, Triangle& tri) {
    for (std::uint32_t& v : tri) v = target[v];
    if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
      collapsed_patches.push_back(patch_of[t].patch);
      return false;
    }
    for (int k = 0; k < 3; ++k) {
      std::uint32_t& n = new_index[tri[k]];
      if (n == UINT32_MAX) {
        n = static_cast<std::uint32_t>(vertices.size());
        vertices.push_back(mesh.vertices[tri[k]]);
      }
      tri[k] = n;
    }
    return true;
  });
  mesh.vertices = std::move(vertices);
  // A collapsed triangle (a patch's degenerate corner, e.g. a stock triangle's apex) may have
  // paired an edge of its neighbour, which therefore carries no border bit although it is now
  // open: recompute the bits of the patches that lost triangles.
  std::sort(collapsed_patches.begin(), collapsed_patches.end());
  collapsed_patches.erase(std::unique(collapsed_patches.begin(), collapsed_patches.end()),
                          collapsed_patches.end());
  if (!collapsed_patches.empty()) {
    auto affected = [&](std::uint32_t patch) {
      return std::binary_search(collapsed_patches.begin(), collapsed_patches.end(), patch);
    };
    std::vector<std::array<std::uint32_t, 3>> keys;  // (patch, from, to)
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
      if (affected(patch_of[t].patch))
        for (int k = 0; k < 3; ++k)
          keys.push_back({patch_of[t].patch, mesh.triangles[t][k], mesh.triangles[t][(k + 1) % 3]});
    tbb::parallel_sort(keys.begin(), keys.end());
    tbb::parallel_for(std::size_t{0}, mesh.triangles.size(), [&](std::size_t t) {
      if (!affected(patch_of[t].patch)) return;
      const Triangle& tri = mesh.triangles[t];
      for (int k = 0; k < 3; ++k) {
        const std::array<std::uint32_t, 3> reverse{patch_of[t].patch, tri[(k + 1) % 3], tri[k]};
        if (!std::binary_search(keys.begin(), keys.end(), reverse)) patch_of[t].border |= 1u << k;
      }
    });
  }
  return merged;
}

/// Directed edges on patch borders (interior edges of a patch are always paired within it).
struct HalfEdges {
  std::vector<std::uint64_t> sorted;  // edge_key(from, to), once per use
  HalfEdges(const TriangleMesh& mesh, const std::vector<TriangleOrigin>& origin) {
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      if (!origin[i].border) continue;
      const Triangle& t = mesh.triangles[i];
      for (int k = 0; k < 3; ++k)
        if (origin[i].border & (1u << k)) sorted.push_back(edge_key(t[k], t[(k + 1) % 3]));
    }
    tbb::parallel_sort(sorted.begin(), sorted.end());
  }
  /// Only the uses `boundary` needs for the border edges of the triangles flagged in
  /// `may_be_open` (see open_edges; empty: all): those joining two of their ends.
  HalfEdges(const TriangleMesh& mesh, const std::vector<TriangleOrigin>& origin,
            const std::vector<std::uint8_t>& may_be_open) {
    if (may_be_open.empty()) {
      *this = HalfEdges(mesh, origin);
      return;
    }
    std::vector<std::uint8_t> end(mesh.vertices.size(), 0);
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      if (!origin[i].border || (i < may_be_open.size() && !may_be_open[i])) continue;
      const Triangle& t = mesh.triangles[i];
      for (int k = 0; k < 3; ++k)
        if (origin[i].border & (1u << k)) end[t[k]] = end[t[(k + 1) % 3]] = 1;
    }
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
      if (!origin[i].border) continue;
      const Triangle& t = mesh.triangles[i];
      for (int k = 0; k < 3; ++k)
        if ((origin[i].border & (1u << k)) && end[t[k]] && end[t[(k + 1) % 3]])
          sorted.push_back(edge_key(t[k], t[(k + 1) % 3]));
    }
    tbb::parallel_sort(sorted.begin(), sorted.end());
  }
  /// Used once as a->b and never as b->a.
  bool boundary(std::uint32_t a, std::uint32_t b) const {
    const auto [first, last] = std::equal_range(sorted.begin(), sorted.end(), edge_key(a, b));
    return last - first == 1 && !std::binary_search(sorted.begin(), sorted.end(), edge_key(b, a));
  }
};

/// The open border edges of each triangle (bit k: edge k -> k+1 is `half.boundary`), found in
/// parallel. Triangles flagged 0 in `may_be_open` (if it is given; triangles beyond its end are
/// looked at) are known to have none.
std::vector<std::uint8_t> open_edges(const TriangleMesh& mesh, const std::vector<TriangleOrigin>& origin,
                                     const HalfEdges& half, const std::vector<std::uint8_t>& may_be_open) {
  std::vector<std::uint8_t> open(mesh.triangles.size(), 0);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mesh.triangles.size(), 4096),
                    [&](const tbb::blocked_range<std::size_t>& range) {
                      for (std::size_t t = range.begin(); t != range.end(); ++t) {
                        if (!origin[t].border || (t < may_be_open.size() && !may_be_open[t])) continue;
                        const Triangle& tri = mesh.triangles[t];
                        for (int k = 0; k < 3; ++k)
                          if ((origin[t].border & (1u << k)) && half.boundary(tri[k], tri[(k + 1) % 3]))
                            open[t] |= static_cast<std::uint8_t>(1u << k);
                      }
                    });
  return open;
}

/// Merges boundary vertices of different patches closer than `distance` (points of the same
/// curve sampled by both sides at nearly the same place, typically near corners) so that no
/// sliver edges are left for the split pass.
std::size_t snap_boundary(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of, double distance,
                          double on_surface, const SurfaceFunction& surface) {
  const HalfEdges half(mesh, patch_of);
  // Per vertex, the patches whose open border edges it ends (empty: none).
  std::vector<std::vector<std::uint32_t>> patches_of_vertex(mesh.vertices.size());
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      if (!(patch_of[t].border & (1u << k))) continue;
      const std::uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      if (!half.boundary(a, b)) continue;
      for (std::uint32_t v : {a, b}) {
        auto& list = patches_of_vertex[v];
        if (std::find(list.begin(), list.end(), patch_of[t].patch) == list.end())
          list.push_back(patch_of[t].patch);
      }
    }
  std::vector<std::uint32_t> boundary;
  for (std::uint32_t v = 0; v < patches_of_vertex.size(); ++v)
    if (!patches_of_vertex[v].empty()) boundary.push_back(v);
  std::vector<std::uint32_t> target(mesh.vertices.size());
  for (std::uint32_t v = 0; v < target.size(); ++v) target[v] = v;
  const CellIndex index(mesh.vertices, boundary, kCellsPerSearch * distance);
  std::size_t merged = 0;
  auto disjoint = [&](std::uint32_t a, std::uint32_t b) {
    for (std::uint32_t p : patches_of_vertex[a])
      if (std::find(patches_of_vertex[b].begin(), patches_of_vertex[b].end(), p) !=
          patches_of_vertex[b].end())
        return false;
    return true;
  };
  // Two such points lie on each other's surfaces; near a corner where two trimming curves meet
  // at an angle, a point of one curve close to a point of the other does not, and merging the
  // two would fold the faces between them.
  auto on_surfaces_of = [&](std::uint32_t a, std::uint32_t b) {
    for (std::uint32_t q : patches_of_vertex[b])
      if (std::abs(surface(q, mesh.vertices[a])) > on_surface) return false;
    return true;
  };
  const std::vector<std::uint8_t> near = has_near(index, mesh.vertices, boundary, distance);
  // In increasing index, each vertex merges into the first earlier one kept that qualifies.
  for (std::size_t i = 0; i < boundary.size(); ++i) {
    if (!near[i]) continue;
    const std::uint32_t v = boundary[i];
    const std::uint32_t found = find_near(
        index, mesh.vertices, mesh.vertices[v], distance, v,
        [&](std::uint32_t u) { return u < v && target[u] == u; },
        [&](std::uint32_t u) { return disjoint(u, v) && on_surfaces_of(u, v) && on_surfaces_of(v, u); });
    if (found != v) {
      target[v] = found;
      auto& list = patches_of_vertex[found];
      for (std::uint32_t q : patches_of_vertex[v])
        if (std::find(list.begin(), list.end(), q) == list.end()) list.push_back(q);
      ++merged;
    }
  }
  if (merged == 0) return 0;
  keep_triangles(mesh, patch_of, [&](std::size_t, Triangle& tri) {
    for (std::uint32_t& v : tri) v = target[v];
    return tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2];
  });
  return merged;
}

/// One pass of splitting boundary edges at other patches' boundary vertices. Returns the number
/// of vertices inserted. `may_be_open` (see open_edges; empty: every triangle) is replaced by
/// the flags of the triangles that may still have an open edge: those made from a triangle with
/// one (an edge closed before stays closed, as only open edges are split and the rest only
/// gain uses).
std::size_t split_pass(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of, const SeamOptions& options,
                       const SurfaceFunction& surface, std::vector<std::uint8_t>& may_be_open) {
  const HalfEdges half(mesh, patch_of, may_be_open);
  std::vector<std::pair<std::uint32_t, int>> edges;  // (triangle, local edge)
  const std::vector<std::uint8_t> open = open_edges(mesh, patch_of, half, may_be_open);
  may_be_open = open;
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      if (open[t] & (1u << k)) edges.push_back({t, k});
  if (edges.empty()) return 0;
  // Per end of an open edge (the boundary vertices, sorted): the sum of its edges' directions,
  // in the edges' order, and the patches of those edges.
  std::vector<std::uint64_t> ends;  // (vertex << 32) | edge
  ends.reserve(2 * edges.size());
  for (std::uint32_t e = 0; e < edges.size(); ++e) {
    const auto [t, k] = edges[e];
    ends.push_back((std::uint64_t{mesh.triangles[t][k]} << 32) | e);
    ends.push_back((std::uint64_t{mesh.triangles[t][(k + 1) % 3]} << 32) | e);
  }
  std::sort(ends.begin(), ends.end());
  std::vector<std::uint32_t> boundary_vertices;
  std::vector<Vector3d> tangents;
  std::vector<std::uint32_t> patches_begin{0}, patch_list;
  for (std::size_t i = 0; i < ends.size();) {
    const std::uint32_t v = static_cast<std::uint32_t>(ends[i] >> 32);
    Vector3d tangent = Vector3d::Zero();
    const std::size_t first_patch = patch_list.size();
    for (; i < ends.size() && static_cast<std::uint32_t>(ends[i] >> 32) == v; ++i) {
      const auto [t, k] = edges[static_cast<std::uint32_t>(ends[i])];
      const std::uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      tangent += (mesh.vertices[b] - mesh.vertices[a]).normalized();
      if (std::find(patch_list.begin() + first_patch, patch_list.end(), patch_of[t].patch) ==
          patch_list.end())
        patch_list.push_back(patch_of[t].patch);
    }
    boundary_vertices.push_back(v);
    tangents.push_back(tangent);
    patches_begin.push_back(static_cast<std::uint32_t>(patch_list.size()));
  }
  struct BoundaryVertex {
    const Vector3d& tangent;
    const std::uint32_t *patches_first, *patches_last;
    bool has_patch(std::uint32_t patch) const {
      return std::find(patches_first, patches_last, patch) != patches_last;
    }
  };
  auto boundary_vertex = [&](std::uint32_t w) {
    const std::size_t i = static_cast<std::size_t>(
        std::lower_bound(boundary_vertices.begin(), boundary_vertices.end(), w) - boundary_vertices.begin());
    return BoundaryVertex{tangents[i], patch_list.data() + patches_begin[i],
                          patch_list.data() + patches_begin[i + 1]};
  };
  const double cell = std::max(options.cell, 4.0 * options.match_distance);
  const CellIndex index(mesh.vertices, boundary_vertices, cell);

  // Candidate (vertex, edge) matches; a vertex goes into at most one edge of each other patch
  // (the nearest), so that near corners it is not inserted into two consecutive edges.
  struct Match {
    std::uint32_t w, patch;
    double distance, lambda;
    std::uint32_t t;
    int k;
  };
  // Found in parallel, edge by edge, and gathered in the edges' order.
  constexpr std::size_t kEdgesPerChunk = 512;
  std::vector<std::vector<Match>> chunk_matches((edges.size() + kEdgesPerChunk - 1) / kEdgesPerChunk);
  auto match_edge = [&](std::uint32_t t, int k, std::vector<Match>& matches,
                        std::vector<std::uint32_t>& near) {
    const std::uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
    const Vector3d& pa = mesh.vertices[a];
    const Vector3d& pb = mesh.vertices[b];
    const Vector3d ab = pb - pa;
    const double len2 = ab.squaredNorm();
    if (len2 <= 0.0) return;
    // The cells near the edge, piece by piece: a long edge (a big flat stock triangle's side)
    // has a bounding box of far too many cells, but only the cells along it can hold matches.
    near.clear();
    const double length = std::sqrt(len2);
    const int pieces = static_cast<int>(std::min(1e6, std::ceil(length / cell)));
    for (int piece = 0; piece < pieces; ++piece) {
      const Vector3d p0 = pa + (static_cast<double>(piece) / pieces) * ab;
      const Vector3d p1 = pa + (static_cast<double>(piece + 1) / pieces) * ab;
      Eigen::AlignedBox3d box(p0.cwiseMin(p1), p0.cwiseMax(p1));
      box.min().array() -= options.match_distance;
      box.max().array() += options.match_distance;
      const CellKey lo = cell_of(box.min(), cell), hi = cell_of(box.max(), cell);
      for (std::int64_t x = lo.x; x <= hi.x; ++x)
        for (std::int64_t y = lo.y; y <= hi.y; ++y)
          for (std::int64_t z = lo.z; z <= hi.z; ++z) {
            index.for_each_in({x, y, z}, [&](std::uint32_t w) { near.push_back(w); });
          }
    }
    std::sort(near.begin(), near.end());
    near.erase(std::unique(near.begin(), near.end()), near.end());
    for (std::uint32_t w : near) {
      if (w == a || w == b) continue;
      const BoundaryVertex bv = boundary_vertex(w);
      if (bv.has_patch(patch_of[t].patch)) continue;
      const Vector3d& pw = mesh.vertices[w];
      const double lambda = (pw - pa).dot(ab) / len2;
      if (!(lambda > 1e-9 && lambda < 1.0 - 1e-9)) continue;
      const double distance = (pw - (pa + lambda * ab)).norm();
      // A chord of length c of a curve bending no tighter than c/2 stays within c/4 of it.
      if (distance > options.match_distance || distance > 0.25 * std::sqrt(len2)) continue;
      // The other side runs the curve the opposite way.
      if (bv.tangent.dot(ab) >= 0.0) continue;
      // And lies on this side's surface: a vertex of another curve meeting this one at a corner
      // is near the chord without being on the curve.
      if (std::abs(surface(patch_of[t].patch, pw)) > 1e3 * options.weld_distance) continue;
      matches.push_back({w, patch_of[t].patch, distance, lambda, t, k});
    }
  };
  tbb::parallel_for(std::size_t{0}, chunk_matches.size(), [&](std::size_t chunk) {
    std::vector<std::uint32_t> near;
    const std::size_t end = std::min(edges.size(), (chunk + 1) * kEdgesPerChunk);
    for (std::size_t e = chunk * kEdgesPerChunk; e < end; ++e)
      match_edge(edges[e].first, edges[e].second, chunk_matches[chunk], near);
  });
  std::vector<Match> matches;
  for (const std::vector<Match>& chunk : chunk_matches)
    matches.insert(matches.end(), chunk.begin(), chunk.end());
  std::sort(matches.begin(), matches.end(), [](const Match& x, const Match& y) {
    if (x.w != y.w) return x.w < y.w;
    if (x.patch != y.patch) return x.patch < y.patch;
    if (x.distance != y.distance) return x.distance < y.distance;
    return x.t < y.t;
  });
  std::unordered_map<std::uint64_t, std::vector<std::pair<double, std::uint32_t>>>
      splits;  // (t,k) -> (lambda, w)
  std::size_t inserted = 0;
  for (std::size_t i = 0; i < matches.size(); ++i) {
    if (i > 0 && matches[i].w == matches[i - 1].w && matches[i].patch == matches[i - 1].patch) continue;
    splits[edge_key(matches[i].t, static_cast<std::uint32_t>(matches[i].k))].push_back(
        {matches[i].lambda, matches[i].w});
    ++inserted;
  }
  for (auto& [key, list] : splits) std::sort(list.begin(), list.end());
  if (splits.empty()) return 0;

  // The triangles that replace the split ones, in order (the others move in place, below).
  std::vector<Triangle> triangles;
  std::vector<FaceTag> tags;
  std::vector<TriangleOrigin> patches;
  std::vector<std::uint8_t> patches_may_be_open;
  // The triangles with a split edge, in order.
  std::vector<std::uint32_t> split_triangles;
  split_triangles.reserve(splits.size());
  for (const auto& [key, list] : splits) split_triangles.push_back(static_cast<std::uint32_t>(key >> 32));
  std::sort(split_triangles.begin(), split_triangles.end());
  split_triangles.erase(std::unique(split_triangles.begin(), split_triangles.end()), split_triangles.end());
  std::vector<std::uint32_t> kept, polygon;  // scratch of split_triangle
  std::vector<int> from_edge;
  auto split_triangle = [&](std::uint32_t t) {
    const Triangle tri = mesh.triangles[t];
    const std::vector<std::pair<double, std::uint32_t>>* on_edge[3] = {nullptr, nullptr, nullptr};
    int split_edges = 0;
    for (int k = 0; k < 3; ++k) {
      if (!(open[t] & (1u << k))) continue;  // only open edges are split
      auto it = splits.find(edge_key(t, static_cast<std::uint32_t>(k)));
      if (it != splits.end()) {
        on_edge[k] = &it->second;
        ++split_edges;
      }
    }
    // New triangles keep border bits only on edges lying on the original triangle's edges.
    const std::uint8_t bits = patch_of[t].border;
    auto bit = [&](int original_edge, int new_edge) {
      return static_cast<std::uint8_t>(((bits >> original_edge) & 1u) << new_edge);
    };
    auto push = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint8_t border) {
      triangles.push_back({a, b, c});
      tags.push_back(mesh.tags[t]);
      patches.push_back({patch_of[t].patch, border});
      patches_may_be_open.push_back(open[t] != 0);
    };
    if (split_edges == 0) {
      triangles.push_back(tri);
      tags.push_back(mesh.tags[t]);
      patches.push_back(patch_of[t]);
      patches_may_be_open.push_back(open[t] != 0);
      return;
    }
    const Vector3d normal =
        (mesh.vertices[tri[1]] - mesh.vertices[tri[0]]).cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]]);
    auto keeps_orientation = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      return (mesh.vertices[b] - mesh.vertices[a]).cross(mesh.vertices[c] - mesh.vertices[a]).dot(normal) >
             0.0;
    };
    if (split_edges == 1) {
      const int k = on_edge[0] ? 0 : on_edge[1] ? 1 : 2;
      const std::uint32_t p0 = tri[k], p1 = tri[(k + 1) % 3], o = tri[(k + 2) % 3];
      // Drop insertions that would fold the fan (a vertex off the chord on the wrong side).
      kept.clear();
      std::uint32_t previous = p0;
      const auto& list = *on_edge[k];
      for (std::size_t i = 0; i < list.size(); ++i) {
        const std::uint32_t w = list[i].second;
        const std::uint32_t following = i + 1 < list.size() ? list[i + 1].second : p1;
        if (keeps_orientation(o, previous, w) && keeps_orientation(o, w, following) &&
            keeps_orientation(o, w, p1)) {
          kept.push_back(w);
          previous = w;
        }
      }
      if (kept.empty()) {
        push(tri[0], tri[1], tri[2], bits);
        return;
      }
      // (p0, p1, o) has edges k: p0->p1, k+1: p1->o, k+2: o->p0.
      previous = p0;
      for (const std::uint32_t w : kept) {
        push(o, previous, w, static_cast<std::uint8_t>(2u | (previous == p0 ? bit((k + 2) % 3, 0) : 0u)));
        previous = w;
      }
      push(o, previous, p1, static_cast<std::uint8_t>(2u | bit((k + 1) % 3, 2)));
      return;
    }
    // Several edges split: fan from the centroid.
    polygon.clear();
    from_edge.clear();  // original edge of polygon edge i -> i+1
    for (int k = 0; k < 3; ++k) {
      polygon.push_back(tri[k]);
      from_edge.push_back(k);
      if (on_edge[k])
        for (const auto& [lambda, w] : *on_edge[k]) {
          polygon.push_back(w);
          from_edge.push_back(k);
        }
    }
    const std::uint32_t centre = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back((mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0);
    for (std::size_t i = 0; i < polygon.size(); ++i)
      push(centre, polygon[i], polygon[(i + 1) % polygon.size()], bit(from_edge[i], 1));
  };
  // Where each split triangle's replacements start in `triangles`.
  std::vector<std::size_t> replaced_from;
  replaced_from.reserve(split_triangles.size() + 1);
  for (const std::uint32_t t : split_triangles) {
    replaced_from.push_back(triangles.size());
    split_triangle(t);
  }
  replaced_from.push_back(triangles.size());
  // The mesh grows in place from its end: every triangle moves up by the replacements before
  // it, never onto one not yet moved (no fresh arrays of the mesh's size to fault in).
  const std::size_t count = mesh.triangles.size();
  const std::size_t total = count - split_triangles.size() + triangles.size();
  mesh.triangles.resize(total);
  mesh.tags.resize(total);
  patch_of.resize(total);
  may_be_open.assign(total, 0);
  std::size_t end = count, to = total;  // the unmoved run ends at `end`, goes to end at `to`
  for (std::size_t i = split_triangles.size(); i-- > 0;) {
    const std::size_t t = split_triangles[i];
    const std::size_t run = end - (t + 1);
    std::move_backward(mesh.triangles.begin() + t + 1, mesh.triangles.begin() + end,
                       mesh.triangles.begin() + to);
    std::move_backward(mesh.tags.begin() + t + 1, mesh.tags.begin() + end, mesh.tags.begin() + to);
    std::move_backward(patch_of.begin() + t + 1, patch_of.begin() + end, patch_of.begin() + to);
    for (std::size_t k = 0; k < run; ++k) may_be_open[to - run + k] = open[t + 1 + k] != 0;
    to -= run;
    const std::size_t first = replaced_from[i], last = replaced_from[i + 1];
    to -= last - first;
    std::copy(triangles.begin() + first, triangles.begin() + last, mesh.triangles.begin() + to);
    std::copy(tags.begin() + first, tags.begin() + last, mesh.tags.begin() + to);
    std::copy(patches.begin() + first, patches.begin() + last, patch_of.begin() + to);
    std::copy(patches_may_be_open.begin() + first, patches_may_be_open.begin() + last,
              may_be_open.begin() + to);
    end = t;
  }
  for (std::size_t k = 0; k < end; ++k) may_be_open[k] = open[k] != 0;
  return inserted;
}

/// Point nearest to `start` on all the given surfaces (Levenberg-Marquardt on their functions).
Vector3d corner_point(const std::vector<std::uint32_t>& patches, const SurfaceFunction& surface,
                      const Vector3d& start, double reach) {
  Vector3d x = start;
  const int m = static_cast<int>(patches.size());
  Eigen::VectorXd r(m);
  Eigen::MatrixXd J(m, 3);
  for (int it = 0; it < 30; ++it) {
    for (int i = 0; i < m; ++i) {
      r[i] = surface(patches[i], x);
      const double h = 1e-7;
      for (int c = 0; c < 3; ++c) {
        Vector3d e = Vector3d::Zero();
        e[c] = h;
        J(i, c) = (surface(patches[i], x + e) - surface(patches[i], x - e)) / (2 * h);
      }
    }
    if (r.cwiseAbs().maxCoeff() < 1e-10) break;
    const Eigen::Matrix3d A = J.transpose() * J + 1e-9 * Eigen::Matrix3d::Identity();
    const Vector3d step = A.ldlt().solve(J.transpose() * r);
    x -= step;
    if (step.norm() < 1e-13) break;
  }
  for (int i = 0; i < m; ++i)
    if (std::abs(surface(patches[i], x)) > 1e-7) return start;
  if ((x - start).norm() > reach) return start;
  return x;
}

/// How a hole is closed, decided from its loop alone (the loop's vertices, its triangles'
/// patches, the exact surfaces and field), so that holes can be planned in parallel.
struct FillPlan {
  enum class Kind { kNone, kVertexFan, kRinged, kCornerFan } kind = Kind::kNone;
  std::size_t centre = 0;                    // kVertexFan: the loop vertex fanned from
  std::vector<std::vector<Vector3d>> rings;  // kRinged: rings[k][i], 0 < k < levels
  Vector3d corner = Vector3d::Zero();        // kRinged, kCornerFan
};

/// A hole to close: its loop, the triangle of each loop edge, the patches of those triangles,
/// and where the loop lies.
struct Hole {
  std::vector<std::uint32_t> loop, loop_triangles, patches;
  std::size_t best = 0;  // the loop vertex nearest to lying on every patch's surface
  double best_residual = 0.0;
  Eigen::AlignedBox3d box;
  Vector3d centroid;
};

FillPlan plan_fill(const TriangleMesh& mesh, const SeamOptions& options, const SurfaceFunction& surface,
                   const FieldFunction& field, const Hole& hole) {
  constexpr std::size_t kMaxCornerPatches = 6;  // at most 20 triples
  const std::vector<std::uint32_t>& loop = hole.loop;
  const std::vector<std::uint32_t>& patches = hole.patches;
  const std::size_t best = hole.best;
  const Eigen::AlignedBox3d& box = hole.box;
  FillPlan plan;
  // A fan whose triangles leave the exact surface (a loop doubling back along a sliver fanned
  // into a fin) is no fill; the local repair, which checks more, gets the hole instead.
  auto fan_fits = [&](const Vector3d& apex, std::size_t skip) {
    for (std::size_t i = 0; i < loop.size(); ++i) {
      if (i == skip || (i + 1) % loop.size() == skip) continue;
      const Vector3d &a = mesh.vertices[loop[i]], &b = mesh.vertices[loop[(i + 1) % loop.size()]];
      if (!triangle_near_field(a, b, apex, field, 2.0 * options.match_distance)) return false;
    }
    return true;
  };
  auto vertex_fan = [&](std::size_t centre) {
    plan.kind = FillPlan::Kind::kVertexFan;
    plan.centre = centre;
    return plan;
  };
  if (hole.best_residual <= 1e-7 && fan_fits(mesh.vertices[loop[best]], best)) return vertex_fan(best);
  const Vector3d start = mesh.vertices[loop[best]];
  // A corner far outside the hole is where the same surfaces meet again, not this corner.
  Eigen::AlignedBox3d near_box = box;
  near_box.min().array() -= 0.25 * box.diagonal().norm();
  near_box.max().array() += 0.25 * box.diagonal().norm();
  auto is_corner = [&](const Vector3d& x) {
    return x != start && near_box.contains(x) && std::abs(field(x)) <= 1e3 * options.weld_distance;
  };
  Vector3d found = corner_point(patches, surface, start, box.diagonal().norm());
  bool valid = is_corner(found);
  // Four or more surfaces around a hole need not share a point (a tool surface beside the
  // corner without reaching it): then a corner of three of them on the exact surface, the
  // nearest to the hole's centroid whose fan fits, else the nearest.
  if (!valid && patches.size() > 3 && patches.size() <= kMaxCornerPatches) {
    std::vector<std::pair<double, Vector3d>> corners;
    for (std::size_t a = 0; a < patches.size(); ++a)
      for (std::size_t b = a + 1; b < patches.size(); ++b)
        for (std::size_t c = b + 1; c < patches.size(); ++c) {
          const Vector3d x =
              corner_point({patches[a], patches[b], patches[c]}, surface, start, box.diagonal().norm());
          if (is_corner(x)) corners.push_back({(x - hole.centroid).norm(), x});
        }
    std::stable_sort(corners.begin(), corners.end(),
                     [](const auto& p, const auto& q) { return p.first < q.first; });
    if (!corners.empty()) {
      valid = true;
      found = corners.front().second;
      for (const auto& [distance, x] : corners)
        if (fan_fits(x, loop.size())) {
          found = x;
          break;
        }
    }
  }
  // Newton steps along the field's gradient.
  auto onto_field = [&](Vector3d x) {
    for (int it = 0; it < 20; ++it) {
      const double f = field(x);
      if (std::abs(f) <= 1e-3 * options.weld_distance) break;
      Vector3d gradient;
      const double h = 1e-7 * std::max(1.0, box.diagonal().norm());
      for (int k = 0; k < 3; ++k)
        gradient[k] = (field(x + h * Vector3d::Unit(k)) - field(x - h * Vector3d::Unit(k))) / (2 * h);
      if (gradient.squaredNorm() < 1e-12) break;
      x -= f * gradient / gradient.squaredNorm();
    }
    return x;
  };
  // Otherwise the centroid moved onto the exact surface; a hole where even that fails is left
  // to the local repair, which checks its fans.
  Vector3d corner = found;
  if (!valid) {
    corner = onto_field(hole.centroid);
    if (!(std::abs(field(corner)) <= 1e3 * options.weld_distance) || !near_box.contains(corner)) return plan;
  }
  // A corner found within the weld distance of one of the loop's own vertices is that vertex: a
  // new point there would leave an edge a billionth long that no later fan can cross.
  {
    std::size_t nearest = 0;
    for (std::size_t i = 1; i < loop.size(); ++i)
      if ((mesh.vertices[loop[i]] - corner).squaredNorm() <
          (mesh.vertices[loop[nearest]] - corner).squaredNorm())
        nearest = i;
    if ((mesh.vertices[loop[nearest]] - corner).norm() <= options.weld_distance &&
        fan_fits(mesh.vertices[loop[nearest]], nearest))
      return vertex_fan(nearest);
  }
  plan.corner = corner;
  if (fan_fits(corner, loop.size())) {
    plan.kind = FillPlan::Kind::kCornerFan;
    return plan;
  }
  // A curved or creased hole: rings of exact-surface points between the loop and the corner
  // take the fan's triangles closer to the surface.
  const std::size_t n = loop.size();
  for (int levels = 2; levels <= 3; ++levels) {
    // rings[k][i], k = 0 the loop, k = levels the corner.
    std::vector<std::vector<Vector3d>> rings(levels + 1, std::vector<Vector3d>(n, corner));
    bool fits = true;
    for (std::size_t i = 0; i < n; ++i) rings[0][i] = mesh.vertices[loop[i]];
    for (int k = 1; k < levels && fits; ++k)
      for (std::size_t i = 0; i < n && fits; ++i) {
        const double t = static_cast<double>(k) / levels;
        rings[k][i] = onto_field((1.0 - t) * rings[0][i] + t * corner);
        fits = std::abs(field(rings[k][i])) <= 1e3 * options.weld_distance;
      }
    const double limit = 2.0 * options.match_distance;
    for (int k = 0; k < levels && fits; ++k)
      for (std::size_t i = 0; i < n && fits; ++i) {
        const std::size_t j = (i + 1) % n;
        fits = triangle_near_field(rings[k][j], rings[k][i], rings[k + 1][i], field, limit) &&
               (k + 1 == levels ||
                triangle_near_field(rings[k][j], rings[k + 1][i], rings[k + 1][j], field, limit));
      }
    if (!fits) continue;
    plan.kind = FillPlan::Kind::kRinged;
    plan.rings.assign(rings.begin() + 1, rings.end() - 1);
    return plan;
  }
  return plan;
}

std::size_t fill_holes(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of, const SeamOptions& options,
                       const SurfaceFunction& surface, const FieldFunction& field,
                       const std::vector<std::uint8_t>& may_be_open) {
  const HalfEdges half(mesh, patch_of, may_be_open);
  const std::vector<std::uint8_t> open = open_edges(mesh, patch_of, half, may_be_open);
  // Outgoing boundary half-edges per vertex, with their triangle.
  std::unordered_map<std::uint32_t, std::vector<std::pair<std::uint32_t, std::uint32_t>>>
      out;  // v -> (next, tri)
  std::vector<std::pair<std::uint32_t, std::uint32_t>> starts;
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      if (!(open[t] & (1u << k))) continue;
      const std::uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      out[a].push_back({b, t});
      starts.push_back({a, b});
    }
  // The next hole from start edge a0 -> b0 over edges not `used`; false if there is none there.
  auto find_hole = [&](std::uint32_t a0, std::uint32_t b0,
                       const std::unordered_map<std::uint64_t, bool>& used, Hole& hole) {
    // Shortest loop of unused boundary edges back to a0 (breadth first): where two holes touch
    // at a vertex (a trimming curve ending exactly on another patch's border), that vertex has
    // two outgoing boundary edges and a plain walk could not choose.
    constexpr std::size_t kMaxLoop = 32;
    std::vector<std::uint32_t> frontier{b0};
    std::unordered_map<std::uint32_t, std::pair<std::uint32_t, std::uint32_t>>
        reached;  // v -> (previous, triangle)
    std::uint32_t first_triangle = UINT32_MAX;
    for (const auto& [b, t] : out[a0])
      if (b == b0) {
        first_triangle = t;
        break;
      }
    reached[b0] = {a0, first_triangle};
    bool closed = false;
    for (std::size_t depth = 1; depth < kMaxLoop && !frontier.empty() && !closed; ++depth) {
      std::vector<std::uint32_t> next;
      for (std::uint32_t a : frontier) {
        for (const auto& [b, t] : out[a]) {
          if (used.count(edge_key(a, b))) continue;
          if (b == a0) {
            reached[a0] = {a, t};
            closed = true;
            break;
          }
          if (reached.count(b)) continue;
          reached[b] = {a, t};
          next.push_back(b);
        }
        if (closed) break;
      }
      frontier = std::move(next);
    }
    if (!closed) return false;
    hole.loop.clear();
    hole.loop_triangles.clear();
    for (std::uint32_t v = a0;;) {
      const auto [previous, t] = reached.at(v);
      hole.loop.push_back(previous);
      hole.loop_triangles.push_back(t);
      v = previous;
      if (v == a0) break;
    }
    std::reverse(hole.loop.begin(), hole.loop.end());
    std::reverse(hole.loop_triangles.begin(), hole.loop_triangles.end());
    if (hole.loop.size() < 3) return false;
    hole.box = Eigen::AlignedBox3d();
    hole.centroid = Vector3d::Zero();
    for (std::uint32_t v : hole.loop) {
      hole.box.extend(mesh.vertices[v]);
      hole.centroid += mesh.vertices[v];
    }
    hole.centroid /= static_cast<double>(hole.loop.size());
    if (hole.box.diagonal().norm() > options.hole_diameter) return false;
    hole.patches.clear();
    for (std::uint32_t t : hole.loop_triangles)
      if (std::find(hole.patches.begin(), hole.patches.end(), patch_of[t].patch) == hole.patches.end())
        hole.patches.push_back(patch_of[t].patch);
    // The loop vertex nearest to lying on every surface: often the corner itself (a hole left
    // where a trimming curve ends exactly at a corner), else where the corner search starts, so
    // that it finds the corner next to the hole, not another point where the same surfaces meet
    // (which may lie inside a third move's sweep).
    hole.best = 0;
    hole.best_residual = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < hole.loop.size(); ++i) {
      double residual = 0.0;
      for (std::uint32_t q : hole.patches)
        residual = std::max(residual, std::abs(surface(q, mesh.vertices[hole.loop[i]])));
      if (residual < hole.best_residual) {
        hole.best_residual = residual;
        hole.best = i;
      }
    }
    return true;
  };
  auto plan_of = [&](const Hole& hole) { return plan_fill(mesh, options, surface, field, hole); };
  // The holes as the walk below meets them if every one is closed, planned in parallel. Where
  // one is not, its edges are free again and the walk may meet holes not planned here: those
  // are planned as they come.
  std::vector<Hole> holes;
  {
    std::unordered_map<std::uint64_t, bool> used;
    Hole hole;
    for (const auto& [a0, b0] : starts) {
      if (used.count(edge_key(a0, b0)) || !find_hole(a0, b0, used, hole)) continue;
      for (std::size_t i = 0; i < hole.loop.size(); ++i)
        used[edge_key(hole.loop[i], hole.loop[(i + 1) % hole.loop.size()])] = true;
      holes.push_back(hole);
    }
  }
  std::vector<FillPlan> plans(holes.size());
  tbb::parallel_for(std::size_t{0}, holes.size(), [&](std::size_t i) { plans[i] = plan_of(holes[i]); });
  std::map<std::vector<std::uint32_t>, std::size_t> planned;  // loop -> index in holes
  for (std::size_t i = 0; i < holes.size(); ++i) planned.emplace(holes[i].loop, i);
  {
    // Room for what the plans add, so that appending does not copy the whole mesh.
    std::size_t triangles = 0, vertices = 0;
    for (std::size_t i = 0; i < holes.size(); ++i) {
      triangles += 2 * (plans[i].rings.size() + 1) * holes[i].loop.size();
      vertices += 1;
      for (const std::vector<Vector3d>& ring : plans[i].rings) vertices += ring.size();
    }
    reserve_large(mesh.triangles, mesh.triangles.size() + triangles);
    reserve_large(mesh.tags, mesh.tags.size() + triangles);
    reserve_large(patch_of, patch_of.size() + triangles);
    reserve_large(mesh.vertices, mesh.vertices.size() + vertices);
  }

  // Closes a hole as its plan says.
  auto close = [&](const Hole& hole, const FillPlan& plan) {
    const auto& loop = hole.loop;
    const auto& loop_triangles = hole.loop_triangles;
    auto push = [&](const Triangle& t, std::size_t i) {
      mesh.triangles.push_back(t);
      mesh.tags.push_back(mesh.tags[loop_triangles[i]]);
      patch_of.push_back({patch_of[loop_triangles[i]].patch, 7});
    };
    const std::size_t n = loop.size();
    if (plan.kind == FillPlan::Kind::kVertexFan) {
      for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t va = loop[i], vb = loop[(i + 1) % n];
        if (i == plan.centre || (i + 1) % n == plan.centre) continue;
        push({vb, va, loop[plan.centre]}, i);
      }
    } else if (plan.kind == FillPlan::Kind::kRinged) {
      const int levels = static_cast<int>(plan.rings.size()) + 1;
      // Vertex indices: the loop's own, then the inner rings' new points, then the corner.
      const auto first = static_cast<std::uint32_t>(mesh.vertices.size());
      auto index = [&](int k, std::size_t i) {
        if (k == 0) return loop[i];
        if (k == levels) return first + static_cast<std::uint32_t>((levels - 1) * n);
        return first + static_cast<std::uint32_t>((k - 1) * n + i);
      };
      for (const std::vector<Vector3d>& ring : plan.rings)
        mesh.vertices.insert(mesh.vertices.end(), ring.begin(), ring.end());
      mesh.vertices.push_back(plan.corner);
      for (std::size_t i = 0; i < n; ++i) {
        const std::size_t j = (i + 1) % n;
        for (int k = 0; k < levels; ++k) {
          push({index(k, j), index(k, i), index(k + 1, i)}, i);
          if (k + 1 < levels) push({index(k, j), index(k + 1, i), index(k + 1, j)}, i);
        }
      }
    } else {
      const std::uint32_t c = static_cast<std::uint32_t>(mesh.vertices.size());
      mesh.vertices.push_back(plan.corner);
      for (std::size_t i = 0; i < n; ++i) push({loop[(i + 1) % n], loop[i], c}, i);
    }
  };
  // Where every hole found has a fill, the walk below would meet the same holes in the same
  // order (each closed hole takes the same edges out of the walk as above): they are closed as
  // found.
  if (std::all_of(plans.begin(), plans.end(),
                  [](const FillPlan& plan) { return plan.kind != FillPlan::Kind::kNone; })) {
    for (std::size_t i = 0; i < holes.size(); ++i) close(holes[i], plans[i]);
    return holes.size();
  }
  std::unordered_map<std::uint64_t, bool> used;
  std::size_t filled = 0;
  Hole hole;
  for (const auto& [a0, b0] : starts) {
    if (used.count(edge_key(a0, b0)) || !find_hole(a0, b0, used, hole)) continue;
    auto it = planned.find(hole.loop);
    const FillPlan plan = it != planned.end() && holes[it->second].loop_triangles == hole.loop_triangles
                              ? plans[it->second]
                              : plan_of(hole);
    if (plan.kind == FillPlan::Kind::kNone) continue;
    for (std::size_t i = 0; i < hole.loop.size(); ++i)
      used[edge_key(hole.loop[i], hole.loop[(i + 1) % hole.loop.size()])] = true;
    close(hole, plan);
    ++filled;
  }
  return filled;
}

std::size_t count_boundary(const TriangleMesh& mesh, const std::vector<TriangleOrigin>& patch_of,
                           const std::vector<std::uint8_t>& may_be_open) {
  const HalfEdges half(mesh, patch_of, may_be_open);
  std::size_t n = 0;
  for (const std::uint8_t bits : open_edges(mesh, patch_of, half, may_be_open))
    n += (bits & 1u) + ((bits >> 1) & 1u) + ((bits >> 2) & 1u);
  return n;
}

}  // namespace

bool triangle_near_field(const Vector3d& a, const Vector3d& b, const Vector3d& c, const FieldFunction& field,
                         double limit) {
  constexpr double kWeights[7][3] = {{1 / 3.0, 1 / 3.0, 1 / 3.0},
                                     {0.5, 0.5, 0},
                                     {0, 0.5, 0.5},
                                     {0.5, 0, 0.5},
                                     {0.6, 0.2, 0.2},
                                     {0.2, 0.6, 0.2},
                                     {0.2, 0.2, 0.6}};
  for (const auto& w : kWeights)
    if (!(std::abs(field(w[0] * a + w[1] * b + w[2] * c)) <= limit)) return false;
  return true;
}

SeamStats join_seams(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                     const SeamOptions& options, const SurfaceFunction& surface, const FieldFunction& field) {
  SeamStats stats;
  { stats.welded = weld(mesh, patch_of_triangle, options.weld_distance); }
  {
    stats.welded +=
        snap_boundary(mesh, patch_of_triangle, options.snap_distance, 1e3 * options.weld_distance, surface);
  }
  // The triangles that may have an open edge (empty: all), narrowed by each split pass.
  std::vector<std::uint8_t> may_be_open;
  for (int pass = 0; pass < 3; ++pass) {
    const std::size_t n = split_pass(mesh, patch_of_triangle, options, surface, may_be_open);
    stats.splits += n;
    if (n == 0) break;
  }
  // A trimming curve bending tighter than the grids resolve (a shallow cut's small circle) has
  // chords on either side up to twice their sagitta apart: what is still open gets one wider pass.
  {
    SeamOptions wide = options;
    wide.match_distance = 2.0 * options.match_distance;
    for (int pass = 0; pass < 3; ++pass) {
      const std::size_t n = split_pass(mesh, patch_of_triangle, wide, surface, may_be_open);
      stats.splits += n;
      if (n == 0) break;
    }
  }
  { stats.holes_filled = fill_holes(mesh, patch_of_triangle, options, surface, field, may_be_open); }
  { stats.boundary_edges = count_boundary(mesh, patch_of_triangle, may_be_open); }
  return stats;
}

}  // namespace morph::detail
