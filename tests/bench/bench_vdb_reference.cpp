// SPDX-License-Identifier: Apache-2.0
// The level-set reference of one slot job at voxel sizes 0.4, 0.2 and 0.1: active voxels, memory
// and time should grow like surface area / voxel^2 (x4 per halving), not like volume (x8). And a
// real program: LinuxCNC's 3D_Chips.ngc (4.7k moves of a 10 mm ball end, data/jobs/chips.json) at
// verify's default voxel (radius / 6) and half of it.
#include <benchmark/benchmark.h>
#include <morph/gcode.h>
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

// data/jobs/chips.json built in code (the job reader lives in apps): 100 x 100 x 50 block, ball
// end of radius 5 and length 50, the program as tool 1.
morph::Job chips_job() {
  using namespace vdb_ref_test;
  morph::Job job = box_job(Vector3d(-50, -50, -50), Vector3d(50, 50, 0));
  job.name = "3D_Chips";
  add_tool(job, 1, morph::ToolType::BallEnd, 5.0, 50.0);
  morph::GcodeOptions gcode;
  gcode.initial_tool = 1;
  add_path(job, morph::read_gcode(MORPHMILL_TEST_DATA "/gcode/3D_Chips.ngc", gcode).path.moves);
  return job;
}

void run_reference(benchmark::State& state, const morph::Job& job, double voxel_size) {
  vdb_ref::ReferenceOptions options;
  options.voxel_size = voxel_size;
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

void BM_ReferenceSlotJob(benchmark::State& state) {
  run_reference(state, slot_job(), static_cast<double>(state.range(0)) / 1000.0);
}

// Argument: voxels per tool radius (6 is verify's default voxel).
void BM_ReferenceChips(benchmark::State& state) {
  run_reference(state, chips_job(), 5.0 / static_cast<double>(state.range(0)));
}

BENCHMARK(BM_ReferenceSlotJob)->Arg(400)->Arg(200)->Arg(100)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK(BM_ReferenceChips)->Arg(6)->Arg(12)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace
