// SPDX-License-Identifier: Apache-2.0
#include <morph/tool_polytope.h>

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "morph/tool_shapes_support.h"

namespace {

using Eigen::Vector3d;

// Exact signed distance of the tool (tool point at the origin) at p.
double exact_distance(const morph::ToolProfile& profile, const Vector3d& p) {
  return profile.signed_distance(std::hypot(p.x(), p.y()), p.z() + profile.point_height());
}

// Largest |exact distance| over a 6 x 6 barycentric grid of every fan triangle of every facet:
// how far the polytope's surface strays from the tool's.
double polytope_to_tool(const morph::ConvexPolytope& polytope, const morph::ToolProfile& profile) {
  double worst = 0.0;
  const int n = 6;
  for (const morph::PolytopeFacet& facet : polytope.facets) {
    const Vector3d& a = polytope.vertices[facet.loop[0]];
    for (std::size_t t = 1; t + 1 < facet.loop.size(); ++t) {
      const Vector3d& b = polytope.vertices[facet.loop[t]];
      const Vector3d& c = polytope.vertices[facet.loop[t + 1]];
      for (int i = 0; i <= n; ++i)
        for (int j = 0; i + j <= n; ++j) {
          const Vector3d p = a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n);
          worst = std::max(worst, std::abs(exact_distance(profile, p)));
        }
    }
  }
  return worst;
}

// Largest distance from points of the exact surface (each piece sampled at 40 parameters, on
// meridians at every sector's vertex, middle and quarter angles) to the polytope's surface.
double tool_to_polytope(const morph::ToolPolytope& tool, const morph::ToolProfile& profile) {
  double worst = 0.0;
  const int per_piece = 40;
  for (const morph::ProfilePiece& piece : profile.pieces()) {
    for (int i = 0; i <= per_piece; ++i) {
      const double s = double(i) / per_piece;
      Eigen::Vector2d q;
      if (piece.kind == morph::ProfilePiece::Kind::Segment) {
        q = piece.from + s * (piece.to - piece.from);
      } else {
        const double angle = piece.angle0 + s * (piece.angle1 - piece.angle0);
        q = piece.centre +
            Eigen::Vector2d(piece.radii.x() * std::cos(angle), piece.radii.y() * std::sin(angle));
      }
      // Sectors 0 and 1 suffice: every sector is the same up to rotation.
      for (double k : {0.0, 0.25, 0.5, 0.75, 1.0}) {
        const double angle = 2.0 * M_PI * k / tool.sectors;
        const Vector3d p(q.x() * std::cos(angle), q.x() * std::sin(angle), q.y() - profile.point_height());
        worst = std::max(worst, morph::boundary_distance(tool.polytope, p));
      }
    }
  }
  return worst;
}

TEST(ToolPolytope, EveryShapeIsAClosedConvexPolytopeWithinTheDeviationBothWays) {
  for (double deviation : {0.004, 0.05}) {
    for (const auto& [name, tool] : morph_test::every_tool_shape()) {
      SCOPED_TRACE(name + " at " + std::to_string(deviation));
      const morph::ToolPolytope built = morph::tool_polytope(tool.profile, deviation);
      const morph::ConvexPolytope& p = built.polytope;
      EXPECT_EQ(p.unmatched_edges(), 0u);
      // Euler: V - E + F = 2 for a closed sphere-like surface.
      std::size_t edges = 0;
      for (const auto& f : p.facets) edges += f.loop.size();
      EXPECT_EQ(static_cast<long>(p.vertices.size()) - static_cast<long>(edges / 2) +
                    static_cast<long>(p.facets.size()),
                2);
      // Convex: every vertex on or below every facet plane.
      double above = -1.0;
      for (const Vector3d& v : p.vertices) above = std::max(above, p.plane_value(v));
      EXPECT_LE(above, 1e-12 * tool.profile.height());
      EXPECT_LE(polytope_to_tool(p, tool.profile), deviation);
      EXPECT_LE(tool_to_polytope(built, tool.profile), deviation);
      // Straddling: the volume error is about a sixth of the sagitta times the area (measured
      // 0.07-0.24 x deviation x area); an inscribed polytope would be off by about 1.2 x.
      EXPECT_LT(std::abs(p.volume() - tool.profile.volume()), 0.4 * deviation * p.area());
    }
  }
}

TEST(ToolPolytope, FlatEndsAreSingleFacetsAndLinesStayWhole) {
  const morph::Tool flat = morph::flat_tool(3.0, 12.0);
  const morph::ToolPolytope built = morph::tool_polytope(flat.profile, 0.004);
  // A cylinder: bottom and top N-gons and one rectangle per sector, nothing else.
  EXPECT_EQ(built.polytope.facets.size(), static_cast<std::size_t>(built.sectors + 2));
  EXPECT_EQ(built.meridian.size(), 4u);
  EXPECT_EQ(built.sectors % 4, 0);
  const double bottom = built.polytope.facets.front().normal.z();
  EXPECT_EQ(bottom, -1.0);
  // Ring angles are anchored to the frame: vertex 0 lies on the +x axis.
  EXPECT_EQ(built.polytope.vertices[0].y(), 0.0);
  EXPECT_GT(built.polytope.vertices[0].x(), 3.0);
}

