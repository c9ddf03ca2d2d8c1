// The level-set reference of one slot job at voxel sizes 0.4, 0.2 and 0.1: active voxels, memory
// and time should grow like surface area / voxel^2 (x4 per halving), not like volume (x8).
#include <benchmark/benchmark.h>
#include <vdb_ref/reference.h>

#include "../vdb_ref/job_builders.h"

namespace {

using Eigen::Vector3d;

// Box 60 x 40 x 15; a ball end of radius 3 cuts four parallel slots 2 deep and one diagonal
// slot 4 deep; a sphere of radius 4 moves inside, leaving a void.
morph::Job slot_job() {
  using namespace vdb_ref_test;
  morph::Job job = box_job(Vector3d(0, 0, 0), Vector3d(60, 40, 15));
  add_tool(job, 1, morph::ToolType::BallEnd, 3.0, 20.0);
  add_tool(job, 2, morph::ToolType::Sphere, 4.0);
  std::vector<morph::Move> moves;
  for (double y : {8.0, 16.0, 24.0, 32.0})
    moves.push_back(line(Vector3d(-5, y, 13), Vector3d(65, y, 13), 1, 1));
  moves.push_back(line(Vector3d(-5, -5, 11), Vector3d(65, 45, 11), 1, 2));
  add_path(job, moves);
  add_path(job, {line(Vector3d(10, 10, 6), Vector3d(50, 30, 7), 2, 3)});
  return job;
}

void BM_ReferenceSlotJob(benchmark::State& state) {
  const morph::Job job = slot_job();
  vdb_ref::ReferenceOptions options;
  options.voxel_size = static_cast<double>(state.range(0)) / 1000.0;
  vdb_ref::ReferenceResult result;
  for (auto _ : state) {
    result = vdb_ref::compute_reference(job, options);
    benchmark::DoNotOptimize(result.mesh.vertices.data());
  }
  const vdb_ref::ReferenceStats& s = result.stats;
  state.counters["voxel"] = s.voxel_size;
  state.counters["active_voxels"] = static_cast<double>(s.active_voxels);
  state.counters["memory_MiB"] = static_cast<double>(s.memory_bytes) / (1 << 20);
  state.counters["estimate_MiB"] = static_cast<double>(s.estimated_bytes) / (1 << 20);
  state.counters["leaf_evals"] = static_cast<double>(s.sweep_leaf_evaluations);
  state.counters["stock_s"] = s.stock_seconds;
  state.counters["sweep_s"] = s.sweep_seconds;
  state.counters["difference_s"] = s.difference_seconds;
  state.counters["mesh_s"] = s.mesh_seconds;
  state.counters["segment_s"] = s.segment_seconds;
  state.counters["total_s"] = s.total_seconds;
  state.counters["triangles"] = static_cast<double>(result.mesh.triangle_count());
}

BENCHMARK(BM_ReferenceSlotJob)->Arg(400)->Arg(200)->Arg(100)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
