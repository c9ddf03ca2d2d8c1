// SPDX-License-Identifier: Apache-2.0
// Speed of the exact self-intersection test (morphmill::find_self_intersections) on the
// generator's surface of bear.nc (1.33M triangles), threaded and on one thread, beside the
// topology report that `erode` computes with it.
#include <benchmark/benchmark.h>
#include <morph/erode.h>
#include <morph/gcode.h>
#include <morph/topology.h>
#include <morphmill/self_intersections.h>

#include <fstream>
#include <memory>

namespace {

/// bear.nc's surface at tolerance 0.01 mm, built once; null if bear.nc is missing.
const morph::TriangleMesh* bear_surface() {
  static std::unique_ptr<morph::TriangleMesh> mesh = [] {
    std::unique_ptr<morph::TriangleMesh> built;
    const std::string path = std::string(MORPHMILL_SHARED_DIR) + "/gcode/bear.nc";
    if (!std::ifstream(path)) return built;
    morph::GcodeOptions options;
    options.initial_tool = 1;
    morph::Job job;
    job.name = "bear";
    job.stock.type = morph::StockType::Box;
    job.stock.box = Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, -20), Eigen::Vector3d(80, 80, 0));
    morph::Tool tool;
    tool.number = 1;
    tool.type = morph::ToolType::BallEnd;
    tool.radius = 1.5875;
    tool.length = 25.4;
    job.tools[1] = tool;
    job.tolerance = 0.01;
    job.paths.push_back(morph::read_gcode(path, options).path);
    built = std::make_unique<morph::TriangleMesh>(morph::erode(job).mesh);
    return built;
  }();
  return mesh.get();
}

void BM_SelfIntersectionsBear(benchmark::State& state) {
  const morph::TriangleMesh* mesh = bear_surface();
  if (!mesh) {
    state.SkipWithError("missing ../shared/gcode/bear.nc");
    return;
  }
  const bool threaded = state.range(0) != 0;
  std::size_t pairs = 0;
  for (auto _ : state) pairs = morphmill::find_self_intersections(*mesh, 10, threaded).pairs;
  state.counters["triangles"] = static_cast<double>(mesh->triangle_count());
  state.counters["pairs"] = static_cast<double>(pairs);
}
BENCHMARK(BM_SelfIntersectionsBear)->Arg(1)->Arg(0)->Unit(benchmark::kSecond)->Iterations(1);

void BM_TopologyReportBear(benchmark::State& state) {
  const morph::TriangleMesh* mesh = bear_surface();
  if (!mesh) {
    state.SkipWithError("missing ../shared/gcode/bear.nc");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(morph::topology_report(*mesh).components);
}
BENCHMARK(BM_TopologyReportBear)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
