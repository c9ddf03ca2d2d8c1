// SPDX-License-Identifier: Apache-2.0
#include <morph/quantize.h>
#include <morph/sweep_polytope.h>
#include <morph/tool_polytope.h>

#include <gtest/gtest.h>

#include <cmath>

#include "morph/tool_shapes_support.h"

namespace {

using Eigen::Vector3d;

// ∫ over θ in [0, 2π] of |A cos θ + B|, in closed form.
double absolute_cosine_integral(double A, double B) {
  A = std::abs(A);
  if (std::abs(B) >= A) return 2.0 * M_PI * std::abs(B);
  const double alpha = std::acos(-B / A);
  return 4.0 * std::sqrt(A * A - B * B) + B * (4.0 * alpha - 2.0 * M_PI);
}

// Area of the exact tool's shadow on the plane normal to the unit u, by Cauchy's formula
// ½∫|n·u| dA over the surface of revolution: θ in closed form, the profile by the midpoint rule
// (4000 steps per piece).
double exact_projected_area(const morph::ToolProfile& profile, const Vector3d& u) {
  const double uh = std::hypot(u.x(), u.y()), uz = u.z();
  double sum = 0.0;
  const int steps = 4000;
  for (const morph::ProfilePiece& piece : profile.pieces()) {
    for (int i = 0; i < steps; ++i) {
      const double s0 = double(i) / steps, s1 = double(i + 1) / steps;
      auto at = [&](double s) -> Eigen::Vector2d {
        if (piece.kind == morph::ProfilePiece::Kind::Segment) return piece.from + s * (piece.to - piece.from);
        const double angle = piece.angle0 + s * (piece.angle1 - piece.angle0);
        return piece.centre +
               Eigen::Vector2d(piece.radii.x() * std::cos(angle), piece.radii.y() * std::sin(angle));
      };
      const Eigen::Vector2d p0 = at(s0), p1 = at(s1), mid = at(0.5 * (s0 + s1));
      const Eigen::Vector2d d = p1 - p0;
      const double ds = d.norm();
      if (ds == 0.0) continue;
      const Eigen::Vector2d normal(d.y() / ds, -d.x() / ds);  // outward: right of travel
      sum += mid.x() * ds * absolute_cosine_integral(normal.x() * uh, normal.y() * uz);
    }
  }
  return 0.5 * sum;
}

double worst_plane_excess(const morph::ConvexPolytope& p) {
  double worst = -1.0;
  for (const Vector3d& v : p.vertices) worst = std::max(worst, p.plane_value(v));
  return worst;
}

double worst_off_plane(const morph::ConvexPolytope& p) {
  double worst = 0.0;
  for (const morph::PolytopeFacet& f : p.facets)
    for (int v : f.loop) worst = std::max(worst, std::abs(f.normal.dot(p.vertices[v]) - f.offset));
  return worst;
}

const std::vector<std::pair<std::string, Vector3d>>& motions() {
  static const std::vector<std::pair<std::string, Vector3d>> list{
      {"level along x", Vector3d(7.0, 0.0, 0.0)}, {"level oblique", Vector3d(5.0, 3.5, 0.0)},
      {"plunge", Vector3d(0.0, 0.0, -5.0)},       {"retract", Vector3d(0.0, 0.0, 4.0)},
      {"ramp", Vector3d(4.0, 4.0, -2.5)},         {"steep ramp", Vector3d(0.6, 0.3, -4.0)},
  };
  return list;
}

TEST(SweepPolytope, CauchyReferenceMatchesTheDesignNotesClosedForms) {
  const Vector3d level(1, 0, 0), vertical(0, 0, 1);
  const morph::Tool flat = morph::flat_tool(3.0, 12.0);
  EXPECT_NEAR(exact_projected_area(flat.profile, level), 2.0 * 3.0 * 12.0, 1e-6);
  EXPECT_NEAR(exact_projected_area(flat.profile, vertical), M_PI * 9.0, 1e-6);
  const double h = morph::cone_height(3.0, 60.0);
  const morph::Tool vbit = morph::conical_tool(3.0, 60.0, h);
  EXPECT_NEAR(exact_projected_area(vbit.profile, level), 3.0 * h, 1e-6);
  const morph::Tool ball = morph::ball_tool(1.5875, 10.0);
  EXPECT_NEAR(exact_projected_area(ball.profile, level), M_PI * 1.5875 * 1.5875 / 2.0 + 2.0 * 1.5875 * 10.0,
              1e-5);
  EXPECT_NEAR(exact_projected_area(ball.profile, vertical), M_PI * 1.5875 * 1.5875, 1e-5);
  // Oblique: a sphere's shadow is a disc whatever the direction.
  const morph::Tool sphere = morph::sphere_tool(2.0);
  EXPECT_NEAR(exact_projected_area(sphere.profile, Vector3d(0.6, 0.0, -0.8)), M_PI * 4.0, 1e-5);
}

TEST(SweepPolytope, EveryShapeAndMotionIsClosedConvexAndHasTheCavalieriVolume) {
  const double deviation = 0.004;
  for (const auto& [name, tool] : morph_test::every_tool_shape()) {
    const morph::ToolPolytope built = morph::tool_polytope(tool.profile, deviation);
    const morph::SweepPolytopeBuilder sweep_of(built.polytope);
    const Vector3d start(1.0, -2.0, 3.0);
    for (const auto& [motion_name, motion] : motions()) {
      SCOPED_TRACE(name + ", " + motion_name);
      const morph::ConvexPolytope sweep = sweep_of(start, start + motion);
      EXPECT_EQ(sweep.unmatched_edges(), 0u);
      EXPECT_LE(worst_plane_excess(sweep), 1e-11);
      EXPECT_LE(worst_off_plane(sweep), 1e-11);
      const double L = motion.norm();
      const Vector3d u = motion / L;
      // Exact for the polytope: V = V(P) + L·A⊥(P, u).
      const double polytope_form = built.polytope.volume() + L * built.polytope.projected_area(u);
      EXPECT_NEAR(sweep.volume(), polytope_form, 1e-10 * polytope_form);
      // The smooth tool's closed form, within the deviation over the sweep's surface.
      const double smooth_form = tool.profile.volume() + L * exact_projected_area(tool.profile, u);
      EXPECT_NEAR(sweep.volume(), smooth_form, deviation * sweep.area());
    }
  }
}

TEST(SweepPolytope, LevelFlatBottomAndPlungingCylinderAreSweptAsWholeFaces) {
  const morph::Tool flat = morph::flat_tool(3.0, 12.0);
  const morph::ToolPolytope built = morph::tool_polytope(flat.profile, 0.004);
  const morph::ConvexPolytope& tool = built.polytope;
  const morph::SweepPolytopeBuilder sweep_of(tool);
  // Level: one bottom face, the disc polygon plus its shadow width times the length.
  const Vector3d v(5.0, 3.5, 0.0);
  const morph::ConvexPolytope level = sweep_of(Vector3d::Zero(), v);
  int bottoms = 0;
  double bottom_area = 0.0;
  for (const morph::PolytopeFacet& f : level.facets)
    if (f.normal.z() == -1.0) {
      ++bottoms;
      bottom_area = morph::loop_area_vector(level.vertices, f.loop).norm();
    }
  EXPECT_EQ(bottoms, 1);
  const Vector3d across = Vector3d(-v.y(), v.x(), 0.0).normalized();
  double lo = 1e300, hi = -1e300;
  for (const Vector3d& p : tool.vertices) {
    lo = std::min(lo, p.dot(across));
    hi = std::max(hi, p.dot(across));
  }
  const double disc = morph::loop_area_vector(tool.vertices, tool.facets.front().loop).norm();
  EXPECT_NEAR(bottom_area, disc + v.norm() * (hi - lo), 1e-9);
  // Plunge: the bottom at the lower end, the top at the upper, one rectangle per sector, nothing else.
  const morph::ConvexPolytope plunge = sweep_of(Vector3d(0, 0, 2), Vector3d(0, 0, -3));
  EXPECT_EQ(plunge.facets.size(), static_cast<std::size_t>(built.sectors + 2));
  EXPECT_EQ(plunge.vertices.size(), static_cast<std::size_t>(2 * built.sectors));
  EXPECT_NEAR(plunge.bounds().min().z(), -3.0, 1e-12);
  EXPECT_NEAR(plunge.bounds().max().z(), 2.0 + 12.0, 1e-12);
}

TEST(SweepPolytope, ARetraceIsTheSamePolytopeAndAZeroMoveIsTheTool) {
  const morph::Tool ball = morph::ball_tool(1.5875, 25.4);
  const morph::ToolPolytope built = morph::tool_polytope(ball.profile, 0.004);
  const morph::SweepPolytopeBuilder sweep_of(built.polytope);
  const Vector3d a(10.1, 20.3, -4.7), b(12.9, 19.6, -5.3);
  const morph::ConvexPolytope there = sweep_of(a, b), back = sweep_of(b, a);
  ASSERT_EQ(there.vertices.size(), back.vertices.size());
  ASSERT_EQ(there.facets.size(), back.facets.size());
  for (std::size_t i = 0; i < there.vertices.size(); ++i) EXPECT_EQ(there.vertices[i], back.vertices[i]);
  for (std::size_t f = 0; f < there.facets.size(); ++f) {
    EXPECT_EQ(there.facets[f].loop, back.facets[f].loop);
    EXPECT_EQ(there.facets[f].offset, back.facets[f].offset);
  }
  const morph::ConvexPolytope still = sweep_of(a, a);
  EXPECT_EQ(still.facets.size(), built.polytope.facets.size());
  EXPECT_NEAR(still.volume(), built.polytope.volume(), 1e-12 * still.volume());
}

// The culling takes a tool corner at an end two exact sweeps share as a point of the other sweep
// without looking at its faces (sweep_culling_halfspaces.cpp): every exact plane of an exact sweep
// holds the tool placed at both its ends. Checked in integers, ends on the grid.
TEST(SweepPolytope, AnExactSweepsPlanesHoldTheToolAtBothEndsExactly) {
  const double deviation = 0.004;
  for (const auto& [name, tool] : morph_test::every_tool_shape()) {
    const morph::ToolPolytope built = morph::tool_polytope(tool.profile, deviation);
    const morph::SweepPolytopeBuilder sweep_of(built.polytope);
    const int g = built.grid_exponent;
    std::vector<morph::GridPoint> corners;
    for (const Vector3d& v : built.polytope.vertices) corners.push_back(*morph::grid_point(v, g));
    const Vector3d start = morph::snap_to_grid(Vector3d(1.0, -2.0, 3.0), g);
    for (const auto& [motion_name, motion] : motions()) {
      SCOPED_TRACE(name + ", " + motion_name);
      const Vector3d end = morph::snap_to_grid(start + motion, g);
      ASSERT_TRUE(sweep_of.exact(start, end));
      int planes_touching_a_corner = 0;
      for (const morph::Halfspace& h : sweep_of.halfspaces(start, end)) {
        ASSERT_TRUE(h.exact.set());
        ASSERT_EQ(h.exact.grid_exponent, g);
        bool touches = false;
        for (const Vector3d& at : {start, end}) {
          const morph::GridPoint shift = *morph::grid_point(at, g);
          for (const morph::GridPoint& c : corners) {
            const morph::GridPoint x{c[0] + shift[0], c[1] + shift[1], c[2] + shift[2]};
            const __int128 value = h.exact.value_at(x);
            EXPECT_LE(value, 0) << "a tool corner outside its own sweep";
            touches = touches || value == 0;
          }
        }
        planes_touching_a_corner += touches;
      }
      // And each plane is a supporting plane of the placed tools: one that held them with room to
      // spare would be no face of the sweep.
      EXPECT_EQ(planes_touching_a_corner, static_cast<int>(sweep_of.halfspaces(start, end).size()));
    }
  }
}

}  // namespace
