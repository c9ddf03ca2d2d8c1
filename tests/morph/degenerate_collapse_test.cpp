// SPDX-License-Identifier: Apache-2.0
// Generator 2's limit step on constructed exact degeneracies: four planes through one point, a
// ball polytope's pole inside the stock, a retrace, a 179.99° turn, two cutters touching along an
// edge. Each time the perturbation splits an exact point into several vertices (asserted, so the
// case is exercised); after the limit step and emit the surface must have no zero-area triangle,
// every rounded triangle must turn the way its polygon faces (exact), it must still be a closed,
// oriented 2-manifold, and its volume must be the conformed surface's and the closed form's.
// (Intersecting pairs by the exact CGAL check are asserted in tests/apps/generator2_rounding_test.cpp:
// that check lives in apps.)
#include <morph/carve.h>
#include <morph/conform.h>
#include <morph/degenerate_collapse.h>
#include <morph/emit.h>
#include <morph/quantize.h>
#include <morph/sweep_polytope.h>
#include <morph/tool.h>
#include <morph/tool_polytope.h>
#include <morph/topology.h>

#include <gtest/gtest.h>

#include <algorithm>

namespace {

using Eigen::Vector3d;

struct Stages {
  morph::ConformedSurface conformed;
  morph::LimitSurface limit;
  morph::TriangleMesh mesh;
  morph::EmitCounts emitted;
  morph::TopologyReport topology;
  double conformed_volume = 0;  // the conformed polygons fanned, by the divergence theorem
};

Stages run(const Eigen::AlignedBox3d& box, const std::vector<std::vector<morph::Halfspace>>& cutters,
           morph::ExecutionPolicy policy = morph::ExecutionPolicy::Parallel) {
  std::vector<std::vector<morph::ExactPlane>> sweeps;
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const auto& h : cutters) {
    sweeps.push_back(morph::sweep_planes(h, static_cast<std::uint32_t>(sweeps.size())));
    boxes.push_back(box);  // every pair is tried
  }
  Stages s;
  s.conformed = morph::conform(morph::carve_box(box, sweeps, boxes), policy);
  for (const morph::ConformedPolygon& p : s.conformed.polygons)
    for (std::size_t k = 1; k + 1 < p.loop.size(); ++k) {
      const auto point = [&](std::uint32_t v) {
        const auto& t = s.conformed.vertices[v];
        return morph::vertex_point(t[0], t[1], t[2]);
      };
      s.conformed_volume += point(p.loop[0]).dot(point(p.loop[k]).cross(point(p.loop[k + 1]))) / 6;
    }
  s.limit = morph::collapse_degenerates(s.conformed, policy);
  const std::vector<std::int32_t> moves(cutters.size(), 0);
  s.mesh = morph::emit(s.limit, moves, moves, &s.emitted);
  s.topology = morph::topology_report(s.mesh);
  return s;
}

// The sweeps of a polyline with one tool, as erode builds them.
std::vector<std::vector<morph::Halfspace>> sweeps_of(const morph::Tool& tool,
                                                     const std::vector<Vector3d>& path,
                                                     double tolerance = 0.05) {
  const morph::SweepPolytopeBuilder builder(morph::tool_polytope(tool.profile, 0.4 * tolerance).polytope);
  // The ends on the tool's grid, as erode puts them (quantize.h).
  const int grid = morph::grid_exponent_for(0.4 * tolerance);
  std::vector<std::vector<morph::Halfspace>> out;
  for (std::size_t k = 0; k + 1 < path.size(); ++k)
    out.push_back(
        builder.halfspaces(morph::snap_to_grid(path[k], grid), morph::snap_to_grid(path[k + 1], grid)));
  return out;
}

morph::ConvexPolytope polytope_of(const morph::Tool& tool, double tolerance = 0.05) {
  return morph::tool_polytope(tool.profile, 0.4 * tolerance).polytope;
}

