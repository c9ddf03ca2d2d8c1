// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>
#include <morph/aabb_tree.h>
#include <morph/sweep_distance.h>

#include <cmath>
#include <random>

#include "common/test_tools.h"

using Eigen::Vector3d;
using morph::Move;
using morph::MoveKind;
using morph::Tool;
using morph::ToolType;

namespace {

Tool sphere(double r) {
  return morphmill_test::sphere_tool(r);
}
Tool ballend(double r, double length) {
  return morphmill_test::ballend_tool(r, length);
}

Move line(const Vector3d& a, const Vector3d& b) {
  Move m;
  m.kind = MoveKind::Linear;
  m.start = a;
  m.end = b;
  m.tool = 1;
  return m;
}

// Quarter turn about +z (counter-clockwise) of radius 10 around the origin, rising by `rise`.
Move arc(double sweep, double rise) {
  Move m;
  m.kind = MoveKind::Arc;
  m.center = Vector3d::Zero();
  m.axis = Vector3d::UnitZ();
  m.start = Vector3d(10, 0, 0);
  m.sweep = sweep;
  m.end = Vector3d(10 * std::cos(sweep), 10 * std::sin(sweep), rise);
  m.tool = 1;
  return m;
}

// Dense sampling of the move parameter: an upper bound on the true minimum that converges to it.
double brute_force(const Tool& tool, const Move& m, const Vector3d& p, int samples = 200000) {
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= samples; ++i)
    best = std::min(best, morph::tool_signed_distance(tool, morph::point_at(m, double(i) / samples), p));
  return best;
}

}  // namespace

TEST(SweepDistance, SphereAlongSegmentIsACapsule) {
  const Tool tool = sphere(2.0);
  const Vector3d a(0, 0, 0), b(10, 0, 0);
  // Beside the middle: distance to the axis minus r.
  EXPECT_NEAR(morph::swept_signed_distance(tool, a, b, Vector3d(5, 3, 4)), 5.0 - 2.0, 1e-12);
  // Beyond the end: distance to the end point minus r.
  EXPECT_NEAR(morph::swept_signed_distance(tool, a, b, Vector3d(13, 4, 0)), 5.0 - 2.0, 1e-12);
  // On the axis inside: -r.
  EXPECT_NEAR(morph::swept_signed_distance(tool, a, b, Vector3d(7, 0, 0)), -2.0, 1e-12);
  // A degenerate segment is a ball.
  EXPECT_NEAR(morph::swept_signed_distance(tool, a, a, Vector3d(0, 0, 5)), 3.0, 1e-12);
}

TEST(SweepDistance, BallEndClosedCasesHorizontalSlot) {
  const Tool tool = ballend(3.0, 40.0);
  const Vector3d a(0, 0, 0), b(100, 0, 0);
  // Straight below the tip line: r below the ball centre line minus r.
  EXPECT_NEAR(morph::swept_signed_distance(tool, a, b, Vector3d(50, 0, -2)), 2.0, 1e-9);
  // Beside the body: horizontal distance minus r.
  EXPECT_NEAR(morph::swept_signed_distance(tool, a, b, Vector3d(50, 7, 20)), 4.0, 1e-9);
  // Above the flat top (ball centre at z=3, top at z=43).
  EXPECT_NEAR(morph::swept_signed_distance(tool, a, b, Vector3d(50, 0, 45)), 2.0, 1e-9);
  // Inside the body, nearest the side wall.
  EXPECT_NEAR(morph::swept_signed_distance(tool, a, b, Vector3d(50, 2, 20)), -1.0, 1e-9);
}

TEST(SweepDistance, BallEndMatchesDenseSamplingOnRampsAndPlunges) {
  const Tool tool = ballend(1.5, 10.0);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-6.0, 6.0);
  const Move moves[] = {line({0, 0, 0}, {5, 3, -2}), line({1, 1, 4}, {1, 1, -3}),
                        line({-2, 0, 1}, {4, 0, 1})};
  for (const Move& m : moves) {
    for (int k = 0; k < 60; ++k) {
      const Vector3d p(u(rng), u(rng), u(rng));
      const double exact = morph::swept_signed_distance(tool, m, p);
      const double sampled = brute_force(tool, m, p, 20000);
      // The sampled value is an upper bound within the sampling step of the minimum.
      EXPECT_LE(exact, sampled + 1e-12);
      EXPECT_GE(exact, sampled - morph::length(m) / 20000 - 1e-12);
    }
  }
}

