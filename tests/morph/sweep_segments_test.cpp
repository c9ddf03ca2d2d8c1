// SPDX-License-Identifier: Apache-2.0
// Generator 2's segments: straight runs joined and zero-length moves dropped only where the swept
// solid is the same, decided exactly on the grid; the count made without listing them agrees.
#include <morph/erode.h>
#include <morph/error_budget.h>
#include <morph/quantize.h>
#include <morph/sweep_polytope.h>
#include <morph/sweep_segments.h>
#include <morph/tool.h>
#include <morph/tool_polytope.h>
#include <morph/topology.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>

#include "common/test_jobs.h"

namespace {

using Eigen::Vector3d;

constexpr double kTolerance = 0.05;
const int kGrid = morph::grid_exponent_for(0.4 * kTolerance);

morph::Job job_through(const std::vector<Vector3d>& points) {
  return morphmill_test::box_polyline_job(Eigen::AlignedBox3d(Vector3d(0, 0, 0), Vector3d(20, 10, 5)),
                                          morph::ball_tool(1.0, 10.0), points, kTolerance);
}

std::vector<morph::SweepSegment> segments_of(const morph::Job& job) {
  return morph::sweep_segments(job, 0.4 * kTolerance, kGrid);
}

double counted(const morph::Job& job) {
  double total = 0;
  for (const auto& [tool, count] : morph::sweep_segment_counts(job, 0.4 * kTolerance, kGrid)) total += count;
  return total;
}

Vector3d snapped_at(const Vector3d& x, int grid) {
  return morph::snap_to_grid(x, grid);
}

Vector3d snapped(const Vector3d& x) {
  return morph::snap_to_grid(x, kGrid);
}

TEST(SweepSegments, AStraightRunIsOneSegmentFromItsFirstMove) {
  std::vector<Vector3d> points;
  for (int k = 0; k <= 50; ++k) points.emplace_back(2 + 0.1 * k, 5, 4.5);
  const morph::Job job = job_through(points);
  const std::vector<morph::SweepSegment> s = segments_of(job);
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].from, snapped(points.front()));
  EXPECT_EQ(s[0].to, snapped(points.back()));
  EXPECT_EQ(s[0].move, 0);
  EXPECT_EQ(s[0].line, job.paths[0].moves[0].line);
  EXPECT_EQ(counted(job), 1.0);
}

TEST(SweepSegments, TurnsReversalsAndAGridStepOffTheLineStaySeparate) {
  const Vector3d a(2, 5, 4.5), b(8, 5, 4.5);
  const double step = std::ldexp(1.0, kGrid);
  // A reversal sweeps the same solid too, but its second move is the retrace the joints decide:
  // only a continuation is joined.
  for (const Vector3d& c :
       {Vector3d(2, 5, 4.5), Vector3d(8, 9, 4.5), Vector3d(14, 5 + step, 4.5), Vector3d(14, 5, 4.5 + step)}) {
    const morph::Job job = job_through({a, b, c});
    EXPECT_EQ(segments_of(job).size(), 2u) << c.transpose();
    EXPECT_EQ(counted(job), 2.0) << c.transpose();
  }
  // Going on along the same axis-parallel line: joined.
  EXPECT_EQ(segments_of(job_through({a, b, Vector3d(14, 5, 4.5)})).size(), 1u);
  // A diagonal line on the grid: a, a + d, a + 3d join.
  const Vector3d d = Vector3d(3, 2, -1) * step * 1024;
  const Vector3d start = snapped(a);
  EXPECT_EQ(segments_of(job_through({start, start + d, start + 3 * d})).size(), 1u);
}

TEST(SweepSegments, ZeroLengthMovesGoWhereANeighbourCoversThem) {
  const Vector3d a(2, 5, 4.5), b(8, 5, 4.5), c(8, 9, 4.5);
  // At the start (replaced by the next), in a run (dropped, the run joins across it), at a corner.
  const morph::Job job = job_through({a, a, b, b, Vector3d(10, 5, 4.5), Vector3d(10, 5, 4.5), c});
  const std::vector<morph::SweepSegment> s = segments_of(job);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].from, snapped(a));
  EXPECT_EQ(s[0].to, snapped(Vector3d(10, 5, 4.5)));
  EXPECT_EQ(s[0].move, 1);  // the zero-length move 0 was replaced by move 1
  EXPECT_EQ(s[1].to, snapped(c));
  EXPECT_EQ(counted(job), 2.0);
  // A lone zero-length move is the tool placed once: kept.
  EXPECT_EQ(segments_of(job_through({a, a})).size(), 1u);
}

