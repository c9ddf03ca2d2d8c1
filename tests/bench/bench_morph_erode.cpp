// SPDX-License-Identifier: Apache-2.0
// Speed of the surface generator (morph::erode): raster finishing jobs of 1k, 10k and 100k moves
// over the same 100 x 100 x 20 mm stock at tolerance 0.01 mm, and the real program bear.nc.
// Counters: output triangles, triangles per second, seconds per move.
#include <benchmark/benchmark.h>
#include <morph/erode.h>
#include <morph/gcode.h>

#include <cmath>
#include <fstream>

namespace {

/// A ball-end raster over a wavy surface: rows 1 mm apart, each split into moves_per_row moves.
/// A box stock from (0, 0, -20) to (size, size, 0) cut by bear.nc's 1/8 in ball end (tool 1), at
/// tolerance 0.01 mm; no paths yet.
morph::Job ball_end_box_job(const char* name, double size) {
  morph::Job job;
  job.name = name;
  job.stock.type = morph::StockType::Box;
  job.stock.box = Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, -20), Eigen::Vector3d(size, size, 0));
  morph::Tool tool;
  tool.number = 1;
  tool.type = morph::ToolType::BallEnd;
  tool.radius = 1.5875;
  tool.length = 25.4;
  job.tools[1] = tool;
  job.tolerance = 0.01;
  return job;
}

morph::Job raster_job(int moves) {
  morph::Job job = ball_end_box_job("raster", 100.0);
  const int rows = 100;
  const int per_row = std::max(1, moves / rows);
  morph::Path path;
  auto height = [](double x, double y) { return -6.0 + 3.0 * std::sin(x / 9.0) * std::cos(y / 13.0); };
  Eigen::Vector3d previous(-2.0, 0.5, height(-2.0, 0.5));
  int line = 1;
  for (int row = 0; row < rows; ++row) {
    const double y = 0.5 + row;
    const bool forward = row % 2 == 0;
    for (int k = 0; k <= per_row; ++k) {
      const double s = static_cast<double>(k) / per_row;
      const double x = forward ? -2.0 + 104.0 * s : 102.0 - 104.0 * s;
      const Eigen::Vector3d point(x, y, height(x, y));
      if (k == 0 && row == 0) continue;
      morph::Move m;
      m.start = previous;
      m.end = point;
      m.tool = 1;
      m.line = ++line;
      path.moves.push_back(m);
      previous = point;
    }
  }
  job.paths.push_back(path);
  return job;
}

void report(benchmark::State& state, const morph::ErodeResult& result, double seconds, std::size_t moves) {
  state.counters["moves"] = static_cast<double>(moves);
  state.counters["triangles"] = static_cast<double>(result.stats.triangles);
  state.counters["triangles_per_s"] = static_cast<double>(result.stats.triangles) / seconds;
  state.counters["s_per_move"] = seconds / static_cast<double>(moves);
  state.counters["fallbacks_fired"] = static_cast<double>(morph::fallbacks_fired(result.stats));
}

void BM_ErodeRaster(benchmark::State& state) {
  const morph::Job job = raster_job(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const morph::ErodeResult result = morph::erode(job);
    benchmark::DoNotOptimize(result.mesh.triangles.data());
    report(state, result, result.stats.seconds_total, job.move_count());
  }
}
BENCHMARK(BM_ErodeRaster)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kSecond)->Iterations(1);

// bear.nc: 15k moves, 3.175 mm ball nose, stock (0,0,-20)-(80,80,0), tolerance 0.01 mm
// (CAMotics needs 10.5 s at its 0.3 mm grid on this machine, see ../shared/gcode/README.md).
void BM_ErodeBear(benchmark::State& state) {
  const std::string path = std::string(MORPHMILL_SHARED_DIR) + "/gcode/bear.nc";
  if (!std::ifstream(path)) {
    state.SkipWithError(("missing " + path).c_str());
    return;
  }
  morph::GcodeOptions options;
  options.initial_tool = 1;
  morph::GcodeResult program = morph::read_gcode(path, options);
  morph::Job job = ball_end_box_job("bear", 80.0);
  for (morph::Move& m : program.path.moves) m.tool = 1;
  job.paths.push_back(program.path);
  for (auto _ : state) {
    const morph::ErodeResult result = morph::erode(job);
    benchmark::DoNotOptimize(result.mesh.triangles.data());
    report(state, result, result.stats.seconds_total, job.move_count());
  }
}
BENCHMARK(BM_ErodeBear)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
