// SPDX-License-Identifier: Apache-2.0
// The generator end to end on the motions real programs make (plunge and retract, retraces, turns
// back, tiny moves, helices): closed, oriented and manifold by construction, and the
// volume against closed forms where there is one. The jobs of ../shared/repro/generator/ are
// rebuilt here (same stock, tool and path), at a coarser tolerance to keep the test short.
#include <morph/erode.h>
#include <morph/error_budget.h>
#include <morph/exceptions.h>
#include <morph/gcode.h>
#include <morph/sweep_polytope.h>
#include <morph/tool.h>
#include <morph/tool_polytope.h>
#include <morph/topology.h>
#include <tbb/task_arena.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <sstream>
#include <string>

#include "common/test_jobs.h"

namespace {

using Eigen::Vector3d;

morph::Job job_of(const Eigen::AlignedBox3d& box, const morph::Tool& tool,
                  const std::vector<Vector3d>& polyline, double tolerance = 0.05) {
  return morphmill_test::box_polyline_job(box, tool, polyline, tolerance);
}

struct Outcome {
  morph::TopologyReport topology;
  morph::ErodeResult result;
};

Outcome run(const morph::Job& job) {
  Outcome o;
  o.result = morph::erode(job);
  o.topology = morph::topology_report(o.result.mesh);
  return o;
}

void expect_closed(const Outcome& o, const char* what) {
  EXPECT_TRUE(o.topology.closed_manifold())
      << what << ": " << o.topology.boundary_edges << " boundary, " << o.topology.non_manifold_edges
      << " non-manifold edges, " << o.topology.inconsistent_edges << " inconsistent, "
      << o.topology.non_manifold_vertices << " non-manifold vertices";
  EXPECT_EQ(o.result.mesh.tags.size(), o.result.mesh.triangle_count());
}

// The tool polytope erode uses for `job` (its share of the tolerance, error_budget.h).
morph::ConvexPolytope polytope_of(const morph::Job& job) {
  return morph::tool_polytope(job.tools.begin()->second.profile, morph::error_budget(job, job.tolerance).tool)
      .polytope;
}

TEST(ErodeMotions, MoveInsideTheStockIsACavityOfTheSweepsVolume) {
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(20, 10, 10));
  const morph::Tool tool = morph::ball_tool(1.5, 4.0);
  const Vector3d a(5, 5, 3), b(15, 6, 4);
  const morph::Job job = job_of(box, tool, {a, b});
  const Outcome o = run(job);
  expect_closed(o, "cavity");
  EXPECT_EQ(o.topology.components, 2u);
  const morph::ConvexPolytope sweep = morph::sweep_polytope(polytope_of(job), a, b);
  EXPECT_NEAR(o.topology.volume, box.volume() - sweep.volume(), 1e-9 * box.volume());
}

TEST(ErodeMotions, SlotThroughThePlateAndBack) {
  // r1/r2 shapes: a ball-end slot in from outside the stock and straight back, through and part depth.
  const morph::Tool tool = morph::ball_tool(1.5, 20.0);
  for (double z : {-2.0, 1.5}) {
    const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(40, 30, 3));
    const Outcome there = run(job_of(box, tool, {Vector3d(20, -5, z), Vector3d(20, 15, z)}));
    const Outcome back =
        run(job_of(box, tool, {Vector3d(20, -5, z), Vector3d(20, 15, z), Vector3d(20, -5, z)}));
    expect_closed(there, "slot");
    expect_closed(back, "slot there and back");
    EXPECT_NEAR(back.topology.volume, there.topology.volume, 1e-9 * box.volume());
    // The retrace's planes coincide with the first pass's: no piece is split along them. A tip
    // inside the stock leaves the polytope's pole, where many near-concurrent facets meet: the
    // limit step and the rounding (degenerate_collapse.h, rounding.h) leave no flat triangle.
    EXPECT_EQ(there.topology.degenerate_triangles, 0u);
    EXPECT_EQ(back.topology.degenerate_triangles, 0u);
    // The removed part: the sweep within the stock, by Cavalieri: the polytope's volume is
    // V(P) + L·A⊥(P, u), and its part inside the stock the same at the stock's faces; check
    // the removed volume is below the whole sweep's and above the slot's straight part.
    const morph::ConvexPolytope p =
        polytope_of(job_of(box, tool, {Vector3d(20, -5, z), Vector3d(20, 15, z)}));
    const double removed = box.volume() - there.topology.volume;
    EXPECT_GT(removed, 0);
    EXPECT_LT(removed, morph::sweep_polytope(p, Vector3d(20, -5, z), Vector3d(20, 15, z)).volume());
  }
}