TEST(SweepDistance, ArcAndHelixMatchDenseSampling) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-14.0, 14.0);
  for (const Tool& tool : {sphere(1.0), ballend(2.0, 8.0)}) {
    for (const Move& m : {arc(M_PI / 2, 0.0), arc(-1.5 * M_PI, 3.0), arc(4 * M_PI, -6.0)}) {
      for (int k = 0; k < 40; ++k) {
        const Vector3d p(u(rng), u(rng), 0.5 * u(rng));
        const double exact = morph::swept_signed_distance(tool, m, p);
        const double sampled = brute_force(tool, m, p, 100000);
        EXPECT_LE(exact, sampled + 1e-9);
        EXPECT_GE(exact, sampled - morph::length(m) / 100000 - 1e-9);
      }
    }
  }
}

// A nearest-sweep search passes the nearest value so far: below it a move's distance is the
// same value as without it, at or above it some value no less than it.
TEST(SweepDistance, AMoveWithACutoffIsTheSameBelowItAndNoLessAbove) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-14.0, 14.0);
  const double inf = std::numeric_limits<double>::infinity();
  std::size_t below = 0, above = 0;
  for (const Tool& tool : {sphere(1.0), ballend(2.0, 8.0), morph::flat_tool(2.667, 13.8),
                           morph::conical_tool(3.0, 60.0, 10.0), morph::bullnose_tool(2.0, 0.5, 9.0)}) {
    for (const Move& m :
         {arc(M_PI / 2, 0.0), arc(-1.5 * M_PI, 3.0), arc(6 * M_PI, -4.3),
          line(Vector3d(-5, -3, 1), Vector3d(6, 4, -2)), line(Vector3d(1, 2, 4), Vector3d(1, 2, -3))}) {
      for (int k = 0; k < 30; ++k) {
        const Vector3d p(u(rng), u(rng), 0.5 * u(rng));
        const double d = morph::swept_signed_distance(tool, m, p);
        EXPECT_EQ(morph::swept_signed_distance(tool, m, p, inf), d);
        for (double cutoff : {d - 0.5, d - 1e-9, d, d + 1e-9, d + 0.5}) {
          const double r = morph::swept_signed_distance(tool, m, p, cutoff);
          if (d < cutoff) {
            EXPECT_EQ(r, d) << "cutoff " << cutoff;
            ++below;
          } else {
            EXPECT_GE(r, cutoff);
            ++above;
          }
        }
        // And the value itself is the minimum along the arc (dense sampling bounds it).
        if (k % 10 == 0) {
          const double sampled = brute_force(tool, m, p, 50000);
          EXPECT_LE(d, sampled + 1e-9);
          EXPECT_GE(d, sampled - morph::length(m) / 50000 - 1e-9);
        }
      }
    }
  }
  EXPECT_GT(below, 0u);
  EXPECT_GT(above, 0u);
}

TEST(SweepDistance, SweptBoundsContainTheSweep) {
  const Tool tool = ballend(2.0, 8.0);
  const Move m = arc(-1.5 * M_PI, 3.0);
  const Eigen::AlignedBox3d box = morph::swept_bounds(tool, m);
  for (int i = 0; i <= 1000; ++i) {
    const Vector3d c = morph::point_at(m, i / 1000.0);
    for (const Vector3d& offset : {Vector3d(2, 0, 0), Vector3d(-2, 0, 0), Vector3d(0, 2, 0),
                                   Vector3d(0, -2, 0), Vector3d(0, 0, 0), Vector3d(0, 0, 10)})
      EXPECT_TRUE(box.contains(c + offset));
  }
}

TEST(ErosionField, MatchesBruteForceOverManyMoves) {
  morph::Job job;
  job.tools[1] = sphere(1.5);
  job.stock.type = morph::StockType::Box;
  job.stock.box = Eigen::AlignedBox3d(Vector3d(0, 0, 0), Vector3d(40, 30, 10));
  morph::Path path;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ux(-5, 45), uy(-5, 35), uz(5, 12);
  Vector3d prev(ux(rng), uy(rng), uz(rng));
  for (int i = 0; i < 300; ++i) {
    const Vector3d next(ux(rng), uy(rng), uz(rng));
    path.moves.push_back(line(prev, next));
    prev = next;
  }
  job.paths.push_back(path);
  const morph::ErosionField field(job);
  std::uniform_real_distribution<double> px(-8, 48), py(-8, 38), pz(-3, 14);
  for (int k = 0; k < 500; ++k) {
    const Vector3d p(px(rng), py(rng), pz(rng));
    double brute = std::numeric_limits<double>::infinity();
    int brute_move = -1;
    for (std::size_t i = 0; i < job.paths[0].moves.size(); ++i) {
      const double d = morph::swept_signed_distance(job.tools[1], job.paths[0].moves[i], p);
      if (d < brute) {
        brute = d;
        brute_move = static_cast<int>(i);
      }
    }
    int nearest = -2;
    EXPECT_DOUBLE_EQ(field.sweep_distance(p, &nearest), brute);
    // Consecutive moves tie at their shared end point, so compare the distance of the move
    // reported, not its index.
    ASSERT_GE(nearest, 0);
    EXPECT_DOUBLE_EQ(morph::swept_signed_distance(job.tools[1], job.paths[0].moves[nearest], p),
                     morph::swept_signed_distance(job.tools[1], job.paths[0].moves[brute_move], p));
    EXPECT_DOUBLE_EQ(field.value(p), std::max(morph::analytic_signed_distance(job.stock, p), -brute));
  }
}

