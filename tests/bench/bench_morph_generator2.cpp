// SPDX-License-Identifier: Apache-2.0
// Generator 2 end to end on bear.nc at 0.01 mm (issue 18's speed target: all of bear under 5 s on
// this machine): the culled exact carving (carve_culled.h) stage by stage, then conform and emit,
// on 2 TBB threads.
//
//   build/tests/bench/bench_morph --benchmark_filter='BM_Generator2/1000'
//   build/tests/bench/bench_morph --benchmark_filter='BM_Generator2/0'   # all 15,155 moves
// s_* are CPU seconds summed over the threads (the machine is shared: wall time measures the
// neighbours too); wall_* are wall seconds.
#include <benchmark/benchmark.h>
#include <morph/carve_culled.h>
#include <morph/conform.h>
#include <morph/degenerate_collapse.h>
#include <morph/emit.h>
#include <morph/erode.h>
#include <morph/error_budget.h>
#include <morph/quantize.h>
#include <morph/sweep_segments.h>
#include <morph/tool_polytope.h>
#include <morph/topology.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <fstream>

#include "generator2_bench_support.h"

namespace {

using namespace generator2_bench;

double process_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

void BM_Generator2(benchmark::State& state) {
  const std::string path = std::string(MORPHMILL_SHARED_DIR) + "/gcode/bear.nc";
  if (!std::ifstream(path)) {
    state.SkipWithError(("missing " + path).c_str());
    return;
  }
  morph::Job job = bear_job(path);
  std::vector<morph::Move>& moves = job.paths.front().moves;
  if (state.range(0) > 0 && static_cast<std::size_t>(state.range(0)) < moves.size())
    moves.resize(state.range(0));
  for (const morph::Move& m : moves)
    if (m.is_arc()) {
      state.SkipWithError("bear's moves are straight; an arc here means the job changed");
      return;
    }
  tbb::task_arena arena(2);
  for (auto _ : state) {
    double wall = wall_seconds(), cpu = process_seconds();
    const morph::ErrorBudget budget = morph::error_budget(job, job.tolerance);
    const morph::SweepPolytopeBuilder builder(
        morph::tool_polytope(job.tools.at(1).profile, budget.tool).polytope);
    std::vector<morph::CarveSweep> sweeps;
    // The segments erode sweeps (ends on the tool's grid, straight runs joined): the exact path
    // users run.
    for (const morph::SweepSegment& s : morph::sweep_segments(job, budget.chords, budget.grid_exponent))
      sweeps.push_back({&builder, s.from, s.to});
    const double tool_cpu = process_seconds() - cpu;
    morph::CarveStages stages;
    morph::CarvedPieces pieces;
    arena.execute([&] {
      pieces = morph::carve_culled(job.stock.box, sweeps, morph::ExecutionPolicy::Parallel, &stages);
    });
    const double carve_wall = wall_seconds() - wall;
    cpu = process_seconds();
    morph::ConformedSurface surface;
    arena.execute([&] { surface = morph::conform(pieces); });
    const double conform_cpu = process_seconds() - cpu;
    cpu = process_seconds();
    std::vector<std::int32_t> index(sweeps.size()), line(sweeps.size());
    for (std::size_t k = 0; k < sweeps.size(); ++k) index[k] = line[k] = static_cast<std::int32_t>(k);
    const morph::TriangleMesh mesh = morph::emit(morph::collapse_degenerates(surface), index, line);
    const double emit_cpu = process_seconds() - cpu;
    const double total_wall = wall_seconds() - wall;

    const morph::TopologyReport topology = morph::topology_report(mesh);

    auto& c = state.counters;
    c["moves"] = static_cast<double>(moves.size());
    c["sweep_facets"] = stages.culling.facets;
    c["kept_facets"] = stages.culling.kept;
    c["cutters_per_kept"] = stages.culling.cutters / std::max(1.0, stages.culling.kept);
    c["planes_per_kept"] = stages.culling.cutting_planes / std::max(1.0, stages.culling.kept);
    c["without_witness"] = stages.culling.without_witness;
    c["pieces"] = stages.carve.pieces;
    c["vertices"] = static_cast<double>(surface.vertices.size());
    c["inserted"] = static_cast<double>(surface.inserted);
    c["triangles"] = static_cast<double>(mesh.triangle_count());
    c["closed_manifold"] = topology.closed_manifold();
    c["degenerate_triangles"] = static_cast<double>(topology.degenerate_triangles);
    c["s_tool"] = tool_cpu;
    c["s_setup"] = stages.seconds_setup;
    c["s_cull"] = stages.seconds_cull;
    c["s_facets"] = stages.seconds_facets;
    c["s_stock"] = stages.seconds_stock;
    c["s_own_facets"] = stages.seconds_own_facets;
    c["predicates_own"] = stages.predicates_own;
    c["exact_own"] = stages.exact_own;
    c["predicates_cut"] = stages.predicates_cut;
    c["exact_cut"] = stages.exact_cut;
    c["ties"] = stages.ties;
    c["refined"] = stages.refined;
    c["s_conform"] = conform_cpu;
    c["s_collapse_emit"] = emit_cpu;
    c["wall_carve_2threads"] = carve_wall;
    c["wall_total_2threads"] = total_wall;
  }
}
// Arg: the first N moves of bear (0: all 15,155).
BENCHMARK(BM_Generator2)->Arg(1000)->Arg(0)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
