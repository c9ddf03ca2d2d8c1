// SPDX-License-Identifier: Apache-2.0
#include "verify/generator_choice.h"

#include <morph/erode2.h>
#include <morph/exceptions.h>
#include <morph/tool.h>
#include <tbb/task_group.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>

namespace morphmill {

namespace {

// The option's help, "(default)" on the command's own default.
std::string generator_option_help(int default_generator) {
  auto marked = [&](int generator) { return generator == default_generator ? " (default)" : ""; };
  return std::string("2") + marked(2) +
         ": generator 2, the union of exact sweep polytopes: closed by construction, every tool\n"
         "  of revolution, every stock;\n"
         "1" +
         marked(1) +
         ": generator 1, trimmed patches welded at their seams (sphere and ball-end tools only;\n"
         "  its surface may be open or self-intersecting, and erode then exits 1);\n"
         "auto" +
         marked(kAutoGenerator) +
         ": generator 1's surface when it is sound (closed, oriented, no self-intersections),\n"
         "  otherwise generator 2's; generator 2's also for tools generator 1 cannot build, and when\n"
         "  generator 1 passes its search limit (about what generator 2 costs in all). Generator 2 is\n"
         "  not tried when it would sweep more than " +
         std::to_string(static_cast<long long>(kAutoRetryFacets / 1e6)) + " million facets";
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The first move whose tool generator 1 cannot build, as "the move at line L of F uses tool T
// (shape and sizes)"; "" when it builds every move.
std::string first_move_beyond_generator_1(const morph::Job& job) {
  for (const morph::Path& path : job.paths)
    for (const morph::Move& move : path.moves) {
      const morph::Tool& tool = job.tool_of(move);
      if (!generator_builds(tool, 1))
        return "the move at line " + std::to_string(move.line) + " of " + path.source + " uses tool " +
               std::to_string(move.tool) + " (" + morph::describe(tool) + ")";
    }
  return "";
}

}  // namespace

CLI::Option* add_generator_option(CLI::App& command, int& generator) {
  const CLI::Validator names(
      [](std::string& value) {
        if (value == "auto")
          value = std::to_string(kAutoGenerator);
        else if (value != "1" && value != "2")
          return "must be auto, 1 or 2, not '" + value + "'";
        return std::string();
      },
      "", "generator name");
  return command.add_option("--generator", generator, generator_option_help(generator))
      ->transform(names)
      ->type_name("2|1|auto")
      ->default_str(generator_name(generator));
}

void check_generator(int generator) {
  if (generator != kAutoGenerator && generator != 1 && generator != 2)
    throw morph::InputError("--generator: must be auto, 1 (today's) or 2 (exact plane-based), got " +
                            std::to_string(generator));
}

std::string generator_name(int generator) {
  return generator == kAutoGenerator ? "auto" : std::to_string(generator);
}

bool generator_builds(const morph::Tool& tool, int generator) {
  check_generator(generator);
  return generator != 1 || tool.generator_builds();
}

std::string why_generator_cannot_build(const morph::Job& job, int generator) {
  check_generator(generator);
  if (generator != 1) return "";
  const std::string move = first_move_beyond_generator_1(job);
  return move.empty() ? "" : move + ", which generator 1 cannot build (generator 2, the default, can)";
}

std::string SurfaceSoundness::describe() const {
  if (sound()) return "sound";
  std::ostringstream text;
  if (!topology.closed_manifold())
    text << "not a closed manifold (" << topology.boundary_edges << " boundary, "
         << topology.non_manifold_edges << " non-manifold edges, " << topology.non_manifold_vertices
         << " non-manifold vertices)";
  if (crossings.pairs > 0)
    text << (topology.closed_manifold() ? "" : " and ") << crossings.pairs << " intersecting triangle pairs";
  return text.str();
}

SurfaceSoundness check_soundness(const morph::TriangleMesh& mesh) {
  SurfaceSoundness soundness;
  tbb::task_group checks;
  checks.run([&] { soundness.topology = morph::topology_report(mesh); });
  checks.run([&] { soundness.crossings = find_self_intersections(mesh); });
  checks.wait();
  return soundness;
}

GeneratedSurface run_generator(const morph::Job& job, const morph::ErodeOptions& options, int generator) {
  check_generator(generator);
  GeneratedSurface out;
  if (generator != kAutoGenerator) {
    out.generator = generator;
    out.result = generator == 2 ? morph::erode2(job, options) : morph::erode(job, options);
    return out;
  }
  const std::string beyond = first_move_beyond_generator_1(job);
  if (!beyond.empty()) {
    out.generator = 2;
    out.choice = "generator 1 builds spheres and ball ends only, and " + beyond;
    out.result = morph::erode2(job, options);
    return out;
  }
  const auto start = std::chrono::steady_clock::now();
  const double tolerance = options.tolerance > 0.0 ? options.tolerance : job.tolerance;
  const morph::Erode2Estimate estimate = morph::estimate_erode2(job, tolerance);
  const bool over_cap = options.memory_cap_bytes > 0 && estimate.bytes > double(options.memory_cap_bytes);
  const bool retry = estimate.sweep_facets <= kAutoRetryFacets && !over_cap;
  // Where generator 2 would be tried, generator 1 may spend on its searches about what generator
  // 2 would cost in all (auto_search_limit(), or the caller's limit), and no more.
  morph::ErodeOptions first = options;
  if (retry && first.search_limit == 0) first.search_limit = auto_search_limit(estimate);
  std::ostringstream choice;
  out.generator = 1;
  try {
    out.result = morph::erode(job, first);
    out.soundness = check_soundness(out.result.mesh);
    if (out.soundness->sound()) {
      out.choice = "its surface is sound";
      return out;
    }
    choice << "generator 1's surface is unsound (" << out.soundness->describe() << ")";
  } catch (const morph::SearchLimitError&) {
    if (!retry) throw;  // the caller's own limit, with no generator to take the job instead
    choice << "generator 1 was stopped after " << first.search_limit
           << " searches of its sweep distances, about what generator 2 costs in all on this job";
  }
  if (!retry) {
    if (over_cap)
      choice << "; generator 2 was not tried: it would need about "
             << static_cast<long long>(estimate.bytes / (1 << 20)) << " MiB, over the memory cap of "
             << static_cast<long long>(options.memory_cap_bytes >> 20) << " MiB";
    else
      choice << "; generator 2 was not tried: it would sweep about "
             << static_cast<long long>(estimate.sweep_facets) << " facets, over auto's limit of "
             << static_cast<long long>(kAutoRetryFacets) << " (--generator 2 runs it anyway)";
    out.choice = choice.str();
    return out;
  }
  choice << "; generator 2 built it instead";
  const double first_seconds = seconds_since(start);
  out.generator = 2;
  out.result = {};  // generator 1's surface goes before generator 2 builds its own
  out.result = morph::erode2(job, options);
  if (out.soundness)
    out.result.stats.steps.insert(out.result.stats.steps.begin(), {"generator_1_unsound", 1, true});
  out.result.stats.seconds_total += first_seconds;
  out.soundness.reset();
  out.choice = choice.str();
  return out;
}

std::uint64_t auto_search_limit(const morph::Erode2Estimate& estimate) {
  return static_cast<std::uint64_t>(
      std::max(kAutoSearchFloor, std::ceil(kAutoSearchesPerFacet * estimate.sweep_facets)));
}

}  // namespace morphmill