void expect_clean(const Stages& s, double volume, const char* what, bool no_flat_triangles = true) {
  EXPECT_GT(s.limit.counts.merged_vertices + s.emitted.collapsed_edges + s.emitted.flipped_edges, 0u)
      << what << ": no degeneracy exercised";
  EXPECT_TRUE(s.topology.closed_manifold())
      << what << ": " << s.topology.boundary_edges << " boundary, " << s.topology.non_manifold_edges
      << " non-manifold edges, " << s.topology.inconsistent_edges << " inconsistent, "
      << s.topology.non_manifold_vertices << " non-manifold vertices";
  if (no_flat_triangles) {
    EXPECT_EQ(s.topology.degenerate_triangles, 0u) << what;
  }
  EXPECT_EQ(s.emitted.misoriented_left, 0u) << what;
  EXPECT_EQ(s.limit.counts.flat_polygons_left, 0u) << what;
  EXPECT_EQ(s.topology.unreferenced_vertices, 0u) << what;
  EXPECT_NEAR(s.topology.volume, s.conformed_volume, 1e-11 * std::fabs(volume)) << what;
  EXPECT_NEAR(s.topology.volume, volume, 1e-9 * std::fabs(volume)) << what;
}

TEST(DegenerateCollapse, FourPlanesThroughOnePoint) {
  // An upside-down square pyramid, apex (5, 5, 5) inside the cube [0, 10]³, open above: its four
  // sides meet at the apex. Removed: ∫₀⁵ (2h)² dh = 500/3.
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(10, 10, 10));
  const std::vector<morph::Halfspace> pyramid{{Vector3d(1, 0, -1), 0.0},
                                              {Vector3d(-1, 0, -1), -10.0},
                                              {Vector3d(0, 1, -1), 0.0},
                                              {Vector3d(0, -1, -1), -10.0},
                                              {Vector3d(0, 0, 1), 20.0}};
  const Stages s = run(box, {pyramid});
  expect_clean(s, 1000.0 - 500.0 / 3.0, "pyramid");
}

TEST(DegenerateCollapse, BallPoleInsideTheStock) {
  // A vertical move of a ball end inside the stock: the polytope's pole, where a ring of facets
  // meets, is a vertex of the cavity. Removed: the sweep polytope.
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(20, 20, 30));
  const morph::Tool tool = morph::ball_tool(3.0, 6.0);
  const Vector3d a(10, 10, 5), b(10, 10, 12);
  const Stages s = run(box, sweeps_of(tool, {a, b}));
  expect_clean(s, box.volume() - morph::sweep_polytope(polytope_of(tool), a, b).volume(), "pole");
}

TEST(DegenerateCollapse, RetraceInsideTheStock) {
  // There and straight back inside the stock: every plane of the return coincides with one of
  // the first pass. Removed: the first pass's sweep polytope.
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(30, 20, 20));
  const morph::Tool tool = morph::ball_tool(2.0, 5.0);
  const Vector3d a(8, 10, 6), b(22, 11, 7);
  const Stages s = run(box, sweeps_of(tool, {a, b, a}));
  expect_clean(s, box.volume() - morph::sweep_polytope(polytope_of(tool), a, b).volume(), "retrace");
}

TEST(DegenerateCollapse, TurnAt179Point99Degrees) {
  // A slot from outside turning back 3 µm sideways inside the stock (erode2_test's, r11's shape).
  // No closed form for the union: the volume is the conformed surface's, between the single
  // pass's and that minus the 3 µm strip's bound.
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(40, 30, 5));
  const morph::Tool tool = morph::ball_tool(1.5, 20.0);
  const Stages single = run(box, sweeps_of(tool, {Vector3d(-5, 15, 3), Vector3d(20, 15, 3)}));
  const Stages near =
      run(box, sweeps_of(tool, {Vector3d(-5, 15, 3), Vector3d(20, 15, 3), Vector3d(-5, 15.003, 3)}));
  // Not yet met here: a needle or two (edges ~1e-13 of the triangle's size, exact features of
  // the thin cells) that no collapse, flip or re-rounding settles without turning a neighbour
  // over are left flat (correctly oriented; see rounding.h and notes/18.md). Bounded, not zero:
  expect_clean(near, near.conformed_volume, "179.99 degrees", false);
  EXPECT_LE(near.topology.degenerate_triangles, 3u);
  EXPECT_LT(near.topology.volume, single.topology.volume);
  EXPECT_GT(near.topology.volume, single.topology.volume - 25 * 3 * 0.003);
}

