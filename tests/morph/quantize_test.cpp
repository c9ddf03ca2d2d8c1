// SPDX-License-Identifier: Apache-2.0
// Generator 2's grid (quantize.h): the tool polytope's vertices on the grid and its facets exactly
// planar there, so the facets at a vertex meet exactly in it; the sweeps' planes, silhouette planes
// included, exactly through their vertices; the integer predicates against cpp_int on random and
// degenerate planes. (The tool's accuracy with the grid is tool_polytope_test's: every shape
// within its budget both ways.)
#include "generator/exact_determinant.h"

#include <morph/plane_predicates.h>
#include <morph/quantize.h>
#include <morph/sweep_polytope.h>
#include <morph/tool.h>
#include <morph/tool_polytope.h>

#include <gtest/gtest.h>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <boost/multiprecision/cpp_int.hpp>
#pragma GCC diagnostic pop

#include <map>
#include <random>
#include <string>
#include <vector>

namespace {

using boost::multiprecision::cpp_int;
using Eigen::Vector3d;

std::vector<std::pair<std::string, morph::Tool>> tools() {
  return {{"ball", morph::ball_tool(1.5875, 12)},
          {"flat", morph::flat_tool(3, 20)},
          {"bullnose", morph::bullnose_tool(4, 1, 15)},
          {"tapered", morph::tapered_tool(1, 2, 5.5)},
          {"conical", morph::conical_tool(3, 60, 10)},
          {"tapered ball", morph::tapered_ball_tool(1, 0.2, 10)},
          {"sphere", morph::sphere_tool(2)}};
}

// Every facet of `polytope` has an exact plane holding every vertex of its loop exactly.
void expect_exact_facets(const morph::ConvexPolytope& polytope, int grid, const std::string& what) {
  std::size_t checked = 0;
  for (std::size_t f = 0; f < polytope.facets.size(); ++f) {
    const morph::PolytopeFacet& facet = polytope.facets[f];
    ASSERT_TRUE(facet.exact.set()) << what << " facet " << f;
    EXPECT_EQ(facet.exact.grid_exponent, grid) << what;
    for (int v : facet.loop) {
      const std::optional<morph::GridPoint> p = morph::grid_point(polytope.vertices[v], grid);
      ASSERT_TRUE(p) << what << " vertex " << v << " off the grid";
      EXPECT_TRUE(facet.exact.value_at(*p) == 0) << what << " facet " << f << " misses vertex " << v;
      ++checked;
    }
    // The exact normal points the way the rounded one does.
    const Vector3d n(double(facet.exact.normal[0]), double(facet.exact.normal[1]),
                     double(facet.exact.normal[2]));
    EXPECT_GT(n.normalized().dot(facet.normal), 1 - 1e-9) << what << " facet " << f;
  }
  EXPECT_GT(checked, 0u);
}

TEST(Quantize, ToolFacetsMeetExactlyAtEveryVertex) {
  for (const auto& [name, tool] : tools()) {
    const morph::ToolPolytope built = morph::tool_polytope(tool.profile, 0.004);
    expect_exact_facets(built.polytope, built.grid_exponent, name);
    // Through the predicates too: at every vertex, three facets with independent normals fix it
    // and every other facet there passes exactly through it (limit side 0).
    std::map<int, std::vector<int>> at_vertex;
    for (std::size_t f = 0; f < built.polytope.facets.size(); ++f)
      for (int v : built.polytope.facets[f].loop) at_vertex[v].push_back(static_cast<int>(f));
    auto plane = [&](int f) {
      const morph::PolytopeFacet& facet = built.polytope.facets[f];
      return morph::ExactPlane{facet.normal, facet.offset, morph::sweep_rank(0, f), 1, facet.exact};
    };
    int checked = 0;
    for (const auto& [v, facets] : at_vertex) {
      ASSERT_GE(facets.size(), 3u) << name;
      ++checked;
      const morph::ExactPlane a = plane(facets[0]), b = plane(facets[1]);
      std::size_t third = 2;
      while (third < facets.size() && !morph::vertex_exists(a, b, plane(facets[third]))) ++third;
      ASSERT_LT(third, facets.size()) << name;
      const morph::ExactPlane c = plane(facets[third]);
      for (int f : facets)
        EXPECT_EQ(morph::limit_side_at_vertex(a, b, c, plane(f)), 0) << name << " vertex " << v;
    }
    EXPECT_GT(checked, 0) << name;
  }
}

TEST(Quantize, SweepPlanesPassExactlyThroughTheirVertices) {
  std::mt19937_64 rng(18);
  // Moves of a few mm: a silhouette normal e × m (reduced) fits 52 bits while |e|·|m| stays
  // below ~2^52 grid steps² (256 mm² on the 2^-22 grid); longer ones keep the doubles (below).
  std::uniform_real_distribution<double> coordinate(-40, 40), step(-3, 3);
  for (const auto& [name, tool] : tools()) {
    const morph::ToolPolytope built = morph::tool_polytope(tool.profile, 0.004);
    const morph::SweepPolytopeBuilder sweeps(built.polytope);
    const int grid = built.grid_exponent;
    std::vector<std::pair<Vector3d, Vector3d>> moves = {{Vector3d(0, 0, 0), Vector3d(10, 0, 0)},
                                                        {Vector3d(0, 0, 5), Vector3d(0, 0, -5)},
                                                        {Vector3d(48, 16, 8), Vector3d(10, 16, 6)},
                                                        {Vector3d(1, 2, 3), Vector3d(1.3, -7.1, 2.2)}};
    for (int k = 0; k < 6; ++k) {
      const Vector3d from(coordinate(rng), coordinate(rng), coordinate(rng));
      moves.emplace_back(from, from + Vector3d(step(rng), step(rng), step(rng)));
    }
    for (auto [from, to] : moves) {
      from = morph::snap_to_grid(from, grid);
      to = morph::snap_to_grid(to, grid);
      // The polytope's facets (silhouette parallelograms among them) hold their vertices exactly.
      expect_exact_facets(sweeps(from, to), grid, name);
      const std::vector<morph::Halfspace> halfspaces = sweeps.halfspaces(from, to);
      for (const morph::Halfspace& h : halfspaces) EXPECT_TRUE(h.exact.set()) << name;
    }
    // A long generic move along a long tool edge: the planes that do not fit keep the doubles;
    // the others are exact and hold their vertices.
    const Vector3d far_from = morph::snap_to_grid(Vector3d(-37.3, 21.9, 13.1), grid),
                   far_to = morph::snap_to_grid(Vector3d(38.1, -35.7, -29.3), grid);
    const morph::ConvexPolytope far = sweeps(far_from, far_to);
    for (const morph::PolytopeFacet& facet : far.facets)
      for (int v : facet.loop)
        if (facet.exact.set()) {
          EXPECT_TRUE(facet.exact.value_at(*morph::grid_point(far.vertices[v], grid)) == 0);
        }
    // Ends off the grid: the sweep has the doubles alone.
    for (const morph::Halfspace& h : sweeps.halfspaces(Vector3d(0.1, 0, 0), Vector3d(3, 1, 0)))
      EXPECT_FALSE(h.exact.set()) << name;
  }
}

TEST(Quantize, SilhouettePlanesOfTwoMovesMeetExactlyAtTheSharedRingVertex) {
  // tool_tapered's needles: a ramp and a level move cut the tip ring's edge by their silhouette
  // planes; both pass exactly through the edge's ends, so the two planes and the ring's facets
  // meet in those points exactly.
  const morph::ToolPolytope built = morph::tool_polytope(morph::tapered_tool(1, 2, 5.5).profile, 0.004);
  const morph::SweepPolytopeBuilder sweeps(built.polytope);
  const int grid = built.grid_exponent;
  const Vector3d joint = morph::snap_to_grid(Vector3d(10, 16, 6), grid);
  const Vector3d ramp_start(48, 16, 8), level_end(-8, 16, 6);
  int shared = 0;
  for (const auto& [from, to] : {std::pair{ramp_start, joint}, std::pair{joint, level_end}}) {
    const auto [a, b] = morph::SweepPolytopeBuilder::ordered(from, to);
    for (const morph::SweepPolytopeBuilder::Edge& e : sweeps.edges()) {
      const morph::Halfspace h = sweeps.silhouette_plane(e, a, b - a);
      if (!h.exact.set()) continue;
      for (int v : {e.from, e.to}) {
        for (const Vector3d& at : {a, b}) {
          const auto p = morph::grid_point(built.polytope.vertices[v] + at, grid);
          ASSERT_TRUE(p);
          EXPECT_TRUE(h.exact.value_at(*p) == 0);
          ++shared;
        }
      }
    }
  }
  EXPECT_GT(shared, 0);
}

// The integer predicates against cpp_int.
cpp_int big(__int128 v) {
  const bool negative = v < 0;
  unsigned __int128 m = negative ? -static_cast<unsigned __int128>(v) : static_cast<unsigned __int128>(v);
  cpp_int out = static_cast<std::uint64_t>(m >> 64);
  out <<= 64;
  out += static_cast<std::uint64_t>(m);
  return negative ? cpp_int(-out) : out;
}

int reference_det4(const std::array<morph::IntegerPlane, 4>& p) {
  cpp_int m[4][4];
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 3; ++c) m[r][c] = p[r].normal[c];
    m[r][3] = big(p[r].offset);
  }
  auto det3 = [&](int r0, int r1, int r2) {
    return cpp_int(m[r0][0] * (m[r1][1] * m[r2][2] - m[r1][2] * m[r2][1]) -
                   m[r0][1] * (m[r1][0] * m[r2][2] - m[r1][2] * m[r2][0]) +
                   m[r0][2] * (m[r1][0] * m[r2][1] - m[r1][1] * m[r2][0]));
  };
  const cpp_int det =
      -m[0][3] * det3(1, 2, 3) + m[1][3] * det3(0, 2, 3) - m[2][3] * det3(0, 1, 3) + m[3][3] * det3(0, 1, 2);
  return det.sign();
}