// A fine raster: 0.01 mm steps along x (one run), then a turn, then steps along a line that
// is collinear only to rounding (not joined), with a V-bit whose distance is a 1-D minimisation.
// The field must equal the brute-force minimum over the moves, and name a move whose sweep is
// the nearest.
TEST(ErosionField, FineCollinearStepsGiveTheSameFieldAsTheirMoves) {
  morph::Job job;
  job.tools[1] = morph::conical_tool(2.0, 90.0, 6.0);
  job.tools[1].number = 1;
  job.stock.type = morph::StockType::Box;
  job.stock.box = Eigen::AlignedBox3d(Vector3d(0, 0, 0), Vector3d(10, 10, 5));
  morph::Path path;
  Vector3d prev(1, 2, 4.2);
  for (int i = 0; i < 400; ++i) {
    const Vector3d next(1 + 0.01 * (i + 1), 2, 4.2);
    path.moves.push_back(line(prev, next));
    prev = next;
  }
  const Vector3d direction = Vector3d(0.3, 1, -0.1).normalized();
  for (int i = 0; i < 50; ++i) {
    const Vector3d next = prev + 0.03 * direction;
    path.moves.push_back(line(prev, next));
    prev = next;
  }
  job.paths.push_back(path);
  const morph::ErosionField field(job);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> px(-1, 8), py(0, 6), pz(1.5, 5.5);
  for (int k = 0; k < 200; ++k) {
    const Vector3d p(px(rng), py(rng), pz(rng));
    double brute = std::numeric_limits<double>::infinity();
    for (const Move& m : job.paths[0].moves)
      brute = std::min(brute, morph::swept_signed_distance(job.tools[1], m, p));
    int nearest = -2;
    const double d = field.sweep_distance(p, &nearest);
    EXPECT_NEAR(d, brute, 1e-9) << p.transpose();
    ASSERT_GE(nearest, 0);
    EXPECT_NEAR(morph::swept_signed_distance(job.tools[1], job.paths[0].moves[nearest], p), brute, 1e-9)
        << p.transpose() << " move " << nearest;
  }
}

TEST(AabbTree, OverlapQueryFindsExactlyTheOverlappingBoxes) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 100), s(0.1, 8);
  std::vector<Eigen::AlignedBox3d> boxes;
  for (int i = 0; i < 2000; ++i) {
    const Vector3d lo(u(rng), u(rng), u(rng));
    boxes.emplace_back(lo, lo + Vector3d(s(rng), s(rng), s(rng)));
  }
  const morph::AabbTree tree(boxes);
  for (int k = 0; k < 200; ++k) {
    const Vector3d lo(u(rng), u(rng), u(rng));
    const Eigen::AlignedBox3d query(lo, lo + Vector3d(s(rng), s(rng), s(rng)));
    std::vector<std::uint32_t> found;
    tree.for_each_overlapping(query, [&](std::uint32_t i) { found.push_back(i); });
    std::sort(found.begin(), found.end());
    std::vector<std::uint32_t> expected;
    for (std::uint32_t i = 0; i < boxes.size(); ++i)
      if (boxes[i].intersects(query)) expected.push_back(i);
    EXPECT_EQ(found, expected);
  }
}

TEST(SweepDistance, BallEndBelowTheBallCentresIsTheCapsule) {
  // Below the lowest ball centre the shortcut applies; the full minimisation must agree.
  const Tool tool = ballend(2.5, 12.0);
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> u(-8.0, 8.0);
  const Move m = line({-3, 1, 0.5}, {4, -2, -1.5});
  for (int k = 0; k < 400; ++k) {
    const Vector3d p(u(rng), u(rng), -1.5 + 2.5 - std::abs(u(rng)));
    const double sampled = brute_force(tool, m, p, 20000);
    const double exact = morph::swept_signed_distance(tool, m, p);
    EXPECT_LE(exact, sampled + 1e-12);
    EXPECT_GE(exact, sampled - morph::length(m) / 20000 - 1e-12);
  }
}