TEST(ErodeMotions, ARasterOfManyPassesRemovesItsExactSlab) {
  // Forty-one level passes of a flat tool along x right across a plate, linked outside it: more
  // sweeps meet the top face and the sides at x = 0, 20 than a cell holds, so those faces are
  // carved in cells (stock_face_cells.h), and cell edges cross the strips of the top face that
  // stay. The removed part is a slab: the polytope is a prism, so the passes' union within the
  // plate is 20 long, as wide as the passes' span and the polytope's y extent, and as deep as
  // the pass depth and the polytope's bottom.
  const Eigen::AlignedBox3d box(Vector3d(0, 0, -5), Vector3d(20, 20, 0));
  const morph::Tool tool = morph::flat_tool(1.0, 6.0);
  std::vector<Vector3d> path;
  for (int i = 0; i <= 40; ++i) {
    const double y = 5 + 0.25 * i, x0 = i % 2 ? 23.0 : -3.0, x1 = i % 2 ? -3.0 : 23.0;
    path.emplace_back(x0, y, -1.0);
    path.emplace_back(x1, y, -1.0);
  }
  const morph::Job job = job_of(box, tool, path);
  const Outcome o = run(job);
  expect_closed(o, "raster");
  const morph::ConvexPolytope p = polytope_of(job);
  double low_y = 0, high_y = 0, bottom = 0;
  for (const Vector3d& v : p.vertices) {
    low_y = std::min(low_y, v.y());
    high_y = std::max(high_y, v.y());
    bottom = std::min(bottom, v.z());
  }
  const double slab = 20.0 * ((15 + high_y) - (5 + low_y)) * (1.0 - bottom);
  EXPECT_NEAR(o.topology.volume, box.volume() - slab, 1e-9 * box.volume());
  EXPECT_EQ(morph::fallbacks_fired(o.result.stats), 0u);
}

TEST(ErodeMotions, CountsItsExactStepsAndFallbacks) {
  // r9: a square loop, the second lap reversed. The retraced planes coincide, and where four or
  // more planes meet in one point the perturbation splits it; the exact limit step merges it again.
  const morph::Tool tool = morph::ball_tool(1.5, 20.0);
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(30, 30, 5));
  const Outcome o = run(job_of(
      box, tool,
      {Vector3d(8, 8, 4), Vector3d(22, 8, 4), Vector3d(22, 22, 4), Vector3d(8, 22, 4), Vector3d(8, 8, 4),
       Vector3d(8, 22, 4), Vector3d(22, 22, 4), Vector3d(22, 8, 4), Vector3d(8, 8, 4)}));
  expect_closed(o, "square loop and reversed");
  std::map<std::string, const morph::StepCount*> step;
  std::size_t fallbacks = 0;
  for (const morph::StepCount& s : o.result.stats.steps) {
    step[s.name] = &s;
    if (s.fallback) fallbacks += s.count;
  }
  ASSERT_EQ(step.size(), 12u);
  for (const char* exact : {"ends_aligned", "short_segments_collapsed", "limit_merged_vertices",
                            "limit_removed_polygons", "limit_zipped_slivers"}) {
    ASSERT_TRUE(step.count(exact)) << exact;
    EXPECT_FALSE(step[exact]->fallback) << exact;
  }
  EXPECT_GT(step["limit_merged_vertices"]->count, 0u);
  // What the limit and the rounding leave unsettled would be a defect: none on this job.
  for (const char* left : {"limit_flat_polygons_left", "limit_unsettled", "rounding_misoriented_left"}) {
    ASSERT_TRUE(step.count(left)) << left;
    EXPECT_TRUE(step[left]->fallback) << left;
    EXPECT_EQ(step[left]->count, 0u) << left;
  }
  EXPECT_EQ(morph::fallbacks_fired(o.result.stats), fallbacks);
}

