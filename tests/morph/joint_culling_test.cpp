// SPDX-License-Identifier: Apache-2.0
#include <morph/joint_culling.h>
#include <morph/quantize.h>
#include <morph/sweep_polytope.h>
#include <morph/tool_polytope.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "morph/tool_shapes_support.h"

namespace {

using Eigen::Vector3d;
using morph::ConvexPolytope;
using morph::JointVerdict;

constexpr double kDeviation = 0.004;

Vector3d centroid(const ConvexPolytope& p, const morph::PolytopeFacet& f) {
  Vector3d c = Vector3d::Zero();
  for (int v : f.loop) c += p.vertices[v];
  return c / static_cast<double>(f.loop.size());
}

double facet_area(const ConvexPolytope& p, const morph::PolytopeFacet& f) {
  return morph::loop_area_vector(p.vertices, f.loop).norm();
}

// The verdicts of the two moves s -> j -> e, joined at j.
struct TwoMoves {
  ConvexPolytope first, second;
  std::vector<JointVerdict> first_verdicts, second_verdicts;
};

TwoMoves two_moves(const morph::SweepPolytopeBuilder& sweeps, const Vector3d& s, const Vector3d& j,
                   const Vector3d& e) {
  const morph::ConvexPolytope& tool = sweeps.tool();
  return {sweeps(s, j), sweeps(j, e), morph::joint_verdicts(tool, j - s, std::nullopt, e - j),
          morph::joint_verdicts(tool, e - j, j - s, std::nullopt)};
}

// Area and volume (divergence theorem) of the facets a verdict list keeps; facets past the
// list (silhouette parallelograms) are always kept.
void add_kept(const ConvexPolytope& p, const std::vector<JointVerdict>& verdicts, double& area,
              double& volume) {
  for (std::size_t f = 0; f < p.facets.size(); ++f) {
    if (f < verdicts.size() && morph::culled(verdicts[f])) continue;
    const double a = facet_area(p, p.facets[f]);
    area += a;
    volume += a * p.facets[f].offset / 3.0;
  }
}

// Two collinear moves sweep the one long sweep: the facets the joint keeps must be exactly its
// surface, so their area and enclosed volume are the long sweep's, and its volume is the
// Cavalieri closed form V(T) + L·A⊥(T, u). Directions are generic (no facet parallel to them:
// a facet swept whole would overlap its neighbour's on F + J, which is the clipping's work).
TEST(JointCulling, ACollinearContinuationKeepsExactlyTheOneLongSweep) {
  const std::vector<Vector3d> directions{Vector3d(4.0, 3.1, -2.5), Vector3d(0.6, 0.3, -4.0),
                                         Vector3d(3.0, -1.3, 0.7)};
  for (const auto& [name, tool] : morph_test::every_tool_shape()) {
    const morph::SweepPolytopeBuilder sweeps(morph::tool_polytope(tool.profile, kDeviation).polytope);
    const ConvexPolytope& t = sweeps.tool();
    for (const Vector3d& d : directions) {
      SCOPED_TRACE(name + " along " + std::to_string(d.x()) + "," + std::to_string(d.y()) + "," +
                   std::to_string(d.z()));
      const Vector3d s(1.0, 2.0, -3.0), j = s + d, e = s + 2.5 * d;
      const TwoMoves m = two_moves(sweeps, s, j, e);
      int first_end_cap = 0, second_start_cap = 0;
      for (std::size_t f = 0; f < t.facets.size(); ++f) {
        const double side = t.facets[f].normal.dot(d);
        ASSERT_GT(std::abs(side), 1e-9) << "direction not generic";
        EXPECT_EQ(m.first_verdicts[f], side > 0 ? JointVerdict::InsideNext : JointVerdict::Kept);
        EXPECT_EQ(m.second_verdicts[f], side < 0 ? JointVerdict::InsidePrevious : JointVerdict::Kept);
        first_end_cap += side > 0;
        second_start_cap += side < 0;
      }
      EXPECT_GT(first_end_cap, 0);
      EXPECT_GT(second_start_cap, 0);
      double area = 0.0, volume = 0.0;
      add_kept(m.first, m.first_verdicts, area, volume);
      add_kept(m.second, m.second_verdicts, area, volume);
      const ConvexPolytope whole = sweeps(s, e);
      const double length = (e - s).norm();
      const double cavalieri = t.volume() + length * t.projected_area(d.normalized());
      EXPECT_NEAR(area, whole.area(), 1e-10 * whole.area());
      EXPECT_NEAR(volume, whole.volume(), 1e-10 * whole.volume());
      EXPECT_NEAR(volume, cavalieri, 1e-10 * cavalieri);
    }
  }
}

// At a turn, what the joint culls must lie in the neighbour (every vertex, so the whole convex
// facet, by the neighbour's halfspaces), what it calls shared must be the neighbour's own facet
// or lie in its swept face, and the end cap facets it keeps must not lie inside the neighbour:
// the kept cap is exactly the lune n·v_i > 0 >= n·v_{i+1}.
TEST(JointCulling, AtATurnCulledCapsLieInTheNeighbourAndTheKeptLuneDoesNot) {
  const double degrees[] = {5.0, 45.0, 90.0, 135.0, 179.99, 180.0};
  for (const auto& [name, tool] : morph_test::every_tool_shape()) {
    const morph::SweepPolytopeBuilder sweeps(morph::tool_polytope(tool.profile, kDeviation).polytope);
    const double size = sweeps.tool().bounds().diagonal().norm();
    const double eps = 1e-12 * (size + 20.0);
    for (double deg : degrees)
      for (int plane = 0; plane < 2; ++plane) {
        SCOPED_TRACE(name + " turn " + std::to_string(deg) + (plane ? " in a vertical plane" : " level"));
        const double a = deg * M_PI / 180.0;
        const Vector3d in(6.0, 0.0, 0.0);
        const Vector3d out = plane ? Vector3d(6.0 * std::cos(a), 0.0, 6.0 * std::sin(a))
                                   : Vector3d(6.0 * std::cos(a), 6.0 * std::sin(a), 0.0);
        const Vector3d s(0.5, -0.25, -2.0), j = s + in, e = j + out;
        const TwoMoves m = two_moves(sweeps, s, j, e);
        int inside = 0, shared = 0, lune = 0;
        for (std::size_t f = 0; f < m.second_verdicts.size(); ++f) {
          const morph::PolytopeFacet& facet = m.second.facets[f];
          if (m.second_verdicts[f] == JointVerdict::Kept) continue;
          for (int v : facet.loop) EXPECT_LE(m.first.plane_value(m.second.vertices[v]), eps);
          if (m.second_verdicts[f] == JointVerdict::OwnedByPrevious) {
            ++shared;
            // The previous polytope has a facet in the same plane, facing the same way.
            bool coplanar = false;
            for (const morph::PolytopeFacet& g : m.first.facets)
              coplanar = coplanar || ((g.normal - facet.normal).norm() < 1e-12 &&
                                      std::abs(g.offset - facet.offset) < eps);
            EXPECT_TRUE(coplanar);
          } else {
            ++inside;
          }
        }
        for (std::size_t f = 0; f < m.first_verdicts.size(); ++f) {
          const morph::PolytopeFacet& facet = m.first.facets[f];
          if (m.first_verdicts[f] == JointVerdict::InsideNext) {
            for (int v : facet.loop) EXPECT_LE(m.second.plane_value(m.first.vertices[v]), eps);
          } else if (morph::motion_side(facet.normal, in) > 0) {
            ++lune;
            EXPECT_GE(m.second.plane_value(centroid(m.first, facet)), -eps);
          }
        }
        EXPECT_GT(inside + shared, 0);
        if (deg >= 179.99) {
          EXPECT_EQ(inside, 0);  // a reversal: all of P_{i+1}'s start cap is P_i's end cap
        }
        // Level turns keep a lune of the sides; a flat mill turning upward keeps none (its sides'
        // normals all face the new motion too, and its rim is an edge).
        if (deg >= 45.0 && plane == 0) {
          EXPECT_GT(lune, 0);
        }
      }
  }
}

// The sphere's lune between two half great circles at dihedral angle θ has area 2θr²: the kept
// end cap is that lune, to within the facets crossing its two bounding half circles (each of
// length πr; such a facet lies within its diameter d of the circle, so in a band of area 2πr·d)
// and the polytope's own area error. A fine deviation makes that bound small.
TEST(JointCulling, TheKeptCapOfASphereIsTheLuneOfTheTurnAngle) {
  const double r = 1.5;
  const morph::SweepPolytopeBuilder sweeps(
      morph::tool_polytope(morph::sphere_tool(r).profile, 5e-5).polytope);
  const ConvexPolytope& t = sweeps.tool();
  double diameter = 0.0;
  for (const morph::PolytopeFacet& f : t.facets)
    for (int u : f.loop)
      for (int w : f.loop) diameter = std::max(diameter, (t.vertices[u] - t.vertices[w]).norm());
  const double bound = 4.0 * M_PI * r * diameter + std::abs(t.area() - 4.0 * M_PI * r * r);
  for (double deg : {20.0, 60.0, 90.0, 150.0}) {
    const double a = deg * M_PI / 180.0;
    const Vector3d in = Vector3d(3.0, 1.0, -0.5).normalized() * 5.0;
    const Vector3d axis = in.cross(Vector3d(0.2, -0.4, 1.0)).normalized();
    const Vector3d out = Eigen::AngleAxisd(a, axis) * in;
    const Vector3d s(0.0, 0.0, 0.0), j = s + in, e = j + out;
    const TwoMoves m = two_moves(sweeps, s, j, e);
    double kept = 0.0;
    for (std::size_t f = 0; f < t.facets.size(); ++f)
      if (morph::motion_side(t.facets[f].normal, in) > 0 && !morph::culled(m.first_verdicts[f]))
        kept += facet_area(m.first, m.first.facets[f]);
    EXPECT_NEAR(kept, 2.0 * a * r * r, bound) << deg << "°";
    if (deg >= 60.0) {
      EXPECT_LT(bound, 0.15 * 2.0 * a * r * r) << "a bound that says something";
    }
  }
}

// Between exact sweeps (ends on the tool's grid) a start cap facet at the joint is culled at the
// previous polytope's rim too: every facet the exact verdicts cull has every vertex inside the
// previous polytope by its exact integer planes, the verdicts cull at least what the rounded-plane
// rule culls (strictly more for the curved tools), the end caps keep the rounded-plane verdicts,
// and a facet touching one swept by the previous motion is kept.
TEST(JointCulling, BetweenExactSweepsStartCapsAreCulledAtTheRimToo) {
  int more = 0;
  for (const auto& [name, tool] : morph_test::every_tool_shape()) {
    const morph::ToolPolytope quantized = morph::tool_polytope(tool.profile, kDeviation);
    const int grid = quantized.grid_exponent;
    const morph::SweepPolytopeBuilder sweeps(quantized.polytope);
    const morph::ConvexPolytope& shape = sweeps.tool();
    const morph::FacetsAround around = morph::facets_around(shape);
    const std::vector<std::vector<int>> at_vertex = morph::facets_at_vertices(shape);
    for (double deg : {30.0, 90.0, 150.0})
      for (bool axis : {false, true}) {
        SCOPED_TRACE(name + " turn " + std::to_string(deg) + (axis ? " from an axis move" : ""));
        const double a = deg * M_PI / 180.0;
        const Vector3d in = axis ? Vector3d(6.0, 0.0, 0.0) : Vector3d(6.0, 1.7, -0.9);
        const Vector3d out(6.0 * std::cos(a), 6.0 * std::sin(a), 0.4);
        const Vector3d s = morph::snap_to_grid(Vector3d(0.5, -0.25, -2.0), grid);
        const Vector3d j = morph::snap_to_grid(s + in, grid), e = morph::snap_to_grid(j + out, grid);
        ASSERT_TRUE(sweeps.exact(s, j) && sweeps.exact(j, e));
        const std::vector<JointVerdict> plain = morph::joint_verdicts(shape, e - j, j - s, std::nullopt);
        const std::vector<JointVerdict> rounded =
            morph::joint_verdicts_off_rim(shape, around, e - j, j - s, std::nullopt);
        const std::vector<JointVerdict> exact =
            morph::joint_verdicts_exact(shape, around, e - j, j - s, std::nullopt);
        const morph::ConvexPolytope first = sweeps(s, j);
        const std::optional<morph::GridPoint> joint = morph::grid_point(j, grid);
        ASSERT_TRUE(joint.has_value());
        for (std::size_t f = 0; f < shape.facets.size(); ++f) {
          if (morph::culled(rounded[f])) {
            EXPECT_EQ(exact[f], rounded[f]) << "facet " << f;
          }
          if (morph::culled(exact[f])) {
            EXPECT_EQ(exact[f], plain[f]) << "facet " << f;
          }
          more += morph::culled(exact[f]) && !morph::culled(rounded[f]);
          bool touches_swept = false;
          for (int v : shape.facets[f].loop)
            for (int g : at_vertex[v])
              touches_swept |= morph::motion_side(shape.facets[g].normal, j - s) == 0;
          if (touches_swept) {
            EXPECT_EQ(exact[f], JointVerdict::Kept) << "facet " << f;
          }
          if (!morph::culled(exact[f])) continue;
          for (int v : shape.facets[f].loop) {
            const std::optional<morph::GridPoint> x = morph::grid_point(shape.vertices[v] + j, grid);
            ASSERT_TRUE(x.has_value());
            for (const morph::PolytopeFacet& h : first.facets) {
              ASSERT_TRUE(h.exact.set());
              EXPECT_LE(h.exact.value_at(*x), 0) << "facet " << f << " vertex " << v;
            }
          }
        }
        // The end caps of the first move keep the rounded-plane verdicts.
        EXPECT_EQ(morph::joint_verdicts_exact(shape, around, j - s, std::nullopt, e - j),
                  morph::joint_verdicts_off_rim(shape, around, j - s, std::nullopt, e - j));
      }
  }
  EXPECT_GT(more, 0);
}

TEST(JointCulling, TheFacetsAroundAFacetAreThoseAtItsVerticesEachOnce) {
  for (const auto& [name, tool] : morph_test::every_tool_shape()) {
    SCOPED_TRACE(name);
    const morph::ConvexPolytope shape = morph::tool_polytope(tool.profile, 0.01).polytope;
    const morph::FacetsAround around = morph::facets_around(shape);
    ASSERT_EQ(around.start.size(), shape.facets.size() + 1);
    for (std::size_t f = 0; f < shape.facets.size(); ++f) {
      const std::vector<int> listed(around.facets.begin() + around.start[f],
                                    around.facets.begin() + around.start[f + 1]);
      // Each other facet g is listed exactly when it has a vertex of f among its own.
      for (std::size_t g = 0; g < shape.facets.size(); ++g) {
        bool shares = false;
        for (int v : shape.facets[f].loop)
          for (int w : shape.facets[g].loop) shares |= v == w;
        EXPECT_EQ(std::count(listed.begin(), listed.end(), static_cast<int>(g)), shares ? 1 : 0)
            << "facet " << f << ", facet " << g;
      }
    }
  }
}

TEST(JointCulling, OnlyStraightMovesOfOneToolMeetingBitForBitAreJoined) {
  const morph::SweepPolytopeBuilder sweeps(
      morph::tool_polytope(morph::sphere_tool(1.0).profile, kDeviation).polytope);
  morph::Move a, b;
  a.start = Vector3d(0, 0, 0);
  a.end = Vector3d(1, 0, 0);
  b.start = a.end;
  b.end = Vector3d(1, 1, 0);
  EXPECT_TRUE(morph::joined_at_joint(sweeps, a, b));
  morph::Move other_tool = b;
  other_tool.tool = 2;
  EXPECT_FALSE(morph::joined_at_joint(sweeps, a, other_tool));
  morph::Move gap = b;
  gap.start.x() = std::nextafter(1.0, 2.0);
  EXPECT_FALSE(morph::joined_at_joint(sweeps, a, gap));
  morph::Move zero = b;
  zero.end = zero.start;
  EXPECT_FALSE(morph::joined_at_joint(sweeps, a, zero));
  morph::Move arc = b;
  arc.kind = morph::MoveKind::Arc;
  EXPECT_FALSE(morph::joined_at_joint(sweeps, a, arc));
}

}  // namespace