TEST(SweepSegments, ToolsAndArcsAreNotJoined) {
  morph::Job job = job_through({Vector3d(2, 5, 4.5), Vector3d(5, 5, 4.5), Vector3d(8, 5, 4.5)});
  job.tools.emplace(2, morph::ball_tool(0.5, 10.0));
  job.paths[0].moves[1].tool = 2;
  EXPECT_EQ(segments_of(job).size(), 2u);
  const std::map<int, double> per_tool = morph::sweep_segment_counts(job, 0.4 * kTolerance, kGrid);
  EXPECT_EQ(per_tool.at(1), 1.0);
  EXPECT_EQ(per_tool.at(2), 1.0);

  // A quarter arc then a line leaving along its end tangent: the chords stay as chords, and the
  // line is not joined to the last chord.
  morph::Move arc;
  arc.kind = morph::MoveKind::Arc;
  arc.center = Vector3d(10, 5, 4.5);
  arc.axis = Vector3d::UnitZ();
  arc.start = Vector3d(13, 5, 4.5);
  arc.end = Vector3d(10, 8, 4.5);
  arc.sweep = M_PI / 2;
  arc.tool = 1;
  morph::Move line;
  line.start = arc.end;
  line.end = Vector3d(4, 8, 4.5);
  line.tool = 1;
  morph::Job with_arc = job_through({Vector3d(13, 2, 4.5), Vector3d(13, 5, 4.5)});
  with_arc.paths[0].moves.push_back(arc);
  with_arc.paths[0].moves.push_back(line);
  const double chords = morph::chord_count(arc, 0.4 * kTolerance);
  EXPECT_EQ(segments_of(with_arc).size(), 2u + static_cast<std::size_t>(chords));
  EXPECT_EQ(counted(with_arc), 2.0 + chords);
}

TEST(SweepSegments, ARasterOfShortMovesErodesAsItsRowsDo) {
  // The hostile 10^4-move raster in small: rows of 0.1 mm moves, 0.1 mm apart, sweep exactly what
  // the rows as single moves sweep, so generator 2 builds the same surface from far fewer sweeps.
  std::vector<Vector3d> fine, rows;
  for (int r = 0; r < 6; ++r) {
    const double y = 3 + 0.1 * r;
    for (int k = 0; k <= 40; ++k) {
      const double x = 4 + 0.1 * (r % 2 == 0 ? k : 40 - k);
      fine.emplace_back(x, y, 4.9);
      if (k == 0 || k == 40) rows.emplace_back(x, y, 4.9);
    }
  }
  const morph::ErodeResult from_fine = morph::erode(job_through(fine));
  const morph::ErodeResult from_rows = morph::erode(job_through(rows));
  EXPECT_EQ(from_fine.stats.moves, fine.size() - 1);
  EXPECT_EQ(from_fine.stats.segments, rows.size() - 1);
  EXPECT_EQ(from_fine.mesh.vertices, from_rows.mesh.vertices);
  EXPECT_EQ(from_fine.mesh.triangles, from_rows.mesh.triangles);
  const morph::TopologyReport topology = morph::topology_report(from_fine.mesh);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_EQ(topology.components, 1u);
  EXPECT_LT(topology.volume, 20 * 10 * 5 - 0.3);  // it cut the rows (about 0.5 mm³)
}

TEST(SweepSegments, ErodeJoinsAStraightRunIntoOneSweep) {
  // A run of moves that go on straight is swept as its one segment [a, c]: the same surface.
  std::vector<Vector3d> fine;
  for (int k = 0; k <= 50; ++k) fine.emplace_back(2 + 0.1 * k, 5, 4.5);
  const morph::ErodeResult from_fine = morph::erode(job_through(fine));
  const morph::ErodeResult from_one = morph::erode(job_through({fine.front(), fine.back()}));
  EXPECT_EQ(from_fine.stats.moves, 50u);
  EXPECT_EQ(from_fine.stats.segments, 1u);
  EXPECT_EQ(from_fine.mesh.vertices, from_one.mesh.vertices);
  EXPECT_EQ(from_fine.mesh.triangles, from_one.mesh.triangles);
}

// Long moves in general directions (tapered_triangle_six_times_round(), test_jobs.h): their
// silhouette planes were rounded to doubles, and the rounding had to repair the surface.
struct Star {
  morph::Job job;
  morph::ErrorBudget budget;
  std::unique_ptr<morph::SweepPolytopeBuilder> builder;
  std::map<int, std::int64_t> largest_step;
};

Star tapered_star() {
  Star star;
  star.job = morphmill_test::tapered_triangle_six_times_round();
  star.budget = morph::error_budget(star.job, 0.01);
  star.builder = std::make_unique<morph::SweepPolytopeBuilder>(
      morph::tool_polytope(star.job.tools.begin()->second.profile, star.budget.tool).polytope);
  star.largest_step[star.job.tools.begin()->first] = star.builder->largest_exact_step();
  return star;
}

