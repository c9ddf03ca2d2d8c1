// SPDX-License-Identifier: Apache-2.0
// The culled carving (carve_culled.h) against the all-pairs one (carve_box(), the reference): the
// same pieces (support, edge planes in order, move, facet) and so the same triangles, on the
// erode2_test jobs and on random small jobs for every tool shape, one and several tools, on one
// thread and on TBB.
#include <morph/carve_culled.h>
#include <morph/conform.h>
#include <morph/emit.h>
#include <morph/exceptions.h>
#include <morph/progress.h>
#include <morph/quantize.h>
#include <morph/tool.h>
#include <morph/tool_polytope.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <iterator>
#include <memory>
#include <random>
#include <string>
#include <tuple>

namespace {

using Eigen::AlignedBox3d;
using Eigen::Vector3d;

struct Case {
  AlignedBox3d box;
  std::vector<std::unique_ptr<morph::SweepPolytopeBuilder>> tools;
  std::vector<morph::CarveSweep> sweeps;
};

void add_tool(Case& c, const morph::Tool& tool, double tolerance) {
  c.tools.push_back(std::make_unique<morph::SweepPolytopeBuilder>(
      morph::tool_polytope(tool.profile, 0.4 * tolerance).polytope));
}

void add_path(Case& c, std::size_t tool, const std::vector<Vector3d>& polyline) {
  for (std::size_t k = 0; k + 1 < polyline.size(); ++k)
    c.sweeps.push_back(morph::CarveSweep{c.tools[tool].get(), polyline[k], polyline[k + 1]});
}

// A piece as a comparable key: move, facet, support rank and the edges' (rank, direction) in order.
using PieceKey =
    std::tuple<std::int32_t, std::int32_t, std::uint64_t, std::vector<std::pair<std::uint64_t, int>>>;

std::vector<PieceKey> unsorted_keys(const std::vector<morph::CarvedPiece>& pieces) {
  std::vector<PieceKey> out;
  for (const morph::CarvedPiece& p : pieces) {
    std::vector<std::pair<std::uint64_t, int>> edges;
    for (const morph::ExactPlane& e : p.piece.edges) edges.emplace_back(e.rank, e.direction);
    out.emplace_back(p.move, p.face, p.piece.support.rank, std::move(edges));
  }
  return out;
}

std::vector<PieceKey> keys(const std::vector<morph::CarvedPiece>& pieces) {
  std::vector<PieceKey> out;
  for (const morph::CarvedPiece& p : pieces) {
    std::vector<std::pair<std::uint64_t, int>> edges;
    for (const morph::ExactPlane& e : p.piece.edges) edges.emplace_back(e.rank, e.direction);
    out.emplace_back(p.move, p.face, p.piece.support.rank, std::move(edges));
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string describe(const std::vector<PieceKey>& keys, const char* what) {
  std::string out = std::to_string(keys.size()) + " " + what + ":";
  for (std::size_t k = 0; k < keys.size() && k < 8; ++k) {
    out += " (move " + std::to_string(std::get<0>(keys[k])) + " facet " +
           std::to_string(std::get<1>(keys[k])) + " edges";
    for (const auto& e : std::get<3>(keys[k]))
      out += " " + std::to_string(e.first >> 32) + "." + std::to_string(e.first & 0xffffffffu);
    out += ")";
  }
  return out + "; ";
}

// The emitted triangles as sorted lists of corner coordinates, each rotated to its smallest corner.
using TriangleKey = std::array<std::array<double, 3>, 3>;
std::vector<TriangleKey> triangles(const std::vector<morph::CarvedPiece>& pieces) {
  const morph::ConformedSurface surface = morph::conform(pieces);
  std::vector<std::int32_t> index(pieces.size() + 1000), line(pieces.size() + 1000);
  for (std::int32_t m = 0; m < static_cast<std::int32_t>(index.size()); ++m) index[m] = line[m] = m;
  const morph::TriangleMesh mesh = morph::emit(surface, index, line);
  std::vector<TriangleKey> out;
  for (const auto& t : mesh.triangles) {
    TriangleKey k;
    for (int i = 0; i < 3; ++i)
      for (int a = 0; a < 3; ++a) k[i][a] = mesh.vertices[t[i]][a];
    const auto lowest = std::min_element(k.begin(), k.end()) - k.begin();
    std::rotate(k.begin(), k.begin() + lowest, k.end());
    out.push_back(k);
  }
  std::sort(out.begin(), out.end());
  return out;
}

void expect_same(const Case& c, const std::string& what) {
  std::vector<std::vector<morph::ExactPlane>> planes;
  for (std::size_t j = 0; j < c.sweeps.size(); ++j)
    planes.push_back(morph::sweep_planes(c.sweeps[j].tool->halfspaces(c.sweeps[j].from, c.sweeps[j].to),
                                         static_cast<std::uint32_t>(j)));
  morph::CarveStages stages;
  morph::CuttingOrders orders;
  const std::vector<morph::CarvedPiece> serial = morph::expanded(
      morph::carve_culled(c.box, c.sweeps, morph::ExecutionPolicy::Sequential, &stages, nullptr, &orders));
  // Each kept facet cut in the culled carving's order, by every sweep whose box meets it.
  const std::vector<morph::CarvedPiece> reference =
      morph::carve_box(c.box, planes, morph::sweep_boxes(c.sweeps), nullptr, &orders);
  const std::vector<morph::CarvedPiece> parallel = morph::expanded(morph::carve_culled(c.box, c.sweeps));
  ASSERT_FALSE(reference.empty()) << what;
  const std::vector<PieceKey> got = keys(serial), want = keys(reference);
  std::vector<PieceKey> extra, missing;
  std::set_difference(got.begin(), got.end(), want.begin(), want.end(), std::back_inserter(extra));
  std::set_difference(want.begin(), want.end(), got.begin(), got.end(), std::back_inserter(missing));
  EXPECT_TRUE(extra.empty() && missing.empty())
      << what << ": " << serial.size() << " pieces, reference " << reference.size() << "; "
      << describe(extra, "not in the reference") << describe(missing, "only in the reference");
  if (extra.empty() && missing.empty()) {
    // In the same order too (stock faces' pieces sorted, then moves and facets in order), so the
    // later stages see the same input.
    EXPECT_TRUE(unsorted_keys(serial) == unsorted_keys(reference)) << what;
    EXPECT_TRUE(triangles(serial) == triangles(reference)) << what;
  }
  // TBB: the same pieces in the same order.
  ASSERT_EQ(parallel.size(), serial.size()) << what;
  for (std::size_t k = 0; k < serial.size(); ++k) {
    EXPECT_EQ(parallel[k].piece.support.rank, serial[k].piece.support.rank) << what;
    EXPECT_EQ(parallel[k].piece.edges.size(), serial[k].piece.edges.size()) << what;
  }
  // The culling did cull: fewer facets carved than the sweeps have (unless there are none).
  EXPECT_GT(stages.culling.facets, 0) << what;
}

morph::Tool shape(int k) {
  switch (k) {
    case 0:
      return morph::sphere_tool(1.5);
    case 1:
      return morph::ball_tool(1.5, 6.0);
    case 2:
      return morph::flat_tool(1.5, 6.0);
    case 3:
      return morph::bullnose_tool(1.5, 0.5, 6.0);
    case 4:
      return morph::conical_tool(2.0, 90.0, 6.0);
    case 5:
      return morph::tapered_tool(0.5, 1.5, 6.0);
    case 6:
      return morph::tapered_ball_tool(0.75, 10.0, 6.0);
    default:
      return morph::conical_tool(2.0, 60.0, 6.0, 0.5);
  }
}
constexpr int kShapes = 8;

TEST(CarveCulled, SameAsAllPairsOnTheErode2Jobs) {
  const double tol = 0.05;
  struct Job {
    const char* name;
    AlignedBox3d box;
    morph::Tool tool;
    std::vector<Vector3d> path;
  };
  const std::vector<Job> jobs = {
      {"cavity",
       AlignedBox3d(Vector3d(0, 0, 0), Vector3d(20, 10, 10)),
       morph::ball_tool(1.5, 4.0),
       {Vector3d(5, 5, 3), Vector3d(15, 6, 4)}},
      {"slot there and back, through",
       AlignedBox3d(Vector3d(0, 0, 0), Vector3d(40, 30, 3)),
       morph::ball_tool(1.5, 20.0),
       {Vector3d(20, -5, -2), Vector3d(20, 15, -2), Vector3d(20, -5, -2)}},
      {"slot there and back, partial",
       AlignedBox3d(Vector3d(0, 0, 0), Vector3d(40, 30, 3)),
       morph::ball_tool(1.5, 20.0),
       {Vector3d(20, -5, 1.5), Vector3d(20, 15, 1.5), Vector3d(20, -5, 1.5)}},
      {"plunge and retract, through",
       AlignedBox3d(Vector3d(0, 0, 0), Vector3d(40, 30, 10)),
       morph::ball_tool(3.0, 40.0),
       {Vector3d(20, 15, 20), Vector3d(20, 15, -5), Vector3d(20, 15, 20)}},
      {"plunge and retract, blind",
       AlignedBox3d(Vector3d(0, 0, 0), Vector3d(40, 30, 10)),
       morph::ball_tool(3.0, 40.0),
       {Vector3d(20, 15, 20), Vector3d(20, 15, 5), Vector3d(20, 15, 20)}},
      {"180 degrees",
       AlignedBox3d(Vector3d(0, 0, 0), Vector3d(40, 30, 5)),
       morph::ball_tool(1.5, 20.0),
       {Vector3d(-5, 15, 3), Vector3d(20, 15, 3), Vector3d(-5, 15, 3)}},
      {"179.99 degrees",
       AlignedBox3d(Vector3d(0, 0, 0), Vector3d(40, 30, 5)),
       morph::ball_tool(1.5, 20.0),
       {Vector3d(-5, 15, 3), Vector3d(20, 15, 3), Vector3d(-5, 15.003, 3)}},
      {"1e-6 move at a corner",
       AlignedBox3d(Vector3d(0, 0, 0), Vector3d(30, 30, 5)),
       morph::ball_tool(1.5, 20.0),
       {Vector3d(-5, 10, 3), Vector3d(15, 10, 3), Vector3d(15 + 1e-6, 10, 3), Vector3d(15 + 1e-6, 35, 3)}},
      {"square loop and reversed",
       AlignedBox3d(Vector3d(0, 0, 0), Vector3d(30, 30, 5)),
       morph::ball_tool(1.5, 20.0),
       {Vector3d(8, 8, 4), Vector3d(22, 8, 4), Vector3d(22, 22, 4), Vector3d(8, 22, 4), Vector3d(8, 8, 4),
        Vector3d(8, 22, 4), Vector3d(22, 22, 4), Vector3d(22, 8, 4), Vector3d(8, 8, 4)}},
  };
  for (const Job& job : jobs) {
    Case c;
    c.box = job.box;
    add_tool(c, job.tool, tol);
    // The ends on the tool's grid, as erode puts them (every sweep then exact, quantize.h).
    std::vector<Vector3d> path;
    for (const Vector3d& p : job.path)
      path.push_back(morph::snap_to_grid(p, morph::grid_exponent_for(0.4 * tol)));
    add_path(c, 0, path);
    expect_same(c, job.name);
  }
}

// Random small jobs: level passes, ramps, plunges and retracts, retraces and repeated points on a
// coarse grid (so coincident planes and joints are common), every tool shape.
std::vector<Vector3d> random_path(std::mt19937& rng, int points) {
  std::uniform_int_distribution<int> x(0, 16), y(0, 12), z(0, 6), kind(0, 5);
  std::vector<Vector3d> path{Vector3d(x(rng) * 0.5 + 1, y(rng) * 0.5 + 1, 6)};
  for (int k = 1; k < points; ++k) {
    Vector3d p = path.back();
    switch (kind(rng)) {
      case 0:
        p.z() = z(rng) * 0.5 + 1;
        break;  // plunge or retract
      case 1:
        p.x() = x(rng) * 0.5 + 1;
        break;  // level along x
      case 2:
        p.y() = y(rng) * 0.5 + 1;
        break;  // level along y
      case 3:
        p = path.size() > 1 ? path[path.size() - 2] : p;
        break;  // retrace
      default:
        p = Vector3d(x(rng) * 0.5 + 1, y(rng) * 0.5 + 1, z(rng) * 0.5 + 1);  // anywhere
    }
    path.push_back(p);
  }
  return path;
}

// Twelve trials of ten points per shape: a cutter taken with the planes near the facet alone where
// nothing proves the two meet (a witness claimed at every joint) makes pieces of facets the cutter
// does not reach, and these jobs have such facets.
TEST(CarveCulled, SameAsAllPairsOnRandomJobsOfEveryToolShape) {
  std::mt19937 rng(18);
  for (int s = 0; s < kShapes; ++s) {
    for (int trial = 0; trial < 12; ++trial) {
      Case c;
      c.box = AlignedBox3d(Vector3d(0, 0, 0), Vector3d(10, 8, 4));
      add_tool(c, shape(s), 0.1);
      add_path(c, 0, random_path(rng, 10));
      expect_same(c, "shape " + std::to_string(s) + ", trial " + std::to_string(trial));
    }
  }
}

TEST(CarveCulled, SameAsAllPairsWithSeveralTools) {
  std::mt19937 rng(1818);
  for (int trial = 0; trial < 3; ++trial) {
    Case c;
    c.box = AlignedBox3d(Vector3d(0, 0, 0), Vector3d(10, 8, 4));
    add_tool(c, shape(2 * trial), 0.1);
    add_tool(c, shape(2 * trial + 1), 0.1);
    add_path(c, 0, random_path(rng, 4));
    add_path(c, 1, random_path(rng, 4));
    add_path(c, 0, random_path(rng, 3));
    expect_same(c, "two tools, trial " + std::to_string(trial));
  }
}

// A raster of joined level moves with a ball end, its ends on the tool's grid (every sweep exact):
// a facet of one move touches the next move's sweep along the tool edge at their joint, within
// the rounding of any float test. The tool vertex there, placed at the joint, is a point of both
// sweeps by construction, so it serves as the witness: those cutters take the planes near the
// facet, not every plane crossing it, and the pieces are the all-pairs carving's.
TEST(CarveCulled, AJointsToolVertexWitnessesTheNextSweep) {
  const double tol = 0.05;
  Case c;
  c.box = AlignedBox3d(Vector3d(0, 0, 0), Vector3d(12, 8, 4));
  add_tool(c, morph::ball_tool(1.5, 10.0), tol);
  std::vector<Vector3d> path;
  for (int row = 0; row < 5; ++row)
    for (int step = 0; step <= 6; ++step) {
      const double x = 1.0 + 1.7 * (row % 2 == 0 ? step : 6 - step);
      path.push_back(morph::snap_to_grid(Vector3d(x, 1.5 + 1.3 * row, 3.2 - 0.15 * step - 0.05 * row),
                                         morph::grid_exponent_for(0.4 * tol)));
    }
  add_path(c, 0, path);
  for (const morph::CarveSweep& s : c.sweeps) ASSERT_TRUE(s.tool->exact(s.from, s.to));
  morph::CarveStages stages;
  morph::carve_culled(c.box, c.sweeps, morph::ExecutionPolicy::Sequential, &stages);
  EXPECT_GT(stages.culling.cutters, 0.0);
  // Half of them without that witness (877 of 1684); what is left touches a sweep it shares no
  // end with (11).
  EXPECT_LT(stages.culling.without_witness, 0.02 * stages.culling.cutters)
      << "of " << stages.culling.cutters << " cutters";
  expect_same(c, "a raster of joined moves");
}

// Progress: one unit per stock face and per move, every unit reported once (from both threads),
// the same pieces as without it; a caller that asks to stop gets Interrupted.
class CountingProgress : public morph::Progress {
 public:
  void begin(const std::string& stage, std::size_t total) override {
    stage_ = stage;
    total_ = total;
    ++begun_;
  }
  void advance(std::size_t done) override { done_ += done; }
  void end() override { ++ended_; }
  bool interrupted() const override { return stop_after_ > 0 && done_ >= stop_after_; }

  std::string stage_;
  std::size_t total_ = 0, stop_after_ = 0;
  std::atomic<std::size_t> done_{0};
  int begun_ = 0, ended_ = 0;
};

TEST(CarveCulled, ReportsProgressPerMoveAndStopsWhenAsked) {
  Case c;
  c.box = AlignedBox3d(Vector3d(0, 0, 0), Vector3d(10, 8, 4));
  add_tool(c, shape(1), 0.1);
  add_path(c, 0,
           {Vector3d(1, 1, 3), Vector3d(8, 2, 3), Vector3d(8, 6, 2), Vector3d(2, 6, 3), Vector3d(5, 4, 5)});
  CountingProgress progress;
  const auto pieces = morph::expanded(
      morph::carve_culled(c.box, c.sweeps, morph::ExecutionPolicy::Parallel, nullptr, &progress));
  EXPECT_EQ(progress.stage_, "erode: carve");
  EXPECT_EQ(progress.total_, 6 + c.sweeps.size());
  EXPECT_EQ(progress.done_.load(), progress.total_);
  EXPECT_EQ(progress.begun_, 1);
  EXPECT_EQ(progress.ended_, 1);
  EXPECT_EQ(keys(pieces), keys(morph::expanded(morph::carve_culled(c.box, c.sweeps))));

  CountingProgress stopping;
  stopping.stop_after_ = 2;
  EXPECT_THROW(morph::carve_culled(c.box, c.sweeps, morph::ExecutionPolicy::Sequential, nullptr, &stopping),
               morph::Interrupted);
  EXPECT_LT(stopping.done_.load(), stopping.total_);
}

}  // namespace
