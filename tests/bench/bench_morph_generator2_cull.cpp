// SPDX-License-Identifier: Apache-2.0
// Generator 2's culling stage (morph/sweep_culling.h) on bear.nc at 0.01 mm, the re-spike of
// issue 18: joints by normals, moves and facets by closed-form bounds, then halfspaces; then the
// spike's naive clipping of what is kept (stock box first, then the cutters' crossing planes),
// each stage timed on one core; morph::erode on the same moves in the same run, for the areas.
//
//   build/tests/bench/bench_morph --benchmark_filter='Generator2Cull.*/1000/|BM_ErodeBear'
//   build/tests/bench/bench_morph --benchmark_filter='Generator2Cull.*/0/|BM_ErodeBear'   # all 15,155 moves
// Times are this thread's CPU seconds; s_cull_wall_2threads is the culling's wall time on 2 TBB
// threads (inflated when the machine is shared).
#include <benchmark/benchmark.h>
#include <morph/error_budget.h>
#include <morph/joint_culling.h>
#include <morph/sweep_culling.h>
#include <morph/tool_polytope.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <fstream>

#include "generator2_bench_support.h"

namespace {

using namespace generator2_bench;

void BM_Generator2CullBear(benchmark::State& state) {
  const std::string path = std::string(MORPHMILL_SHARED_DIR) + "/gcode/bear.nc";
  if (!std::ifstream(path)) {
    state.SkipWithError(("missing " + path).c_str());
    return;
  }
  const morph::Job job = bear_job(path);
  std::vector<morph::Move> moves = job.paths.front().moves;
  if (state.range(0) > 0 && static_cast<std::size_t>(state.range(0)) < moves.size())
    moves.resize(state.range(0));
  for (const morph::Move& m : moves)
    if (m.is_arc()) {
      state.SkipWithError("the culling takes straight moves only");
      return;
    }
  const double deviation = morph::error_budget(job, job.tolerance).tool;  // the tool's share
  const Eigen::AlignedBox3d& stock = job.stock.box;
  const Plane stock_planes[6] = {
      {-Vector3d::UnitX(), -stock.min().x()}, {Vector3d::UnitX(), stock.max().x()},
      {-Vector3d::UnitY(), -stock.min().y()}, {Vector3d::UnitY(), stock.max().y()},
      {-Vector3d::UnitZ(), -stock.min().z()}, {Vector3d::UnitZ(), stock.max().z()}};
  for (auto _ : state) {
    double start = thread_seconds();
    const morph::ToolPolytope tool = morph::tool_polytope(job.tools.at(1).profile, deviation);
    const morph::SweepPolytopeBuilder sweeps(tool.polytope);
    std::vector<bool> joined(moves.size(), false);
    for (std::size_t i = 1; i < moves.size(); ++i)
      joined[i] = morph::joined_at_joint(sweeps, moves[i - 1], moves[i]);
    const morph::SweepCulling culling(sweeps, moves, joined, stock);
    const double setup = thread_seconds() - start;

    morph::CullingCounts counts;
    double cull = 0.0, polygons = 0.0, clipping = 0.0, pieces = 0.0, kept_area = 0.0, joined_count = 0.0;
    for (bool j : joined) joined_count += j;
    Polygon above, below;
    morph::SweepCulling::Scratch scratch;
    for (std::size_t i = 0; i < moves.size(); ++i) {
      start = thread_seconds();
      const std::vector<morph::KeptFacet> kept = culling.cull(i, counts, scratch);
      cull += thread_seconds() - start;
      if (kept.empty()) continue;
      start = thread_seconds();
      const morph::ConvexPolytope sweep = sweeps(moves[i].start, moves[i].end);
      polygons += thread_seconds() - start;
      start = thread_seconds();
      std::vector<std::pair<std::uint32_t, std::vector<morph::Halfspace>>> planes_of;
      for (const morph::KeptFacet& k : kept) {
        Polygon polygon;
        for (int v : sweep.facets[k.facet].loop) polygon.push_back(sweep.vertices[v]);
        for (const Plane& plane : stock_planes) {
          split(polygon, plane, above, below);
          polygon.swap(below);
          if (polygon.empty()) break;
        }
        if (polygon.empty()) continue;
        std::vector<std::vector<Plane>> cutters;
        for (const morph::FacetCutter& c : k.cutters) {
          auto found = std::find_if(planes_of.begin(), planes_of.end(),
                                    [&](const auto& e) { return e.first == c.move; });
          if (found == planes_of.end()) {
            planes_of.emplace_back(c.move, sweeps.halfspaces(moves[c.move].start, moves[c.move].end));
            found = planes_of.end() - 1;
          }
          std::vector<Plane>& cutter = cutters.emplace_back();
          for (int h : k.planes_of(c)) cutter.push_back({found->second[h].normal, found->second[h].offset});
        }
        clip(polygon, cutters, pieces, kept_area);
      }
      clipping += thread_seconds() - start;
    }

    // The culling again on 2 threads, wall clock.
    const auto wall_start = std::chrono::steady_clock::now();
    tbb::task_arena arena(2);
    tbb::combinable<double> kept_again;
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range<std::size_t>(0, moves.size(), 64), [&](const auto& range) {
        morph::CullingCounts local;
        morph::SweepCulling::Scratch scratch;
        for (std::size_t i = range.begin(); i < range.end(); ++i) culling.cull(i, local, scratch);
        kept_again.local() += local.kept;
      });
    });
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    if (kept_again.combine(std::plus<double>()) != counts.kept)
      state.SkipWithError("the culling is not deterministic");

    morph::Job cut = job;
    cut.paths.front().moves = moves;
    const morph::ErodeResult generated = morph::erode(cut);

    auto& c = state.counters;
    c["moves"] = static_cast<double>(moves.size());
    c["joints"] = joined_count;
    c["tool_facets"] = static_cast<double>(tool.polytope.facets.size());
    c["sweep_facets"] = counts.facets;
    c["by_joint"] = counts.by_joint;
    c["outside_stock"] = counts.outside_stock;
    c["by_retrace"] = counts.by_retrace;
    c["by_cluster_bound"] = counts.by_cluster_bound;
    c["by_facet_bound"] = counts.by_facet_bound;
    c["by_shared_cap"] = counts.by_shared_cap;
    c["by_planes"] = counts.by_planes;
    c["kept"] = counts.kept;
    c["kept_per_move"] = counts.kept / static_cast<double>(moves.size());
    c["candidates_per_move"] = counts.candidates / static_cast<double>(moves.size());
    c["bound_tests"] = counts.bound_tests;
    c["plane_tests"] = counts.plane_tests;
    c["without_witness"] = counts.without_witness;
    c["candidates_placed"] = counts.candidates_placed;
    c["apart_by_support"] = counts.apart_by_support;
    c["apart_by_box"] = counts.apart_by_box;
    c["cutters_per_kept"] = counts.cutters / std::max(1.0, counts.kept);
    c["cutting_planes_per_kept"] = counts.cutting_planes / std::max(1.0, counts.kept);
    c["pieces_out"] = pieces;
    c["kept_area_mm2"] = kept_area;
    c["erode_sweep_area_mm2"] = sweep_area(generated);
    c["s_setup_1core"] = setup;
    c["s_cull_1core"] = cull;
    c["s_polygons_1core"] = polygons;
    c["s_clip_1core"] = clipping;
    c["s_projected_2core"] = 0.5 * (setup + cull + polygons + clipping);
    c["s_cull_wall_2threads"] = wall;
    c["s_erode"] = generated.stats.seconds_total;
  }
}
// Arg: the first N moves of bear (0: all 15,155).
BENCHMARK(BM_Generator2CullBear)->Arg(100)->Arg(1000)->Arg(0)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
