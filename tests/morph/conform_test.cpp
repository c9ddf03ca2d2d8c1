// SPDX-License-Identifier: Apache-2.0
// Conforming (conform.h): each plane-pair line's vertices are sorted along it once; every edge
// then takes the vertices strictly between its corners from that order. Checked against the
// direct definition, edge by edge: a vertex of the edge's line is inside iff its third plane
// separates the edge's corners, and r1 comes before r2 iff r1's plane separates the first corner
// from r2 (exact predicates).
#include <morph/carve_culled.h>
#include <morph/conform.h>
#include <morph/tool.h>
#include <morph/tool_polytope.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

namespace {

using Eigen::Vector3d;
using Key = std::array<std::uint64_t, 3>;

const morph::ExactPlane& third(const morph::PlaneTriple& v, std::uint64_t s, std::uint64_t e) {
  for (const morph::ExactPlane* p : v.planes)
    if (p->rank != s && p->rank != e) return *p;
  return v[0];
}

// The loop of piece i by the definition: corners, and between corners k and k+1 the vertices
// of their line strictly between them, ordered from corner k.
std::vector<std::uint32_t> expected_loop(const morph::ConformedSurface& surface,
                                         const morph::CarvedPiece& piece,
                                         const std::map<Key, std::uint32_t>& index) {
  const morph::ConvexPiece& p = piece.piece;
  const std::size_t n = p.edges.size();
  auto id = [&](const morph::ExactPlane& a, const morph::ExactPlane& b, const morph::ExactPlane& c) {
    Key k{a.rank, b.rank, c.rank};
    std::sort(k.begin(), k.end());
    return index.at(k);
  };
  std::vector<std::uint32_t> loop;
  for (std::size_t k = 0; k < n; ++k) {
    const morph::ExactPlane &s = p.support, &e = p.edges[k];
    const std::uint32_t from = id(s, p.edges[(k + n - 1) % n], e), to = id(s, e, p.edges[(k + 1) % n]);
    loop.push_back(from);
    const morph::ExactPlane& a = third(surface.vertices[from], s.rank, e.rank);
    const morph::ExactPlane& b = third(surface.vertices[to], s.rank, e.rank);
    std::vector<std::uint32_t> inside;
    for (std::uint32_t r = 0; r < surface.vertices.size(); ++r) {
      const morph::PlaneTriple v = surface.vertices[r];
      const bool on_line = std::count_if(v.planes.begin(), v.planes.end(), [&](const morph::ExactPlane* x) {
                             return x->rank == s.rank || x->rank == e.rank;
                           }) == 2;
      if (!on_line || r == from || r == to) continue;
      const morph::ExactPlane& c = third(v, s.rank, e.rank);
      if (morph::side_at_vertex(s, e, a, c) != morph::side_at_vertex(s, e, b, c)) inside.push_back(r);
    }
    std::sort(inside.begin(), inside.end(), [&](std::uint32_t r1, std::uint32_t r2) {
      const morph::ExactPlane& c1 = third(surface.vertices[r1], s.rank, e.rank);
      const morph::ExactPlane& c2 = third(surface.vertices[r2], s.rank, e.rank);
      return morph::side_at_vertex(s, e, a, c1) != morph::side_at_vertex(s, e, c2, c1);
    });
    loop.insert(loop.end(), inside.begin(), inside.end());
  }
  if (!piece.faces_out()) std::reverse(loop.begin(), loop.end());
  return loop;
}

TEST(Conform, EdgesTakeTheVerticesBetweenTheirCornersInOrder) {
  // A square loop, then the same loop reversed and a diagonal pass: many pieces meet along long
  // lines (the slots' floors and walls), so vertices are inserted into edges.
  const morph::SweepPolytopeBuilder tool(
      morph::tool_polytope(morph::flat_tool(1.5, 20.0).profile, 0.04).polytope);
  const std::vector<Vector3d> path = {Vector3d(8, 8, 4),     Vector3d(22, 8, 4),   Vector3d(22, 22, 4),
                                      Vector3d(8, 22, 4),    Vector3d(8, 8, 4),    Vector3d(8, 22, 3.5),
                                      Vector3d(22, 22, 3.5), Vector3d(22, 8, 3.5), Vector3d(8, 22, 4.5)};
  std::vector<morph::CarveSweep> sweeps;
  for (std::size_t k = 0; k + 1 < path.size(); ++k) sweeps.push_back({&tool, path[k], path[k + 1]});
  const std::vector<morph::CarvedPiece> pieces = morph::expanded(
      morph::carve_culled(Eigen::AlignedBox3d(Vector3d(0, 0, 0), Vector3d(30, 30, 5)), sweeps));
  for (morph::ExecutionPolicy policy :
       {morph::ExecutionPolicy::Sequential, morph::ExecutionPolicy::Parallel}) {
    const morph::ConformedSurface surface = morph::conform(pieces, policy);
    std::map<Key, std::uint32_t> index;
    for (std::uint32_t v = 0; v < surface.vertices.size(); ++v)
      index[{surface.vertices[v][0].rank, surface.vertices[v][1].rank, surface.vertices[v][2].rank}] = v;
    EXPECT_EQ(index.size(), surface.vertices.size()) << "one vertex per plane triple";
    EXPECT_GT(surface.inserted, 20u) << "the job should insert vertices into edges";
    ASSERT_EQ(surface.polygons.size(), pieces.size());
    for (std::size_t i = 0; i < pieces.size(); ++i)
      EXPECT_EQ(surface.polygons[i].loop, expected_loop(surface, pieces[i], index)) << "piece " << i;
  }
}

}  // namespace
