// morphmill erode: the paper's secondary 3D model of the job's erosion (morph::erode), written as
// a mesh with per-face provenance, with a short summary of what was produced.
#include <morph/erode.h>
#include <morph/exceptions.h>
#include <morph/topology.h>
#include <morphmill/job_io.h>
#include <morphmill/mesh_io.h>
#include <tbb/global_control.h>
#include <tbb/task_group.h>

#include <exception>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>

#include "commands.h"
#include "memory_cap.h"
#include "terminal_progress.h"

namespace morphmill {

namespace {

struct ErodeCommandOptions {
  std::string job_path;
  std::string mesh_path;
  double tolerance = 0.0;
  int threads = 0;
  bool ascii = false;
  double memory_cap_gib = 0.0;
};

void run_erode(const ErodeCommandOptions& options) {
  if (options.tolerance < 0.0)
    throw morph::InputError("--tolerance: must be > 0 (or 0 for the job's tolerance)");
  if (options.threads < 0) throw morph::InputError("--threads: must be >= 1 (or 0 for all cores)");
  std::optional<tbb::global_control> threads;
  if (options.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, options.threads);
  const morph::Job job = load_job(options.job_path);
  report_job_warnings(job);
  TerminalProgress progress;
  morph::ErodeOptions erode_options;
  erode_options.tolerance = options.tolerance;
  erode_options.progress = &progress;
  erode_options.memory_cap_bytes = memory_cap_bytes(options.memory_cap_gib);
  const morph::ErodeResult result = [&] {
    try {
      return morph::erode(job, erode_options);
    } catch (const morph::LimitError& e) {
      throw morph::LimitError(options.job_path + ": " + e.what() + " (--memory-cap " +
                              std::to_string(options.memory_cap_gib) + " GiB)");
    }
  }();
  MeshWriteOptions write_options;
  write_options.binary = !options.ascii;
  // The summary's topology is computed while the file is written. A failed write must not
  // unwind the task group while the report runs: the group's destructor would cancel it, its
  // nested parallel loops would stop half-way and it would read half-built arrays. The write's
  // exception waits for the report to finish, then goes on.
  morph::TopologyReport topology;
  tbb::task_group summary;
  summary.run([&] { topology = morph::topology_report(result.mesh); });
  std::exception_ptr write_failure;
  try {
    write_mesh(result.mesh, options.mesh_path, write_options);
  } catch (...) {
    write_failure = std::current_exception();
  }
  summary.wait();
  if (write_failure) std::rethrow_exception(write_failure);
  const morph::ErodeStats& s = result.stats;
  std::cout << "erode " << (job.name.empty() ? options.job_path : job.name) << " at tolerance "
            << (options.tolerance > 0.0 ? options.tolerance : job.tolerance) << ": " << s.moves << " moves ("
            << s.moves_touching_stock << " touching the stock), " << s.patches_kept << " of " << s.patches
            << " patches kept\n"
            << "  " << result.mesh.triangle_count() << " triangles, " << topology.components << " piece(s), "
            << "closed manifold: " << (topology.closed_manifold() ? "yes" : "no");
  if (!topology.closed_manifold())
    std::cout << " (" << topology.boundary_edges << " boundary, " << topology.non_manifold_edges
              << " non-manifold edges, " << topology.non_manifold_vertices << " non-manifold vertices)";
  std::cout << ", volume " << std::setprecision(10) << topology.volume << '\n'
            << std::fixed << std::setprecision(2) << "  " << s.seconds_total << " s (setup "
            << s.seconds_setup << ", trim " << s.seconds_trim << ", assemble " << s.seconds_assemble
            << ") -> " << options.mesh_path << '\n'
            << "  memory: estimated " << describe_bytes(s.estimated_bytes) << " up front (" << s.segments
            << " segments, " << s.patches << " patches, " << std::setprecision(0) << s.grid_cells
            << " grid cells)\n";
}

}  // namespace

void register_erode_command(CLI::App& app) {
  auto options = std::make_shared<ErodeCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "erode",
      "Compute the surface of what the tool leaves of the stock (the paper's secondary 3D model):\n"
      "side sweeps along every move, front sweeps at path ends and turns, and the stock's faces, each\n"
      "trimmed against the exact swept volumes. The PLY output keeps each face's provenance\n"
      "(patch_kind, source = move or stock face, line = G-code line).\n"
      "Example: morphmill erode data/jobs/through_slots.json -o out/part.ply --tolerance 0.01");
  command->add_option("job", options->job_path, "Job file (JSON, see docs/job-format.md)")->required();
  command->add_option("--out,-o", options->mesh_path, "Output mesh (PLY keeps the face provenance)")
      ->required();
  command->add_option("--tolerance", options->tolerance,
                      "Largest distance from the exact surface, job units (default: the job's tolerance)");
  command->add_option("--threads", options->threads, "Worker threads (default: all cores)");
  command->add_flag("--ascii", options->ascii, "Write ASCII instead of binary PLY/STL");
  add_memory_cap_option(command, options->memory_cap_gib);
  command->callback([options] { run_erode(*options); });
}

}  // namespace morphmill