// The axis-aligned box [lo, hi] as a cutter's halfspaces.
std::vector<morph::Halfspace> cube_cutter(const Vector3d& lo, const Vector3d& hi) {
  return {{Vector3d(-1, 0, 0), -lo.x()}, {Vector3d(1, 0, 0), hi.x()},   {Vector3d(0, -1, 0), -lo.y()},
          {Vector3d(0, 1, 0), hi.y()},   {Vector3d(0, 0, -1), -lo.z()}, {Vector3d(0, 0, 1), hi.z()}};
}

TEST(DegenerateCollapse, CuttersTouchingAlongAnEdgeStayApart) {
  // Two cube cutters inside the stock sharing one edge only: the limit solid is not a manifold
  // there (four faces on one edge). The output keeps the two sheets apart and stays a
  // 2-manifold; removed: both cubes.
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(10, 10, 10));
  const Stages s = run(box, {cube_cutter(Vector3d(2, 2, 2), Vector3d(5, 5, 8)),
                             cube_cutter(Vector3d(5, 5, 2), Vector3d(8, 8, 8))});
  EXPECT_TRUE(s.topology.closed_manifold());
  EXPECT_GT(s.limit.counts.kept_apart, 0u);
  EXPECT_EQ(s.emitted.misoriented_left, 0u);
  EXPECT_NEAR(s.topology.volume, 1000.0 - 2 * 54.0, 1e-9);
}

TEST(DegenerateCollapse, CuttersTouchingAtACornerStayApart) {
  // Two cube cutters sharing one corner only: every edge of the limit has two faces, but the
  // shared corner has two fans of faces. Only the fan walk sees it; the output keeps the two
  // cavities apart there.
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(10, 10, 10));
  for (const morph::ExecutionPolicy policy :
       {morph::ExecutionPolicy::Sequential, morph::ExecutionPolicy::Parallel}) {
    const Stages s = run(box,
                         {cube_cutter(Vector3d(2, 2, 2), Vector3d(5, 5, 5)),
                          cube_cutter(Vector3d(5, 5, 5), Vector3d(8, 8, 8))},
                         policy);
    EXPECT_TRUE(s.topology.closed_manifold());
    EXPECT_EQ(s.topology.non_manifold_vertices, 0u);
    EXPECT_GT(s.limit.counts.kept_apart, 0u);
    EXPECT_EQ(s.emitted.misoriented_left, 0u);
    EXPECT_NEAR(s.topology.volume, 1000.0 - 2 * 27.0, 1e-9);
  }
}

