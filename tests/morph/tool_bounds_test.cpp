// SPDX-License-Identifier: Apache-2.0
#include <morph/sweep_polytope.h>
#include <morph/tool_bounds.h>
#include <morph/tool_polytope.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "morph/tool_shapes_support.h"

namespace {

using Eigen::Vector3d;

constexpr double kDeviation = 0.004;

// Roughly even unit directions (a Fibonacci sphere).
std::vector<Vector3d> directions(int count) {
  std::vector<Vector3d> out;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int k = 0; k < count; ++k) {
    const double z = 1.0 - 2.0 * (k + 0.5) / count, r = std::sqrt(1.0 - z * z);
    out.emplace_back(r * std::cos(golden * k), r * std::sin(golden * k), z);
  }
  return out;
}

TEST(ToolBounds, InnerBoundsLieInsideAndOuterBoundsHoldEveryShape) {
  for (const auto& [name, tool] : morph_test::every_tool_shape()) {
    SCOPED_TRACE(name);
    const morph::ConvexPolytope p = morph::tool_polytope(tool.profile, kDeviation).polytope;
    const morph::ToolBounds b = morph::tool_bounds(p);
    const Vector3d c(0.0, 0.0, b.centre_height);
    EXPECT_GT(b.inner_radius, 0.0);
    for (const Vector3d& d : directions(400)) EXPECT_LE(p.plane_value(c + b.inner_radius * d), 1e-12);
    for (int k = 0; k <= 20; ++k)
      for (int s = 0; s < 64; ++s) {
        const double z = b.centre_height + (b.top - b.centre_height) * k / 20.0,
                     angle = 2.0 * M_PI * s / 64.0;
        EXPECT_LE(p.plane_value(
                      Vector3d(b.cylinder_radius * std::cos(angle), b.cylinder_radius * std::sin(angle), z)),
                  1e-12);
      }
    for (const Vector3d& v : p.vertices) {
      EXPECT_LE(v.head<2>().norm(), b.max_radius + 1e-12);
      if (v.z() <= b.centre_height) {
        EXPECT_LE((v - c).norm(), b.outer_radius + 1e-12);
      }
    }
  }
}

// Closed forms for the ball end of radius r: the inscribed ball and the shank's cylinder are
// the ball end's within the deviation, and so is the largest radius. The polytope's inscribed
// radius is flat (to 1e-9) from a little above the ball's centre up the shank; the lowest such
// centre is taken, within 2% of r above the ball's, and the outer ball reaches down to the tip.
TEST(ToolBounds, TheBallEndsBoundsAreItsBallAndShankWithinTheDeviation) {
  const double r = 1.5875;
  const morph::ToolBounds b =
      morph::tool_bounds(morph::tool_polytope(morph::ball_tool(r, 10.0).profile, kDeviation).polytope);
  EXPECT_NEAR(b.inner_radius, r, kDeviation);
  EXPECT_NEAR(b.cylinder_radius, r, kDeviation);
  EXPECT_NEAR(b.max_radius, r, kDeviation);
  EXPECT_GE(b.centre_height, r - kDeviation);
  EXPECT_LE(b.centre_height, 1.02 * r);
  EXPECT_NEAR(b.outer_radius, b.centre_height - b.bottom, kDeviation);
}