TEST(ErodeMotions, PlungeAndRetractIsThePlunge) {
  // r3 / r6: a ball-end plunge through (and into) a plate and straight back up.
  const morph::Tool tool = morph::ball_tool(3.0, 40.0);
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(40, 30, 10));
  for (double bottom : {-5.0, 5.0}) {
    const Outcome plunge = run(job_of(box, tool, {Vector3d(20, 15, 20), Vector3d(20, 15, bottom)}));
    const Outcome both =
        run(job_of(box, tool, {Vector3d(20, 15, 20), Vector3d(20, 15, bottom), Vector3d(20, 15, 20)}));
    expect_closed(plunge, "plunge");
    expect_closed(both, "plunge and retract");
    EXPECT_NEAR(both.topology.volume, plunge.topology.volume, 1e-9 * box.volume());
    if (bottom < 0) {  // as for the slot: the retrace adds nothing
      EXPECT_EQ(both.topology.degenerate_triangles, 0u);
      EXPECT_EQ(both.result.mesh.triangle_count(), plunge.result.mesh.triangle_count());
    }
    if (bottom < 0) {  // through: a prism of the tool's widest cross-section, 10 deep
      const morph::ConvexPolytope p =
          polytope_of(job_of(box, tool, {Vector3d(20, 15, 20), Vector3d(20, 15, bottom)}));
      double section = 0;  // the polytope's projection along z: its widest ring
      const Vector3d down(0, 0, 1);
      section = p.projected_area(down);
      EXPECT_NEAR(plunge.topology.volume, box.volume() - 10 * section, 1e-9 * box.volume());
    }
  }
}

TEST(ErodeMotions, TurnsBackAtAndNear180Degrees) {
  // r8 / r11: a slot that turns back inside the stock, exactly and 3 µm sideways.
  const morph::Tool tool = morph::ball_tool(1.5, 20.0);
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(40, 30, 5));
  const Outcome single = run(job_of(box, tool, {Vector3d(-5, 15, 3), Vector3d(20, 15, 3)}));
  const Outcome reverse =
      run(job_of(box, tool, {Vector3d(-5, 15, 3), Vector3d(20, 15, 3), Vector3d(-5, 15, 3)}));
  const Outcome near =
      run(job_of(box, tool, {Vector3d(-5, 15, 3), Vector3d(20, 15, 3), Vector3d(-5, 15.003, 3)}));
  expect_closed(single, "single");
  expect_closed(reverse, "180 degrees");
  expect_closed(near, "179.99 degrees");
  EXPECT_NEAR(reverse.topology.volume, single.topology.volume, 1e-9 * box.volume());
  EXPECT_LT(near.topology.volume, single.topology.volume);
  EXPECT_GT(near.topology.volume, single.topology.volume - 25 * 3 * 0.003);
}

TEST(ErodeMotions, TinyMoveAtACornerAndARetracedLoop) {
  // r10b / dg: a 1e-6 mm move at a 90-degree corner; r9: a square loop, the second lap reversed.
  const morph::Tool tool = morph::ball_tool(1.5, 20.0);
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(30, 30, 5));
  const Outcome corner = run(job_of(
      box, tool,
      {Vector3d(-5, 10, 3), Vector3d(15, 10, 3), Vector3d(15 + 1e-6, 10, 3), Vector3d(15 + 1e-6, 35, 3)}));
  expect_closed(corner, "1e-6 move at a corner");
  const Outcome once = run(job_of(
      box, tool,
      {Vector3d(8, 8, 4), Vector3d(22, 8, 4), Vector3d(22, 22, 4), Vector3d(8, 22, 4), Vector3d(8, 8, 4)}));
  const Outcome twice = run(job_of(
      box, tool,
      {Vector3d(8, 8, 4), Vector3d(22, 8, 4), Vector3d(22, 22, 4), Vector3d(8, 22, 4), Vector3d(8, 8, 4),
       Vector3d(8, 22, 4), Vector3d(22, 22, 4), Vector3d(22, 8, 4), Vector3d(8, 8, 4)}));
  expect_closed(once, "square loop");
  expect_closed(twice, "square loop and reversed");
  EXPECT_NEAR(twice.topology.volume, once.topology.volume, 1e-9 * box.volume());
}