// Conform numbers the vertices by sorting, and the limit step finds its classes and slivers in
// parallel: the surfaces are the same under either policy, vertex for vertex, and the vertices
// are numbered in the order the pieces' corners first name them. A ball end's zigzag inside the
// stock, its poles and turns splitting points (thousands of corners: the parallel sorts run).
TEST(DegenerateCollapse, TheSameSurfaceUnderEitherPolicy) {
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(40, 30, 20));
  const morph::Tool tool = morph::ball_tool(2.0, 10.0);
  std::vector<std::vector<morph::ExactPlane>> sweeps;
  std::vector<Eigen::AlignedBox3d> boxes;
  for (const auto& h : sweeps_of(tool, {Vector3d(5, 5, 12), Vector3d(35, 8, 12), Vector3d(6, 14, 11),
                                        Vector3d(34, 20, 12), Vector3d(34, 20, 6), Vector3d(5, 25, 12)})) {
    sweeps.push_back(morph::sweep_planes(h, static_cast<std::uint32_t>(sweeps.size())));
    boxes.push_back(box);
  }
  const std::vector<morph::CarvedPiece> pieces = morph::carve_box(box, sweeps, boxes);
  const morph::ConformedSurface one = morph::conform(pieces, morph::ExecutionPolicy::Sequential);
  const morph::ConformedSurface many = morph::conform(pieces, morph::ExecutionPolicy::Parallel);
  ASSERT_GT(one.vertices.size(), 1000u);
  auto ranks = [](const morph::ConformedSurface& s) {
    std::vector<std::uint64_t> out;
    for (std::size_t v = 0; v < s.vertices.size(); ++v)
      for (const morph::ExactPlane* p : s.vertices[v].planes) out.push_back(p->rank);
    return out;
  };
  EXPECT_EQ(ranks(one), ranks(many));
  ASSERT_EQ(one.polygons.size(), many.polygons.size());
  for (std::size_t i = 0; i < one.polygons.size(); ++i)
    EXPECT_EQ(one.polygons[i].loop, many.polygons[i].loop);
  // Numbered by first use: piece by piece, corner by corner, each new vertex the next number.
  std::uint32_t next = 0;
  for (const morph::CarvedPiece& piece : pieces) {
    const std::size_t n = piece.piece.edges.size();
    for (std::size_t k = 0; k < n; ++k) {
      std::array<std::uint64_t, 3> key{piece.piece.support.rank, piece.piece.edges[(k + n - 1) % n].rank,
                                       piece.piece.edges[k].rank};
      std::sort(key.begin(), key.end());
      std::uint32_t v = 0;
      while (v < one.vertices.size() &&
             !(one.vertices[v][0].rank == key[0] && one.vertices[v][1].rank == key[1] &&
               one.vertices[v][2].rank == key[2]))
        ++v;
      ASSERT_LT(v, one.vertices.size());
      ASSERT_LE(v, next);
      if (v == next) ++next;
    }
  }
  EXPECT_EQ(next, one.vertices.size());
  const morph::LimitSurface limit_one = morph::collapse_degenerates(one, morph::ExecutionPolicy::Sequential);
  const morph::LimitSurface limit_many = morph::collapse_degenerates(one, morph::ExecutionPolicy::Parallel);
  EXPECT_GT(limit_one.counts.merged_vertices, 0u);
  EXPECT_EQ(limit_one.counts.merged_vertices, limit_many.counts.merged_vertices);
  EXPECT_EQ(limit_one.counts.zipped_slivers, limit_many.counts.zipped_slivers);
  EXPECT_EQ(limit_one.counts.removed_polygons, limit_many.counts.removed_polygons);
  ASSERT_EQ(limit_one.polygons.size(), limit_many.polygons.size());
  for (std::size_t i = 0; i < limit_one.polygons.size(); ++i) {
    EXPECT_EQ(limit_one.polygons[i].loop, limit_many.polygons[i].loop);
    EXPECT_EQ(limit_one.polygons[i].straight_corners, limit_many.polygons[i].straight_corners);
  }
  // Emitted alike: the same points bit for bit, triangles and provenance, centroids included.
  std::vector<std::int32_t> move_index, move_line;
  for (std::size_t m = 0; m < sweeps.size(); ++m) {
    move_index.push_back(static_cast<std::int32_t>(m));
    move_line.push_back(static_cast<std::int32_t>(10 + m));
  }
  const morph::TriangleMesh mesh_one =
      morph::emit(limit_one, move_index, move_line, nullptr, morph::ExecutionPolicy::Sequential);
  const morph::TriangleMesh mesh_many =
      morph::emit(limit_one, move_index, move_line, nullptr, morph::ExecutionPolicy::Parallel);
  EXPECT_TRUE(std::any_of(limit_one.polygons.begin(), limit_one.polygons.end(),
                          [](const morph::LimitPolygon& p) { return !p.strictly_convex(); }));
  EXPECT_EQ(mesh_one.vertices, mesh_many.vertices);
  EXPECT_EQ(mesh_one.triangles, mesh_many.triangles);
  EXPECT_TRUE(mesh_one.tags == mesh_many.tags);
  EXPECT_GT(mesh_one.triangle_count(), 1000u);
}

}  // namespace
