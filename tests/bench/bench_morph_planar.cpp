// SPDX-License-Identifier: Apache-2.0
// The planar erosion's speed on large trajectories. Run: bench_morph --benchmark_filter=Planar
// Reports moves/s (items_per_second) and the result's size; the issue asks for a 10^5-move job in
// seconds.
#include <benchmark/benchmark.h>
#include <morph/planar_erosion.h>

#include <cmath>

namespace {

using morph::planar::Origin;
using morph::planar::Vec2;

morph::planar::Region plate(double size) {
  morph::planar::Loop loop;
  const Vec2 p[4] = {{0, 0}, {size, 0}, {size, size}, {0, size}};
  for (int i = 0; i < 4; ++i) loop.curves.push_back(morph::planar::make_segment(p[i], p[(i + 1) % 4]));
  return morph::planar::make_region({loop});
}

/// A raster pocket: rows 4.5 apart (tool radius 3) across a plate, each row made of moves 2 long,
/// alternating direction, with a step move between rows. Moves = rows * (per_row + 1).
morph::planar::Trajectory raster(int rows, int per_row) {
  morph::planar::Trajectory moves;
  const double length = 2.0;
  for (int row = 0; row < rows; ++row) {
    const double y = 5.0 + 4.5 * row;
    for (int k = 0; k < per_row; ++k) {
      const double x0 = row % 2 ? 5.0 + length * (per_row - k) : 5.0 + length * k;
      const double x1 = row % 2 ? x0 - length : x0 + length;
      moves.push_back(
          morph::planar::make_segment({x0, y}, {x1, y}, {Origin::Sweep, static_cast<int>(moves.size()), 0}));
    }
    const Vec2 end = moves.back().end;
    moves.push_back(morph::planar::make_segment(end, end + Vec2(0, 4.5),
                                                {Origin::Sweep, static_cast<int>(moves.size()), 0}));
  }
  return moves;
}

/// An Archimedean spiral of arcs (each a tenth of a turn, radius growing 4 per turn), tool radius 3.
morph::planar::Trajectory spiral(int arcs, const Vec2& center) {
  morph::planar::Trajectory moves;
  Vec2 at = center + Vec2(2.0, 0.0);
  for (int i = 0; i < arcs; ++i) {
    // Each arc about a centre chosen so that it ends on the spiral: a circle through both points.
    const double a1 = 2.0 * M_PI * (i + 1) / 10.0, r1 = 2.0 + 4.0 * (i + 1) / 10.0;
    const Vec2 next = center + r1 * Vec2(std::cos(a1), std::sin(a1));
    moves.push_back(
        morph::planar::make_bulge(at, next, std::tan(2.0 * M_PI / 10.0 / 4.0), {Origin::Sweep, i, 0}));
    at = next;
  }
  return moves;
}

void run(benchmark::State& state, const morph::planar::Region& stock,
         const morph::planar::Trajectory& moves) {
  std::size_t curves = 0, pieces = 0, intersections = 0;
  for (auto _ : state) {
    const auto result = morph::planar::erode(stock, moves, 3.0);
    curves = result.stats.pieces_kept;
    pieces = result.region.pieces.size();
    intersections = result.stats.intersections;
    benchmark::DoNotOptimize(result.region.loops.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * moves.size()));
  state.counters["moves"] = static_cast<double>(moves.size());
  state.counters["curves_kept"] = static_cast<double>(curves);
  state.counters["pieces"] = static_cast<double>(pieces);
  state.counters["intersections"] = static_cast<double>(intersections);
}

void BM_PlanarRaster(benchmark::State& state) {
  // rows x 499 moves + a step per row: 200 rows is 10^5 moves.
  const int rows = static_cast<int>(state.range(0));
  run(state, plate(1010.0), raster(rows, 499));
}
BENCHMARK(BM_PlanarRaster)->Arg(20)->Arg(200)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PlanarSpiral(benchmark::State& state) {
  const int arcs = static_cast<int>(state.range(0));
  const double reach = 2.0 + 4.0 * arcs / 10.0 + 5.0;
  run(state, plate(2.0 * reach), spiral(arcs, Vec2(reach, reach)));
}
BENCHMARK(BM_PlanarSpiral)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