// Long moves in general directions (stress seed 53, case 2106: a tapered tool six times round a
// triangle of radius 12.65) had silhouette planes rounded to doubles, whose corners missed the
// tool vertices they hold by ~1e-15 and left needles for the rounding to collapse. Their ends
// now lie on a coarser grid, every plane is exact, and no fallback fires.
TEST(ErodeMotions, LongMovesInGeneralDirectionsNeedNoFallback) {
  const Outcome o = run(morphmill_test::tapered_triangle_six_times_round());
  expect_closed(o, "tapered triangle six times round");
  std::map<std::string, std::size_t> count;
  for (const morph::StepCount& s : o.result.stats.steps) count[s.name] = s.count;
  EXPECT_GT(count["ends_aligned"], 0u);
  EXPECT_EQ(morph::fallbacks_fired(o.result.stats), 0u);
}

// Ball-end passes at one depth crossing and ending on each other (stress seed 89, case 9160: a
// square spiral crossing itself). With an apex at the tip, one pass's fan of nearly level facets
// grazed another's and cut a cloud of distinct exact points within 1e-6 mm, which the output
// rounding met as a needle. A level cap at the pole puts both passes' bottoms in one exact plane.
TEST(ErodeMotions, BallPassesAtOneDepthCrossingNeedNoFallback) {
  const morph::Tool tool = morph::ball_tool(2.503, 17.086);
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(17.094, 22.46, 7.086));
  const double z = 5.122;
  std::vector<Vector3d> spiral{{13.698, 16.381, z}, {3.396, 6.079, z}, {3.396, 16.381, z}};
  for (const auto& [x, y] : std::vector<std::pair<double, double>>{{13.698, 16.381},
                                                                   {13.698, 7.796},
                                                                   {5.113, 7.796},
                                                                   {5.113, 14.664},
                                                                   {11.981, 14.664},
                                                                   {11.981, 9.513},
                                                                   {6.83, 9.513},
                                                                   {6.83, 12.947},
                                                                   {10.264, 12.947},
                                                                   {10.264, 11.23},
                                                                   {8.547, 11.23}})
    spiral.emplace_back(x, y, z);
  const Outcome o = run(job_of(box, tool, spiral));
  expect_closed(o, "spiral at one depth");
  EXPECT_EQ(o.topology.components, 1u);
  EXPECT_EQ(morph::fallbacks_fired(o.result.stats), 0u);
}

// A flat end mill's helix down through the stock's top, then half its last circle back at the
// bottom (stress seed 191, cases 2178 and 4506). Near-parallel planes cross a side facet's edge
// 4e-9 mm apart, and that facet's polygon is 1.5e-7 mm wide: fanned from its centroid it gave a
// needle flat in doubles, which the rounding had to flip. Emit fans such a polygon from a
// corner whose triangles are not flat, so the fallback has nothing to do.
TEST(ErodeMotions, AFlatHelixAndItsReversedHalfCircleNeedNoFallback) {
  std::istringstream program(
      "G21 G90 G17\n"
      "G0 X22.179 Y13.923 Z10.25\n"
      "G3 X22.179 Y13.923 Z5.949 I-8.256 J0 P3\n"
      "G2 X5.667 Y13.923 I-8.256 J0\n"
      "G0 Z10.25\n");
  morph::Path path = morph::parse_gcode(program, "helix.nc").path;
  for (morph::Move& m : path.moves) m.tool = 1;
  morph::Job job =
      morphmill_test::box_polyline_job(Eigen::AlignedBox3d(Vector3d(0, 0, 0), Vector3d(27.846, 27.846, 9.25)),
                                       morph::flat_tool(2.667, 13.838), {}, 0.01);
  job.paths = {path};
  const Outcome o = run(job);
  expect_closed(o, "flat helix and reversed half circle");
  EXPECT_EQ(o.topology.components, 1u);
  EXPECT_EQ(morph::fallbacks_fired(o.result.stats), 0u);
  // Three turns from z 10.25 to 5.949 and half a turn at the bottom: the stock loses a ring of
  // outer radius 8.256 + 2.667 and inner 8.256 - 2.667 down to 5.949 (the helix's last turn
  // sweeps its bottom at a slope, the half turn levels half of it).
  const double outer = 8.256 + 2.667, inner = 8.256 - 2.667;
  const double ring = M_PI * (outer * outer - inner * inner);
  const double box = 27.846 * 27.846 * 9.25;
  const double removed = box - o.topology.volume;
  EXPECT_GT(removed, ring * (9.25 - 5.949 - 1.4337));
  EXPECT_LT(removed, ring * (9.25 - 5.949));
}