TEST(Quantize, IntegerPredicatesAgreeWithCppInt) {
  std::mt19937_64 rng(2026);
  int zeros = 0, cases = 0;
  for (int bits : {8, 20, 30, 42, 52}) {
    std::uniform_int_distribution<std::int64_t> normal(-(std::int64_t{1} << bits) + 1,
                                                       (std::int64_t{1} << bits) - 1);
    std::uniform_int_distribution<std::int64_t> coordinate(-(std::int64_t{1} << 40), std::int64_t{1} << 40);
    for (int trial = 0; trial < 400; ++trial) {
      // Random planes through random grid points; every fourth set through one common point
      // (det 0), every eighth with two coincident or parallel normals.
      const morph::GridPoint common{coordinate(rng), coordinate(rng), coordinate(rng)};
      std::array<morph::IntegerPlane, 4> planes;
      for (auto& p : planes) {
        p.normal = {normal(rng), normal(rng), normal(rng)};
        const morph::GridPoint through =
            trial % 4 == 0 ? common : morph::GridPoint{coordinate(rng), coordinate(rng), coordinate(rng)};
        p.offset = 0;
        p.offset = p.value_at(through);
      }
      if (trial % 8 == 1) planes[3].normal = planes[1].normal;
      if (trial % 8 == 3) planes[2] = planes[0].negated();
      const std::array<const morph::IntegerPlane*, 4> pointers{&planes[0], &planes[1], &planes[2],
                                                               &planes[3]};
      const int want = reference_det4(planes);
      zeros += want == 0;
      ++cases;
      EXPECT_EQ(morph::exact::integer_det4_sign(pointers), want) << bits << " bits, trial " << trial;
      for (auto width :
           {morph::exact::Width::Bits256, morph::exact::Width::Bits512, morph::exact::Width::Unbounded})
        EXPECT_EQ(morph::exact::integer_det4_sign(pointers, width), want);
      // The minors, through the double rows of exact_determinant too.
      cpp_int n[3][3];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) n[r][c] = planes[r].normal[c];
      const cpp_int minor = n[0][0] * (n[1][1] * n[2][2] - n[1][2] * n[2][1]) -
                            n[0][1] * (n[1][0] * n[2][2] - n[1][2] * n[2][0]) +
                            n[0][2] * (n[1][0] * n[2][1] - n[1][1] * n[2][0]);
      EXPECT_EQ(morph::exact::integer_minor_sign(planes[0], planes[1], planes[2]), minor.sign());
      // The predicates' double rows (offset split in two doubles) give the same determinant.
      std::array<morph::exact::Row, 4> rows;
      std::array<double, 4> low;
      for (int r = 0; r < 4; ++r) {
        const auto high = static_cast<double>(planes[r].offset);
        low[r] = std::ldexp(static_cast<double>(planes[r].offset - static_cast<__int128>(high)), -22);
        rows[r] = {double(planes[r].normal[0]), double(planes[r].normal[1]), double(planes[r].normal[2]),
                   std::ldexp(high, -22)};
      }
      EXPECT_EQ(morph::exact::ExactRows(rows, 4, low).det4_sign(), want) << bits << " bits, trial " << trial;
    }
  }
  EXPECT_GT(zeros, cases / 5);  // the degenerate sets are there
  // A tier narrower than the bound throws.
  morph::IntegerPlane wide;
  wide.normal = {std::int64_t{1} << 50, 3, 5};
  wide.offset = static_cast<__int128>(1) << 100;
  EXPECT_THROW(morph::exact::integer_det4_sign({&wide, &wide, &wide, &wide}, morph::exact::Width::Bits128),
               std::logic_error);
}

