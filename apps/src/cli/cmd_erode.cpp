// SPDX-License-Identifier: Apache-2.0
// morphmill erode: the paper's secondary 3D model of the job's erosion (morph::erode), written as
// a mesh with per-face provenance, with a short summary of what was produced.
#include <morph/erode.h>
#include <morph/exceptions.h>
#include <morph/topology.h>
#include <morphmill/job_io.h>
#include <morphmill/mesh_io.h>
#include <morphmill/self_intersections.h>
#include <tbb/global_control.h>
#include <tbb/task_group.h>
#include <nlohmann/json.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>

#include "cli/cli_conventions.h"
#include "cli/commands.h"
#include "cli/memory_cap.h"
#include "cli/terminal_progress.h"
#include "io/provenance.h"
#include "verify/soundness.h"

namespace morphmill {

namespace {

struct ErodeCommandOptions {
  std::string job_path;
  std::string mesh_path;
  double tolerance = 0.0;
  int threads = 0;
  bool ascii = false;
  bool allow_open = false;
  double memory_cap_gib = 0.0;
  std::string json_path;
  CLI::Option* json_option = nullptr;
};

nlohmann::json steps_json(const morph::ErodeStats& stats, bool fallbacks) {
  nlohmann::json out = nlohmann::json::object();
  for (const morph::StepCount& step : stats.steps)
    if (step.fallback == fallbacks) out[step.name] = step.count;
  return out;
}

// Stage -> CPU seconds summed over the threads.
nlohmann::json stage_cpu_json(const morph::ErodeStats& stats) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [stage, seconds] : stats.stage_cpu_seconds) out[stage] = seconds;
  return out;
}

// "none" or "3 (rounding_flipped_edges 2, limit_kept_apart 1)": the steps of one kind that fired.
std::string describe_steps(const morph::ErodeStats& stats, bool fallbacks) {
  std::size_t total = 0;
  std::string fired;
  for (const morph::StepCount& step : stats.steps)
    if (step.fallback == fallbacks && step.count > 0) {
      total += step.count;
      fired += (fired.empty() ? "" : ", ") + step.name + " " + std::to_string(step.count);
    }
  return total == 0 ? std::string("none") : std::to_string(total) + " (" + fired + ")";
}

nlohmann::json summary_json(const ErodeCommandOptions& options, const morph::Job& job, double tolerance,
                            const morph::ErodeResult& result, const morph::TopologyReport& topology,
                            const SelfIntersections& crossings, bool written) {
  const morph::ErodeStats& s = result.stats;
  nlohmann::json pairs = nlohmann::json::array();
  for (const auto& [a, b] : crossings.first_pairs) pairs.push_back({a, b});
  return {{"job", options.job_path},
          {"name", job.name},
          {"units", morph::to_string(job.units)},
          {"tolerance", tolerance},
          {"moves", s.moves},
          {"moves_touching_stock", s.moves_touching_stock},
          {"segments", s.segments},
          {"patches", s.patches},
          {"patches_kept", s.patches_kept},
          {"triangles", result.mesh.triangle_count()},
          {"pieces", topology.components},
          {"closed_manifold", topology.closed_manifold()},
          {"boundary_edges", topology.boundary_edges},
          {"non_manifold_edges", topology.non_manifold_edges},
          {"non_manifold_vertices", topology.non_manifold_vertices},
          {"self_intersecting_pairs", crossings.pairs},
          {"first_self_intersecting_pairs", pairs},
          {"volume", topology.volume},
          {"fallbacks_fired", morph::fallbacks_fired(s)},
          {"fallbacks", steps_json(s, true)},
          {"exact_steps", steps_json(s, false)},
          {"seconds",
           {{"setup", s.seconds_setup},
            {"trim", s.seconds_trim},
            {"assemble", s.seconds_assemble},
            {"total", s.seconds_total}}},
          {"stage_cpu_seconds", stage_cpu_json(s)},
          {"estimated_bytes", s.estimated_bytes},
          {"output", written ? nlohmann::json(options.mesh_path) : nlohmann::json(nullptr)}};
}

// Whether `path` can take the output is known before the long work: a missing or read-only
// directory, a directory or a symbolic-link loop at the path is refused up front (exit 2), also
// when the surface turns out unsound and is not written. Only a full device shows at the write.
void check_output_path(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error && error != std::errc::no_such_file_or_directory)
    throw morph::IoError(path + ": cannot write: " + error.message());
  if (fs::is_directory(status)) throw morph::IoError(path + ": cannot write: it is a directory");
  fs::path directory = fs::path(path).parent_path();
  if (directory.empty()) directory = ".";
  if (!fs::is_directory(directory, error))
    throw morph::IoError(path + ": cannot write: no directory '" + directory.string() + "'");
  // The output goes through a temporary file beside it: creating one is the test that tells.
  const std::string probe = (directory / (".morphmill-probe-" + std::to_string(::getpid()))).string();
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0)
    throw morph::IoError(path + ": cannot write into '" + directory.string() + "': " + std::strerror(errno));
  ::close(fd);
  ::unlink(probe.c_str());
}

