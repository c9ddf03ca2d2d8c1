// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/topology.h>
#include <morph/union_find.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/parallel_sort.h>
#include "mesh/edge_uses.h"
#include "mesh/huge_pages.h"

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace morph {

namespace {

// Conventions shared by every count below:
// - A triangle with a repeated vertex index ("collapsed") is counted in `triangles` and
//   `degenerate_triangles` but takes no part in edges, manifoldness or the Euler characteristic:
//   it has no well-defined edges or orientation. Zero-area triangles with three distinct indices
//   are degenerate geometrically but are ordinary faces combinatorially.
// - Components join triangles that share an undirected edge (any number of triangles on it),
//   including the single edge a collapsed triangle (a, a, b) still has.

bool collapsed(const Triangle& t) {
  return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
}

bool zero_area(const TriangleMesh& mesh, const Triangle& t) {
  return morph::zero_area(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]);
}

using detail::EdgeUse;

// The uses of the edges of proper triangles (three distinct vertices), sorted by (key, triangle)
// so that the uses of one edge are contiguous and the order is deterministic.
std::vector<EdgeUse> proper_edge_uses(const TriangleMesh& mesh) {
  std::vector<EdgeUse> all = detail::sorted_edge_uses(mesh);
  std::vector<EdgeUse> uses;
  detail::reserve_large(uses, all.size());
  for (const EdgeUse& use : all)
    if (!collapsed(mesh.triangles[use.triangle])) uses.push_back(use);
  return uses;
}

// True when the triangles around `v` form one disc or half-disc: the link of v (one edge w1-w2 per
// triangle (v, w1, w2)) is a single cycle or a single path. That holds iff no link vertex has more
// than two link edges (no edge at v is shared by three or more triangles) and the link is connected.
// Storage reused from vertex to vertex (one per thread).
struct LinkScratch {
  std::vector<std::uint32_t> link_vertices;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> link_edges;
  std::vector<int> degree;
  UnionFind sets;
};

bool vertex_is_manifold(std::uint32_t v, const std::uint32_t* incident_begin,
                        const std::uint32_t* incident_end, const TriangleMesh& mesh, LinkScratch& scratch) {
  // Local ids for the link vertices; fans are small, so linear search beats hashing.
  std::vector<std::uint32_t>& link_vertices = scratch.link_vertices;
  std::vector<std::pair<std::uint32_t, std::uint32_t>>& link_edges = scratch.link_edges;
  link_vertices.clear();
  link_edges.clear();
  auto local = [&](std::uint32_t w) -> std::uint32_t {
    auto it = std::find(link_vertices.begin(), link_vertices.end(), w);
    if (it != link_vertices.end()) return static_cast<std::uint32_t>(it - link_vertices.begin());
    link_vertices.push_back(w);
    return static_cast<std::uint32_t>(link_vertices.size() - 1);
  };
  for (const std::uint32_t* it = incident_begin; it != incident_end; ++it) {
    const Triangle& tri = mesh.triangles[*it];
    const int k = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
    link_edges.emplace_back(local(tri[(k + 1) % 3]), local(tri[(k + 2) % 3]));
  }
  std::vector<int>& degree = scratch.degree;
  degree.assign(link_vertices.size(), 0);
  UnionFind& sets = scratch.sets;
  sets.reset(link_vertices.size());
  for (const auto& [a, b] : link_edges) {
    if (++degree[a] > 2 || ++degree[b] > 2) return false;
    sets.unite(a, b);
  }
  for (std::uint32_t i = 1; i < link_vertices.size(); ++i)
    if (sets.find(i) != sets.find(0)) return false;
  return true;
}

void check_indices(const TriangleMesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (std::uint32_t v : mesh.triangles[t])
      if (v >= n)
        throw InputError("topology report: triangle " + std::to_string(t) + " refers to vertex " +
                         std::to_string(v) + " but there are " + std::to_string(n) + " vertices");
}

// Whether each of `count` vertices (row i: vertex_of(i); row_of(v): v's row, or kNoRow) has
// proper triangles forming one disc or half-disc (vertices without any: true).
constexpr std::uint32_t kNoRow = UINT32_MAX;
template <class RowOf, class VertexOf>
std::vector<char> manifold_rows(const TriangleMesh& mesh, std::size_t count, RowOf&& row_of,
                                VertexOf&& vertex_of) {
  // Incident proper triangles of every row's vertex, in compressed rows.
  std::vector<std::uint32_t> row_start(count + 1, 0);
  for (const Triangle& t : mesh.triangles)
    if (!collapsed(t))
      for (std::uint32_t v : t)
        if (const std::uint32_t row = row_of(v); row != kNoRow) ++row_start[row + 1];
  std::partial_sum(row_start.begin(), row_start.end(), row_start.begin());
  std::vector<std::uint32_t> incident_triangles = detail::large_vector<std::uint32_t>(row_start.back());
  std::vector<std::uint32_t> fill(row_start.begin(), row_start.end() - 1);
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
    if (!collapsed(mesh.triangles[t]))
      for (std::uint32_t v : mesh.triangles[t])
        if (const std::uint32_t row = row_of(v); row != kNoRow) incident_triangles[fill[row]++] = t;
  // Each vertex is judged by its own fan alone.
  std::vector<char> manifold(count, 1);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(count)),
                    [&](const tbb::blocked_range<std::uint32_t>& range) {
                      LinkScratch scratch;
                      for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
                        if (row_start[i] == row_start[i + 1]) continue;
                        manifold[i] =
                            vertex_is_manifold(vertex_of(i), incident_triangles.data() + row_start[i],
                                               incident_triangles.data() + row_start[i + 1], mesh, scratch);
                      }
                    });
  return manifold;
}