TEST(Quantize, OffsetPartsAreTheNearestDoubleAndTheRemainder) {
  std::mt19937_64 rng(18);
  int ties = 0;
  for (int length = 0; length <= 120; ++length)
    for (int trial = 0; trial < 200; ++trial) {
      unsigned __int128 m = (static_cast<unsigned __int128>(rng()) << 64) | rng();
      m = length == 0 ? 0 : (m >> (128 - length)) | (static_cast<unsigned __int128>(1) << (length - 1));
      if (trial % 4 == 1 && length > 54) {  // exactly halfway between two doubles
        const int shift = length - 53;
        m = (m >> shift << shift) | (static_cast<unsigned __int128>(1) << (shift - 1));
        ++ties;
      }
      for (const __int128 v : {static_cast<__int128>(m), -static_cast<__int128>(m)}) {
        const auto [high, low] = morph::offset_parts(v);
        const auto want = static_cast<double>(v);
        EXPECT_EQ(high, want) << length;
        if (length <= 106) {
          EXPECT_EQ(static_cast<__int128>(low), v - static_cast<__int128>(want)) << length;
          EXPECT_EQ(low, static_cast<double>(static_cast<__int128>(low)));  // exact
        }
      }
    }
  EXPECT_GT(ties, 1000);
}

TEST(Quantize, GridHelpers) {
  const int grid = morph::grid_exponent_for(0.004);
  EXPECT_LE(std::ldexp(1.0, grid), 0.004 * std::ldexp(1.0, -14));
  EXPECT_GT(std::ldexp(1.0, grid), 0.004 * std::ldexp(1.0, -16));
  const Vector3d x(1.2345678, -9.87654321, 0.3);
  const Vector3d snapped = morph::snap_to_grid(x, grid);
  EXPECT_LE((snapped - x).cwiseAbs().maxCoeff(), std::ldexp(0.5, grid));
  ASSERT_TRUE(morph::grid_point(snapped, grid));
  EXPECT_FALSE(morph::grid_point(x, grid));
  // A normal reduced by its gcd; one beyond 2^52 after reduction is refused.
  const auto plane = morph::plane_through({6, 9, 12}, {1, 1, 1}, grid);
  ASSERT_TRUE(plane);
  EXPECT_EQ(plane->normal, (morph::GridPoint{2, 3, 4}));
  EXPECT_TRUE(plane->offset == 9);
  EXPECT_FALSE(morph::plane_through({static_cast<__int128>(1) << 53, 1, 0}, {0, 0, 0}, grid));
  EXPECT_FALSE(morph::plane_through({0, 0, 0}, {0, 0, 0}, grid));
}

}  // namespace