void run_erode(const ErodeCommandOptions& options) {
  if (options.tolerance < 0.0)
    throw morph::InputError("--tolerance: must be > 0 (or 0 for the job's tolerance)");
  if (options.threads < 0) throw morph::InputError("--threads: must be >= 1 (or 0 for all cores)");
  std::optional<tbb::global_control> threads;
  if (options.threads > 0) threads.emplace(tbb::global_control::max_allowed_parallelism, options.threads);
  const morph::Job job = load_job(options.job_path);
  report_job_warnings(job);
  check_output_path(options.mesh_path);
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
  // What the surface is decides whether it is written: a surface that is not a closed, oriented
  // 2-manifold free of self-intersections is not the solid that was promised.
  const SurfaceSoundness soundness = check_soundness(result.mesh);
  const morph::TopologyReport& topology = soundness.topology;
  const SelfIntersections& crossings = soundness.crossings;
  const bool valid = soundness.sound();
  if (valid || options.allow_open) {
    MeshWriteOptions write_options;
    write_options.binary = !options.ascii;
    const Provenance provenance = make_provenance(
        job_input_files(job),
        {{"command", "erode"}, {"tolerance", options.tolerance > 0.0 ? options.tolerance : job.tolerance}},
        morph::to_string(job.units));
    write_mesh(result.mesh, options.mesh_path, write_options, provenance_lines(provenance));
  }
  const morph::ErodeStats& s = result.stats;
  const bool json_on_stdout =
      options.json_option->count() > 0 && (options.json_path.empty() || options.json_path == "-");
  if (!json_on_stdout) {
    std::cout << "erode " << (job.name.empty() ? options.job_path : job.name) << " at tolerance "
              << (options.tolerance > 0.0 ? options.tolerance : job.tolerance) << ": " << s.moves
              << " moves (" << s.moves_touching_stock << " touching the stock), " << s.patches_kept << " of "
              << s.patches << " patches kept\n"
              << "  " << result.mesh.triangle_count() << " triangles, " << topology.components
              << " piece(s), "
              << "closed manifold: " << (topology.closed_manifold() ? "yes" : "no");
    if (!topology.closed_manifold())
      std::cout << " (" << topology.boundary_edges << " boundary, " << topology.non_manifold_edges
                << " non-manifold edges, " << topology.non_manifold_vertices << " non-manifold vertices)";
    std::cout << ", self-intersections: " << crossings.pairs << " pairs";
    if (!crossings.first_pairs.empty())
      std::cout << " (first: triangles " << crossings.first_pairs[0].first << " and "
                << crossings.first_pairs[0].second << ")";
    std::cout << ", volume " << std::setprecision(10) << topology.volume << '\n'
              << std::fixed << std::setprecision(2) << "  " << s.seconds_total << " s (setup "
              << s.seconds_setup << ", trim " << s.seconds_trim << ", assemble " << s.seconds_assemble
              << ") -> " << (valid || options.allow_open ? options.mesh_path : "not written") << '\n'
              << "  memory: estimated " << describe_bytes(s.estimated_bytes) << " up front (" << s.segments
              << " segments, " << s.patches << " patches";
    std::cout << ")\n";
    if (!s.stage_cpu_seconds.empty()) {
      std::cout << "  CPU s by stage:";
      for (const auto& [stage, seconds] : s.stage_cpu_seconds) std::cout << ' ' << stage << ' ' << seconds;
      std::cout << '\n';
    }
    std::cout << "  fallbacks fired: " << describe_steps(s, true);
    if (std::any_of(s.steps.begin(), s.steps.end(),
                    [](const morph::StepCount& step) { return !step.fallback; }))
      std::cout << "; exact steps: " << describe_steps(s, false);
    std::cout << '\n';
  }
  if (options.json_option->count() > 0)
    write_json(summary_json(options, job, options.tolerance > 0.0 ? options.tolerance : job.tolerance, result,
                            topology, crossings, valid || options.allow_open),
               options.json_path);
  if (!valid) {
    std::cerr << "erode: the surface is not a closed, oriented 2-manifold free of self-intersections; "
              << (options.allow_open ? "written anyway (--allow-open)"
                                     : "not written (--allow-open writes it anyway)")
              << '\n';
    throw VerdictFailed{};
  }
}

}  // namespace

void register_erode_command(CLI::App& app) {
  auto options = std::make_shared<ErodeCommandOptions>();
  CLI::App* command = app.add_subcommand(
      "erode",
      "Compute the surface of what the tool leaves of the stock (the paper's secondary 3D model):\n"
      "the stock's faces and the faces of every move's sweep (the tool's profile swept along it:\n"
      "side sweeps, and the tool's own surface at path ends and turns), each cut where the other\n"
      "sweeps and the stock decide, by exact predicates, so that the seams match by construction.\n"
      "Every tool of revolution; arcs and the tool's curved surfaces within the tolerance.\n"
      "The PLY output keeps each face's provenance (patch_kind, source = move or stock face,\n"
      "line = G-code line).\n"
      "Exit code 0 when the surface is a closed, oriented 2-manifold free of self-intersections\n"
      "(exact predicates); 1 when it is not (nothing is written unless --allow-open); 2 bad input.\n"
      "Example: morphmill erode data/jobs/through_slots.json -o out/part.ply --tolerance 0.01");
  command->add_option("job", options->job_path, "Job file (JSON, see docs/job-format.md)")->required();
  command->add_option("-o,--output", options->mesh_path, "Output mesh (PLY keeps the face provenance)")
      ->required();
  command->add_option("--tolerance", options->tolerance,
                      "Largest distance from the exact surface, job units (default: the job's tolerance)");
  command->add_option("--threads", options->threads, "Worker threads (default: all cores)");
  add_retired_generator_option(*command);
  command->add_flag("--ascii", options->ascii, "Write ASCII instead of binary PLY/STL");
  command->add_flag("--allow-open", options->allow_open,
                    "Write the surface even when it is not a closed, oriented 2-manifold free of\n"
                    "self-intersections (the exit code is still 1)");
  add_memory_cap_option(command, options->memory_cap_gib);
  options->json_option = add_json_option(*command, options->json_path, "the summary (also when exit 1)");
  command->callback([options] { run_erode(*options); });
}

}  // namespace morphmill