TEST(ErodeMotions, RefusesWhatItDoesNotSupport) {
  morph::Job job = job_of(Eigen::AlignedBox3d(Vector3d(0, 0, 0), Vector3d(1, 1, 1)), morph::ball_tool(0.5, 2),
                          {Vector3d(0, 0, 2), Vector3d(1, 1, 2)});
  job.stock.type = morph::StockType::Cylinder;  // of radius 0
  EXPECT_THROW(morph::erode(job), morph::InputError);
  job.stock.type = morph::StockType::Mesh;  // with no triangles
  EXPECT_THROW(morph::erode(job), morph::InputError);
}

}  // namespace

namespace {

TEST(ErodeMotions, RefusesAToleranceTheCoordinatesCannotResolve) {
  // coord_offset_1e15 of the hostile reproducers: doubles are 0.125 apart at 1e15.
  const Vector3d far(1e15, 0, 0);
  morph::Job job = job_of(Eigen::AlignedBox3d(far, far + Vector3d(20, 10, 5)), morph::ball_tool(1.5, 20.0),
                          {far + Vector3d(-5, 5, 4), far + Vector3d(25, 5, 4)}, 0.01);
  job.file = "far.json";
  try {
    morph::erode(job);
    ADD_FAILURE() << "generator 2 ran at 1e15 with a tolerance of 0.01";
  } catch (const morph::InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find("far.json: tolerance 0.01 is below what the coordinates can resolve"),
        std::string::npos)
        << e.what();
  }
}

}  // namespace

namespace {

morph::ErodeEstimate estimate_on_threads(const morph::Job& job, int threads) {
  morph::ErodeEstimate estimate;
  tbb::task_arena arena(threads);
  arena.execute([&] { estimate = morph::estimate_erode(job, job.tolerance); });
  return estimate;
}

}  // namespace

TEST(ErodeMotions, TheMemoryEstimateCountsEveryThreadsCaches) {
  // Fitted on 2 threads; each further one holds its own plane cache (up to 64 MiB) and culling
  // scratch, which on a many-core machine outweigh the rest.
  const morph::Tool tool = morph::ball_tool(1.5, 20.0);
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(40, 30, 5));
  std::vector<Vector3d> raster;
  for (int row = 0; row < 40; ++row) {
    raster.emplace_back(row % 2 ? 45 : -5, 0.7 * row, 3);
    raster.emplace_back(row % 2 ? -5 : 45, 0.7 * row, 3);
  }
  const morph::Job job = job_of(box, tool, raster, 0.01);
  const morph::ErodeEstimate one = estimate_on_threads(job, 1), two = estimate_on_threads(job, 2),
                             eight = estimate_on_threads(job, 8);
  EXPECT_EQ(one.bytes, two.bytes);
  EXPECT_EQ(eight.sweep_facets, two.sweep_facets);
  const double per_thread = (eight.bytes - two.bytes) / 6.0;
  EXPECT_GE(per_thread, std::min(64.0 * (1 << 20), 112.0 * two.sweep_facets));
  EXPECT_LE(per_thread, 64.0 * (1 << 20) + 144.0 * two.sweep_facets);
}
