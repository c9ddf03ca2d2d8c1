// SPDX-License-Identifier: Apache-2.0
// Embree deviation measurement: closest-point queries per second and a one-sided deviation of a
// 1M-triangle sphere against a 200k-triangle one (the pair of the peer comparison, built in code).
#include <benchmark/benchmark.h>
#include <raytest/deviation.h>
#include <raytest/surface_query.h>

#include <cmath>

#include "raytest/raytest_support.h"

namespace {

// The UV sphere of the raytest tests (same layout as ../shared/peers/make_meshes.py):
// 2 * nlon * (nlat - 1) triangles.
using raytest_test::uv_sphere;

const morph::TriangleMesh& sphere_1m() {
  static const morph::TriangleMesh mesh = uv_sphere(1.01, 500, 1000);  // 998,000 triangles
  return mesh;
}

const morph::TriangleMesh& sphere_200k() {
  static const morph::TriangleMesh mesh = uv_sphere(1.0, 250, 400);  // 199,200 triangles
  return mesh;
}

const raytest::SurfaceQuery& query_200k() {
  static const raytest::SurfaceQuery query(sphere_200k());
  return query;
}

void BM_BuildSurfaceQuery200k(benchmark::State& state) {
  for (auto _ : state) {
    raytest::SurfaceQuery query(sphere_200k());
    benchmark::DoNotOptimize(query);
  }
  state.counters["triangles/s"] = benchmark::Counter(static_cast<double>(sphere_200k().triangle_count()),
                                                     benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_BuildSurfaceQuery200k)->Unit(benchmark::kMillisecond);

// Single-threaded closest points without hints: the raw query rate.
void BM_ClosestPointQueries(benchmark::State& state) {
  const raytest::SurfaceQuery& query = query_200k();
  const auto& points = sphere_1m().vertices;
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(query.closest_point(points[i]));
    i = (i + 7919) % points.size();  // hop around the sphere: no coherence between queries
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
}
BENCHMARK(BM_ClosestPointQueries);

// The deviation command's inner loop: vertices of the 1M sphere against the 200k sphere, in
// parallel, neighbouring samples hinting each other; items = queries.
void BM_DeviationVertices1MTo200k(benchmark::State& state) {
  const raytest::SurfaceQuery& query = query_200k();
  raytest::DeviationOptions options;
  options.mode = state.range(0) ? raytest::DeviationMode::Signed : raytest::DeviationMode::Unsigned;
  for (auto _ : state) {
    const auto result = raytest::measure_one_sided(sphere_1m(), query, options);
    benchmark::DoNotOptimize(result.stats.max);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * sphere_1m().vertex_count()));
}
BENCHMARK(BM_DeviationVertices1MTo200k)
    ->Arg(0)
    ->Arg(1)
    ->ArgNames({"signed"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// What `morphmill deviation D C --one-sided --samples 0 --signed` does after loading: build the
// query on the 200k sphere (its pseudo-normals on first use) and measure the 1M sphere's vertices.
void BM_SignedDeviationWithQueryBuild(benchmark::State& state) {
  raytest::DeviationOptions options;
  options.mode = raytest::DeviationMode::Signed;
  for (auto _ : state) {
    const raytest::SurfaceQuery query(sphere_200k());
    const auto result = raytest::measure_one_sided(sphere_1m(), query, options);
    benchmark::DoNotOptimize(result.stats.max);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * sphere_1m().vertex_count()));
}
BENCHMARK(BM_SignedDeviationWithQueryBuild)->Unit(benchmark::kMillisecond)->UseRealTime();

// Angle-weighted vertex normals of the 1M sphere (the sign's pseudo-normals and ray directions).
void BM_VertexNormals1M(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(raytest::angle_weighted_vertex_normals(sphere_1m()));
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * sphere_1m().triangle_count()));
}
BENCHMARK(BM_VertexNormals1M)->Unit(benchmark::kMillisecond)->UseRealTime();

// One million area-uniform face samples of the 1M sphere to the 200k sphere.
void BM_DeviationFaceSamples1MTo200k(benchmark::State& state) {
  const raytest::SurfaceQuery& query = query_200k();
  raytest::DeviationOptions options;
  options.sampling.vertices = false;
  options.sampling.face_samples = 1000000;
  for (auto _ : state) {
    const auto result = raytest::measure_one_sided(sphere_1m(), query, options);
    benchmark::DoNotOptimize(result.stats.max);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * 1000000));
}
BENCHMARK(BM_DeviationFaceSamples1MTo200k)->Unit(benchmark::kMillisecond)->UseRealTime();

// Ray mode: vertices of the 1M sphere along their normals to the 200k sphere.
void BM_RayDeviationVertices1MTo200k(benchmark::State& state) {
  const raytest::SurfaceQuery& query = query_200k();
  raytest::DeviationOptions options;
  options.mode = raytest::DeviationMode::Ray;
  options.max_distance = 0.1;
  for (auto _ : state) {
    const auto result = raytest::measure_one_sided(sphere_1m(), query, options);
    benchmark::DoNotOptimize(result.stats.max);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * sphere_1m().vertex_count()));
}
BENCHMARK(BM_RayDeviationVertices1MTo200k)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