// Balls the bounds call inside have every sampled point inside the sweep polytope (by its
// halfspaces); balls they call apart have none; and both proofs fire often near a sweep.
TEST(ToolBounds, SweptBoundsProveInsideAndApartSoundlyAndOften) {
  std::mt19937 random(18);
  const std::vector<Vector3d> ball_points = [] {
    std::vector<Vector3d> points{Vector3d::Zero()};
    for (const Vector3d& d : directions(60)) {
      points.push_back(d);
      points.push_back(0.5 * d);
    }
    return points;
  }();
  const std::vector<Vector3d> motions{Vector3d(7, 0, 0), Vector3d(3, 2, -1.5), Vector3d(0, 0, -5),
                                      Vector3d(0.4, -0.2, 4)};
  for (const auto& [name, tool] : morph_test::every_tool_shape()) {
    const morph::SweepPolytopeBuilder sweeps(morph::tool_polytope(tool.profile, kDeviation).polytope);
    const morph::ToolBounds b = morph::tool_bounds(sweeps.tool());
    const Eigen::AlignedBox3d tool_box = sweeps.tool().bounds();
    for (const Vector3d& v : motions) {
      SCOPED_TRACE(name + " motion " + std::to_string(v.x()) + "," + std::to_string(v.y()) + "," +
                   std::to_string(v.z()));
      const Vector3d a(1.0, -2.0, 0.5), e = a + v;
      const morph::ConvexPolytope sweep = sweeps(a, e);
      Eigen::AlignedBox3d box = sweep.bounds();
      box.min().array() -= 1.0;
      box.max().array() += 1.0;
      std::uniform_real_distribution<double> radius(0.0, 0.1 * tool_box.diagonal().norm());
      int inside = 0, apart = 0, capsules_apart = 0, inner_boxes_skip = 0, points_inside_somewhere = 0;
      for (int k = 0; k < 1500; ++k) {
        const Vector3d centre = box.sample();
        const double rho = radius(random);
        const bool in = morph::ball_inside_sweep(b, a, e, centre, rho);
        const bool out = morph::ball_misses_sweep(b, a, e, centre, rho);
        ASSERT_FALSE(in && out);
        // The fused test gives both proofs' verdicts, bit for bit.
        EXPECT_EQ(morph::ball_against_sweep(b, a, e, centre, rho), in    ? morph::BallVerdict::Inside
                                                                   : out ? morph::BallVerdict::Misses
                                                                         : morph::BallVerdict::Unknown);
        // The inner box holds every ball proven inside, whichever end comes first.
        const Eigen::AlignedBox3d ball_box(centre.array() - rho, centre.array() + rho);
        if (in) {
          EXPECT_TRUE(morph::inner_box(b, a, e).contains(ball_box));
          EXPECT_TRUE(morph::inner_box(b, e, a).contains(ball_box));
        }
        inner_boxes_skip += !morph::inner_box(b, a, e).contains(ball_box);
        for (const Vector3d& q : ball_points) {
          if (in) {
            EXPECT_LE(sweep.plane_value(centre + rho * q), 1e-12);
          }
          if (out) {
            EXPECT_GT(sweep.plane_value(centre + rho * q), 0.0);
          }
        }
        inside += in;
        apart += out;
        // Points: some proven inside by the batch test exactly when by the test of each.
        std::vector<Vector3d> points;
        for (std::size_t q = 0; q < 6; ++q)
          points.push_back(centre + rho * ball_points[(k + 7 * q) % ball_points.size()]);
        EXPECT_EQ(morph::any_point_inside_sweep(b, a, e, points),
                  std::any_of(points.begin(), points.end(),
                              [&](const Vector3d& x) { return morph::ball_inside_sweep(b, a, e, x, 0.0); }));
        points_inside_somewhere += morph::any_point_inside_sweep(b, a, e, points);
        // A capsule from the centre along a random direction: apart means no sampled point of it
        // lies in the sweep.
        const Vector3d to = centre + 3.0 * rho * directions(7)[k % 7];
        if (k % 5 == 0 && morph::capsule_misses_sweep(b, a, e, centre, to, rho)) {
          ++capsules_apart;
          for (int s = 0; s <= 5; ++s)
            for (const Vector3d& q : ball_points)
              EXPECT_GT(sweep.plane_value(centre + 0.2 * s * (to - centre) + rho * q), 0.0);
        }
      }
      EXPECT_GT(capsules_apart, name.rfind("tapered", 0) == 0 ? 3 : 10);
      EXPECT_GT(inner_boxes_skip, 300);  // and it spares the test for many that are not
      EXPECT_GT(inside, 50);
      EXPECT_GT(points_inside_somewhere, inside);  // a point inside is proven more often than a ball
      // A ball and a cylinder bound a taper loosely (the outer ball holds all below the widest
      // inscribed ball, high up the cone), so its proofs of "apart" are rarer.
      EXPECT_GT(apart, name.rfind("tapered", 0) == 0 ? 30 : 150);
    }
  }
}

}  // namespace