std::vector<char> manifold_vertices(const TriangleMesh& mesh) {
  auto same = [](std::uint32_t v) { return v; };
  return manifold_rows(mesh, mesh.vertices.size(), same, same);
}

// Each piece's own Euler characteristic and soundness. Edges belong to one piece (pieces are
// edge-connected); a vertex where pieces touch counts once in each of them.
std::vector<PieceTopology> piece_topologies(const TriangleMesh& mesh, const std::vector<EdgeUse>& uses,
                                            const std::vector<char>& manifold,
                                            const std::vector<std::uint32_t>& component_of_triangle,
                                            std::size_t components) {
  std::vector<long> vertices(components, 0), edges(components, 0);
  std::vector<char> sound(components, 1);
  for (std::size_t begin = 0; begin < uses.size();) {
    std::size_t end = begin + 1;
    while (end < uses.size() && uses[end].key == uses[begin].key) ++end;
    const std::uint32_t piece = component_of_triangle[uses[begin].triangle];
    ++edges[piece];
    if (end - begin != 2 || uses[begin].forward == uses[begin + 1].forward) sound[piece] = 0;
    begin = end;
  }
  std::vector<PieceTopology> pieces(components);
  constexpr std::uint32_t kNone = UINT32_MAX;
  std::vector<std::uint32_t> first_piece(mesh.vertices.size(), kNone);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> shared;  // (vertex, a further piece)
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    if (collapsed(tri)) continue;
    const std::uint32_t piece = component_of_triangle[t];
    ++pieces[piece].triangles;
    for (std::uint32_t v : tri) {
      if (!manifold[v]) sound[piece] = 0;
      if (first_piece[v] == kNone) {
        first_piece[v] = piece;
        ++vertices[piece];
      } else if (first_piece[v] != piece) {
        shared.emplace_back(v, piece);
      }
    }
  }
  std::sort(shared.begin(), shared.end());
  shared.erase(std::unique(shared.begin(), shared.end()), shared.end());
  for (const auto& vertex_piece : shared) ++vertices[vertex_piece.second];
  for (std::size_t c = 0; c < components; ++c) {
    PieceTopology& piece = pieces[c];
    piece.euler_characteristic = vertices[c] - edges[c] + static_cast<long>(piece.triangles);
    piece.closed_manifold = sound[c] && piece.triangles > 0;
    piece.genus = piece.closed_manifold ? (2 - piece.euler_characteristic) / 2 : -1;
  }
  return pieces;
}

}  // namespace