TEST(SettleSegmentEnds, LongMovesInGeneralDirectionsGetExactPlanesAndLapsStillMeet) {
  const Star star = tapered_star();
  const std::vector<morph::SweepSegment> before =
      morph::sweep_segments(star.job, star.budget.chords, star.budget.grid_exponent);
  ASSERT_EQ(before.size(), 18u);
  EXPECT_TRUE(std::any_of(before.begin(), before.end(),
                          [&](const morph::SweepSegment& s) { return !star.builder->exact(s.from, s.to); }));
  std::vector<morph::SweepSegment> after = before;
  const morph::SettledEnds settled =
      morph::settle_segment_ends(after, star.largest_step, star.budget.grid_exponent, star.budget.ends);
  EXPECT_GT(settled.aligned, 0u);
  EXPECT_EQ(settled.collapsed, 0u);
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t i = 0; i < after.size(); ++i) {
    EXPECT_TRUE(star.builder->exact(after[i].from, after[i].to)) << i;
    EXPECT_LE((after[i].from - before[i].from).norm(), star.budget.ends) << i;
    EXPECT_LE((after[i].to - before[i].to).norm(), star.budget.ends) << i;
    // Where the path met itself it still does: the moves join, and each lap meets the others.
    if (i + 1 < after.size()) {
      EXPECT_EQ(after[i].to, after[i + 1].from) << i;
    }
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_EQ(after[i].from == after[j].from, before[i].from == before[j].from) << i << ' ' << j;
      EXPECT_EQ(after[i].to == after[j].to, before[i].to == before[j].to) << i << ' ' << j;
    }
  }
  EXPECT_EQ(after.back().to == after.front().from, before.back().to == before.front().from);
}

TEST(SettleSegmentEnds, LevelAndAxisMovesNextToALongOneStayLevelAndOnTheirAxis) {
  const Star star = tapered_star();
  const int grid = star.budget.grid_exponent;
  const Vector3d a(-12, -9, 3.021), b(11.3, 7.7, 3.021), c = b + Vector3d(1, 0, 0), d = c + Vector3d(0, 1, 0);
  std::vector<morph::SweepSegment> segments;
  const std::vector<Vector3d> path{a, b, c, d};
  for (std::size_t k = 0; k + 1 < path.size(); ++k)
    segments.push_back({morph::snap_to_grid(path[k], grid), morph::snap_to_grid(path[k + 1], grid),
                        static_cast<std::int32_t>(k), 0, star.job.tools.begin()->first});
  ASSERT_FALSE(star.builder->exact(segments[0].from, segments[0].to));
  const morph::SettledEnds settled =
      morph::settle_segment_ends(segments, star.largest_step, grid, star.budget.ends);
  EXPECT_GT(settled.aligned, 0u);
  ASSERT_EQ(segments.size(), 3u);
  for (const morph::SweepSegment& s : segments) {
    EXPECT_TRUE(star.builder->exact(s.from, s.to));
    EXPECT_EQ(s.from.z(), s.to.z());  // level
  }
  EXPECT_EQ(segments[1].from.y(), segments[1].to.y());  // along x
  EXPECT_EQ(segments[2].from.x(), segments[2].to.x());  // along y
  EXPECT_LE((segments[1].from - snapped_at(b, grid)).norm(), star.budget.ends);
}

TEST(SettleSegmentEnds, AMoveShorterThanTheShareEndsWhereItStarts) {
  const Star star = tapered_star();
  const int grid = star.budget.grid_exponent;
  // A 1e-6 mm step down at a turn, then back over the same points (a retrace).
  const Vector3d a(-5, -5, 3), b(5, -5, 3), c = b - Vector3d(0, 0, 1e-6), d(5, 5, 3);
  std::vector<morph::SweepSegment> segments;
  const std::vector<Vector3d> path{a, b, c, d, c, b};
  for (std::size_t k = 0; k + 1 < path.size(); ++k)
    segments.push_back({morph::snap_to_grid(path[k], grid), morph::snap_to_grid(path[k + 1], grid),
                        static_cast<std::int32_t>(k), 0, star.job.tools.begin()->first});
  const morph::SettledEnds settled =
      morph::settle_segment_ends(segments, star.largest_step, grid, star.budget.ends);
  EXPECT_EQ(settled.collapsed, 1u);
  // a-b, b-d, d-b: the step is gone, its end joined to b everywhere it occurs.
  ASSERT_EQ(segments.size(), 3u);
  const Vector3d sb = morph::snap_to_grid(b, grid), sd = morph::snap_to_grid(d, grid);
  EXPECT_EQ(segments[0].to, sb);
  EXPECT_EQ(segments[1].from, sb);
  EXPECT_EQ(segments[1].to, sd);
  EXPECT_EQ(segments[2].from, sd);
  EXPECT_EQ(segments[2].to, sb);
  EXPECT_EQ(segments[2].move, 3);
}

}  // namespace
