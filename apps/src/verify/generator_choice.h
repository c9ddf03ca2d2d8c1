// SPDX-License-Identifier: Apache-2.0
#pragma once
// Which surface generator a command runs (`--generator`): 2, the default (morph::erode2: the
// union of exact sweep polytopes, closed by construction; every tool of revolution, every stock);
// 1, the sweep-patch generator (morph::erode: sphere and ball-end tools, every stock); or auto,
// which takes generator 1's surface when it is sound and generator 2's otherwise. One place decides what each
// can build, so erode, verify, compare, stress and study agree.
#include <morph/erode.h>
#include <morph/erode2.h>
#include <morph/job.h>
#include <morph/topology.h>
#include <morphmill/self_intersections.h>

#include <cstdint>
#include <optional>
#include <string>

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace morphmill {

/// `--generator auto`: generator 1 where it builds a sound surface, generator 2 where it does not.
constexpr int kAutoGenerator = 0;

/// The generator commands run when --generator is not given: generator 2, which builds a sound
/// surface on every bundled job and real program, and faster than generator 1 wherever generator
/// 1's is sound (docs/design/generator.md, "Generator 2 by default").
constexpr int kDefaultGenerator = 2;

/// Generator 2's estimated sweep facets (morph::estimate_erode2) up to which `auto` hands a job
/// whose generator-1 surface is unsound to generator 2: about a minute of generator 2 on this
/// project's 2-core machine at today's speed (2026-11-27: bear.nc at 0.01 is estimated at 11.8
/// million and takes 30 s; generator 1 leaves it with 1,316 intersecting triangle pairs). Nor is
/// generator 2 tried when its estimated memory is over the caller's cap.
constexpr double kAutoRetryFacets = 2e7;

/// Generator 1's searches of its exact sweep distances (ErodeOptions::search_limit) that auto
/// allows per sweep facet generator 2 would make, where it would try generator 2: about what
/// generator 2 costs in all. Measured on this 2-core machine (2026-11-27): generator 1 runs about
/// 1.7 million searches a second where they are its time, generator 2 sweeps 200,000 to 400,000
/// facets a second. Most jobs need far fewer (bear.nc at 0.01: 0.12 a facet, slots.json 0.19); heart's
/// deep ball-end pockets 572, ten minutes of generator 1 where generator 2 takes eight seconds.
constexpr double kAutoSearchesPerFacet = 5.0;
/// ... and at least this many (well under a second), so that a small job is not judged by them.
constexpr double kAutoSearchFloor = 1e6;

/// The search limit auto gives generator 1 on a job of this estimate.
std::uint64_t auto_search_limit(const morph::Erode2Estimate& estimate);

/// Adds `--generator auto|1|2` to `command`, stored as kAutoGenerator, 1 or 2.
CLI::Option* add_generator_option(CLI::App& command, int& generator);

/// Throws morph::InputError unless `generator` is kAutoGenerator, 1 or 2.
void check_generator(int generator);

/// "auto", "1" or "2".
std::string generator_name(int generator);

/// Whether `generator` (kAutoGenerator, 1 or 2) builds `tool`: generator 1 spheres and ball ends,
/// generator 2 and auto every tool of revolution.
bool generator_builds(const morph::Tool& tool, int generator);

/// Why `generator` cannot build `job`, as a sentence naming the move and tool or the stock ("" if
/// it can build it all; auto builds every job).
std::string why_generator_cannot_build(const morph::Job& job, int generator);

/// Whether a surface is what erode promises: a closed, oriented 2-manifold free of
/// self-intersections (exact predicates).
struct SurfaceSoundness {
  morph::TopologyReport topology;
  SelfIntersections crossings;
  bool sound() const { return topology.closed_manifold() && crossings.pairs == 0; }
  /// What is wrong, e.g. "open (12 boundary edges) with 3 intersecting pairs" ("sound" if nothing).
  std::string describe() const;
};

/// Checks `mesh` (topology and exact self-intersections, side by side on all cores).
SurfaceSoundness check_soundness(const morph::TriangleMesh& mesh);

/// A generator's surface and which generator built it.
struct GeneratedSurface {
  morph::ErodeResult result;
  int generator = 1;  ///< 1 or 2: the generator whose surface `result` is
  /// How auto chose, as a sentence ("" when the generator was given).
  std::string choice;
  /// The soundness of `result.mesh`, when auto checked it (the caller need not check again).
  std::optional<SurfaceSoundness> soundness;
};

/// Runs the generator chosen (checked with check_generator). Auto runs generator 2 for a job
/// generator 1 cannot build; otherwise generator 1, and when generator 2's estimate is within
/// kAutoRetryFacets and generator 1's surface is unsound (then a fallback step
/// `generator_1_unsound` is counted in generator 2's stats) or generator 1 passes its search limit
/// (auto_search_limit(), or options.search_limit when the caller gives one), generator 2.
GeneratedSurface run_generator(const morph::Job& job, const morph::ErodeOptions& options, int generator);

}  // namespace morphmill