std::vector<std::uint32_t> non_manifold_vertices(const TriangleMesh& mesh) {
  check_indices(mesh);
  const std::vector<char> manifold = manifold_vertices(mesh);
  std::vector<std::uint32_t> vertices;
  for (std::uint32_t v = 0; v < manifold.size(); ++v)
    if (!manifold[v]) vertices.push_back(v);
  return vertices;
}

std::vector<std::uint32_t> non_manifold_vertices(const TriangleMesh& mesh,
                                                 const std::vector<std::uint32_t>& among) {
  check_indices(mesh);
  std::vector<std::uint32_t> row_of(mesh.vertices.size(), kNoRow);
  for (std::uint32_t i = 0; i < among.size(); ++i) {
    if (among[i] >= mesh.vertices.size())
      throw InputError("non-manifold vertices: vertex " + std::to_string(among[i]) +
                       " asked about but there are " + std::to_string(mesh.vertices.size()) + " vertices");
    row_of[among[i]] = i;
  }
  const std::vector<char> manifold = manifold_rows(
      mesh, among.size(), [&](std::uint32_t v) { return row_of[v]; },
      [&](std::uint32_t i) { return among[i]; });
  std::vector<std::uint32_t> vertices;
  for (std::uint32_t i = 0; i < among.size(); ++i)
    if (!manifold[i]) vertices.push_back(among[i]);
  return vertices;
}

std::size_t connected_components(const TriangleMesh& mesh,
                                 std::vector<std::uint32_t>& component_of_triangle) {
  check_indices(mesh);
  return detail::components_of_uses(mesh.triangles.size(), detail::sorted_edge_uses(mesh),
                                    component_of_triangle);
}

TopologyReport topology_report(const TriangleMesh& mesh) {
  check_indices(mesh);
  TopologyReport report;
  const std::size_t vertex_count = mesh.vertices.size();
  report.triangles = mesh.triangles.size();

  std::vector<char> referenced(vertex_count, 0);
  std::size_t proper_triangles = 0;
  for (const Triangle& t : mesh.triangles) {
    for (std::uint32_t v : t) referenced[v] = 1;
    if (collapsed(t)) {
      ++report.degenerate_triangles;
      continue;
    }
    ++proper_triangles;
    if (zero_area(mesh, t)) ++report.degenerate_triangles;
  }
  report.vertices = static_cast<std::size_t>(std::count(referenced.begin(), referenced.end(), 1));
  report.unreferenced_vertices = vertex_count - report.vertices;

  const std::vector<EdgeUse> uses = proper_edge_uses(mesh);
  for (std::size_t begin = 0; begin < uses.size();) {
    std::size_t end = begin + 1;
    while (end < uses.size() && uses[end].key == uses[begin].key) ++end;
    const std::size_t count = end - begin;
    ++report.edges;
    if (count == 1)
      ++report.boundary_edges;
    else if (count >= 3)
      ++report.non_manifold_edges;
    else if (uses[begin].forward == uses[begin + 1].forward)
      ++report.inconsistent_edges;
    begin = end;
  }

  const std::vector<char> manifold = manifold_vertices(mesh);
  report.non_manifold_vertices = static_cast<std::size_t>(std::count(manifold.begin(), manifold.end(), 0));

  std::vector<std::uint32_t> component_of_triangle;
  // Without collapsed triangles the edges joining components are the ones already sorted (a
  // collapsed (a, a, b) still joins by its edge a-b).
  if (proper_triangles == mesh.triangles.size())
    report.components = detail::components_of_uses(mesh.triangles.size(), uses, component_of_triangle);
  else
    report.components = detail::components_of_uses(mesh.triangles.size(), detail::sorted_edge_uses(mesh),
                                                   component_of_triangle);
  report.euler_characteristic = static_cast<long>(report.vertices) - static_cast<long>(report.edges) +
                                static_cast<long>(proper_triangles);
  report.pieces = piece_topologies(mesh, uses, manifold, component_of_triangle, report.components);
  report.volume = enclosed_volume(mesh);
  report.area = surface_area(mesh);
  return report;
}

}  // namespace morph