// A pole (a ball's tip, a sphere's top and bottom) is a level N-gon cut off where it bulges by a
// chord's sagitta, not an apex with a fan of nearly level facets: two passes at one depth then
// share that facet's plane exactly (stress seed 89, case 9160, Erode2 below).
TEST(ToolPolytope, APoleIsOneLevelFacetWithinTheDeviation) {
  const double deviation = 0.004;
  for (const morph::Tool& tool : {morph::ball_tool(2.503, 17.0), morph::sphere_tool(1.5875)}) {
    const morph::ToolPolytope built = morph::tool_polytope(tool.profile, deviation);
    const auto& m = built.meridian;
    ASSERT_GE(m.size(), 4u);
    EXPECT_EQ(m[0].x(), 0.0);
    EXPECT_EQ(m[1].y(), m[0].y());  // level cap, not an apex
    EXPECT_EQ(m[m.size() - 2].y(), m.back().y());
    const double r = tool.profile.radius();
    // The cap straddles the pole: its plane within the deviation of the exact tip, the ring
    // beyond it, and only the pole's cap is level (one N-gon facet at each end).
    const double tip = -tool.profile.point_height();
    EXPECT_LT(m[0].y() - tip, deviation);
    EXPECT_GT(m[0].y() - tip, 0.0);
    EXPECT_GT(m[1].x(), 0.0);
    EXPECT_LT(m[1].x(), r);
    std::size_t level = 0;
    for (const morph::PolytopeFacet& f : built.polytope.facets) level += std::abs(f.normal.z()) == 1.0;
    EXPECT_EQ(level, 2u);
    EXPECT_EQ(built.polytope.facets.front().normal.z(), -1.0);
  }
}

TEST(ToolPolytope, FinerDeviationMeansMoreFacetsAndTheSagittaFixesTheSectorCount) {
  const morph::Tool ball = morph::ball_tool(1.5875, 25.4);
  const morph::ToolPolytope coarse = morph::tool_polytope(ball.profile, 0.04);
  const morph::ToolPolytope fine = morph::tool_polytope(ball.profile, 0.004);
  EXPECT_GT(fine.polytope.facets.size(), coarse.polytope.facets.size());
  // Half a sector's sagitta, half a meridian chord's and the grid's eighth make the deviation:
  // where the meridian bulges, the side of a sector is within 0.875 x deviation of its circle,
  // and the count is the least multiple of 4 that does it.
  const double r = 1.5875;
  EXPECT_LE(r * (1.0 - std::cos(M_PI / fine.sectors)), 0.875 * 0.004);
  EXPECT_GT(r * (1.0 - std::cos(M_PI / (fine.sectors - 4))), 0.875 * 0.004);
  // A meridian of lines only keeps the same sectors: its rings do not take the meridian's half
  // (error_budget.h: a coarser V-bit erased a thin pillar).
  for (const morph::Tool& straight : {morph::flat_tool(r, 25.4), morph::conical_tool(r, 60.0, 25.4)})
    EXPECT_EQ(morph::tool_polytope(straight.profile, 0.004).sectors, fine.sectors);
}

TEST(ToolPolytope, ItsSizeIsKnownWithoutBuildingIt) {
  for (double deviation : {0.004, 0.05}) {
    for (const auto& [name, tool] : morph_test::every_tool_shape()) {
      SCOPED_TRACE(name + " at " + std::to_string(deviation));
      const morph::ToolPolytope built = morph::tool_polytope(tool.profile, deviation);
      const morph::ToolPolytopeSize size = morph::tool_polytope_size(tool.profile, deviation);
      EXPECT_EQ(size.sectors, built.sectors);
      EXPECT_EQ(size.meridian_points, built.meridian.size());
      // Exact for pointed and rounded ends; a flat end's N-gon is counted as a fan of N.
      const std::size_t n = static_cast<std::size_t>(built.sectors);
      EXPECT_GE(size.facets, built.polytope.facets.size());
      EXPECT_LE(size.facets, built.polytope.facets.size() + 2 * (n - 1));
      EXPECT_EQ((size.facets - built.polytope.facets.size()) % (n - 1), 0u);
    }
  }
  const morph::Tool ball = morph::ball_tool(1.0, 5.0);
  EXPECT_THROW(morph::tool_polytope_size(ball.profile, 1e-12), morph::LimitError);
}

TEST(ToolPolytope, RejectsBadInput) {
  const morph::Tool ball = morph::ball_tool(1.0, 5.0);
  EXPECT_THROW(morph::tool_polytope(ball.profile, 0.0), morph::InputError);
  EXPECT_THROW(morph::tool_polytope(ball.profile, std::nan("")), morph::InputError);
  EXPECT_THROW(morph::tool_polytope(morph::ToolProfile(), 0.01), morph::InputError);
  EXPECT_THROW(morph::tool_polytope(ball.profile, 1e-12), morph::LimitError);
}

}  // namespace
