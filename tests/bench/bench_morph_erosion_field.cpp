// SPDX-License-Identifier: Apache-2.0
// The exact field (morph/sweep_distance.h), what verify and stress pay for every deviation sample:
//  - a fine raster, 2,000 steps of 0.01 mm along x under a 90° V-bit of radius 2.6 (the stress
//    family fine_steps): its steps joined into one sweep (morph::swept_runs), against the same
//    steps each nudged off the line by 1e-9 mm so that none joins (what every step cost before);
//  - a G19 arc of 300° under a bull-nose and a ball end (the stress family arcs).
// Each iteration evaluates the field at 2,000 points near the cut's surface.
//
//   build/tests/bench/bench_morph --benchmark_filter='ErosionField'
#include <benchmark/benchmark.h>
#include <morph/sweep_distance.h>

#include <random>

#include "common/test_jobs.h"

namespace {

using Eigen::Vector3d;

const Eigen::AlignedBox3d kStock(Vector3d(-5, -5, 0), Vector3d(30, 5, 6));

// Points spread around the cut's surface: the tool's points at random positions along the path,
// moved by up to a tenth of the tool's radius.
std::vector<Vector3d> samples_near(const morph::Job& job, std::size_t count) {
  std::mt19937_64 rng(5);
  const std::vector<const morph::Move*> moves = job.moves();
  std::uniform_int_distribution<std::size_t> which(0, moves.size() - 1);
  std::uniform_real_distribution<double> unit(0.0, 1.0), angle(0.0, 2 * M_PI), jitter(-0.1, 0.1);
  const morph::Tool& tool = job.tools.at(1);
  std::vector<Vector3d> points;
  while (points.size() < count) {
    const Vector3d at = morph::point_at(*moves[which(rng)], unit(rng));
    const double h = unit(rng) * tool.radius, a = angle(rng);
    const double r = tool.profile.empty() ? tool.radius : tool.profile.radius_at(h);
    points.push_back(at + Vector3d(r * std::cos(a), r * std::sin(a), h) +
                     tool.radius * Vector3d(jitter(rng), jitter(rng), jitter(rng)));
  }
  return points;
}

void evaluate(benchmark::State& state, const morph::Job& job) {
  const morph::ErosionField field(job);
  const std::vector<Vector3d> points = samples_near(job, 2000);
  for (auto _ : state) {
    double sum = 0.0;
    for (const Vector3d& p : points) sum += field.value(p);
    benchmark::DoNotOptimize(sum);
  }
  // Microseconds per point: the inverse of a rate of points per microsecond.
  state.counters["us_per_point"] =
      benchmark::Counter(1e-6 * static_cast<double>(points.size()),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["sweeps"] = static_cast<double>(morph::swept_runs(job).size());
}

void BM_ErosionFieldFineRaster(benchmark::State& state) {
  const bool nudged = state.range(0) != 0;
  std::vector<Vector3d> raster;
  for (int i = 0; i <= 2000; ++i) raster.emplace_back(0.01 * i, nudged && i % 2 ? 1e-9 : 0.0, 3.0);
  const morph::Job job =
      morphmill_test::box_polyline_job(kStock, morph::conical_tool(2.6, 90.0, 8.0), raster, 0.01);
  evaluate(state, job);
}
BENCHMARK(BM_ErosionFieldFineRaster)->ArgName("nudged")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_ErosionFieldArc(benchmark::State& state) {
  const morph::Tool tool =
      state.range(0) == 0 ? morph::ball_tool(1.9, 10.0) : morph::bullnose_tool(2.3, 1.0, 10.0);
  morph::Job job = morphmill_test::box_polyline_job(kStock, tool, {}, 0.01);
  job.paths.clear();
  morph::Move arc;
  arc.kind = morph::MoveKind::Arc;
  arc.tool = 1;
  arc.axis = Vector3d::UnitX();  // G19: the YZ plane
  arc.center = Vector3d(10, 0, 5);
  arc.start = Vector3d(10, 2.7, 5);
  arc.sweep = 300.0 * M_PI / 180.0;
  arc.end = arc.center + 2.7 * Vector3d(0, std::cos(arc.sweep), std::sin(arc.sweep));
  morph::Path path;
  path.moves.push_back(arc);
  job.paths.push_back(path);
  evaluate(state, job);
}
BENCHMARK(BM_ErosionFieldArc)->ArgName("bullnose")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
