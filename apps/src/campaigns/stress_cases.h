// SPDX-License-Identifier: Apache-2.0
#pragma once
// Random jobs built to break the generator: `morphmill stress` draws one per case index.
// Every case is a job file (JSON, docs/job-format.md) plus, for mesh stock, the stock mesh, and
// carries what is known about its result by construction (piece count, sometimes the volume).
#include <morph/mesh.h>

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace morphmill::stress {

/// A deterministic stream of random numbers (SplitMix64): the same seed gives the same numbers on
/// every platform and standard library, unlike the std:: distributions.
class CaseRandom {
 public:
  explicit CaseRandom(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next();
  /// Uniform in [low, high).
  double uniform(double low, double high);
  /// Uniform integer in [low, high].
  int integer(int low, int high);
  /// True with probability p.
  bool chance(double p);

 private:
  std::uint64_t state_;
};

/// One stress case: a job and what its result must be.
struct StressCase {
  std::uint64_t seed = 0;  ///< the campaign's seed
  std::size_t index = 0;   ///< the case's index in the campaign
  std::string family;      ///< what it is built to break, e.g. "through_slots" (see case_families())
  std::string variant;     ///< the family's choices in words, e.g. "box, ballend, 3 slots along y"
  nlohmann::json job;      ///< the job file's content; a mesh stock is referenced by "path": stock_file
  std::optional<morph::TriangleMesh> stock_mesh;  ///< mesh stock, written next to the job as stock_file
  std::string stock_file;                         ///< file name of the stock mesh ("" without one)
  std::string
      gcode_file;  ///< file name of the case's G-code program, written next to the job ("" without one)
  std::string gcode_text;    ///< that program
  int expected_pieces = -1;  ///< solid pieces of the result known by construction; -1 if not known
  /// Volume of the result known by construction (passes that never enter the stock), job units^3.
  std::optional<double> expected_volume;
  /// Sum of the genus of the result's pieces known by construction (blind cuts leave genus 0, each
  /// contour cut through a sheet adds one tunnel); -1 if not known.
  int expected_genus = -1;
  double voxel_size = 0.0;  ///< reference voxel for this case, job units
};

/// The version of the case generator: raise it with every change to make_case() that changes a
/// job, so shards drawn by different generators are never merged as one campaign.
constexpr int kCaseGeneratorVersion = 2;

/// The classic families (splits, islands, removed pieces, self-crossing, coincident, tangent and
/// grazing passes, features at the tolerance, passes outside; box, cylinder and mesh stock), in
/// the order the case index cycles through them: the default campaign.
const std::vector<std::string>& case_families();

/// The motion families (stress_motions.cpp): retraces, plunge and retract, reversals up to
/// 179.99 degrees and 180, sub-micron moves, arcs in G17/G18/G19 and helices, sheet cut-outs
/// freeing parts and slugs, paths crossing themselves dozens of times, several tools in one job;
/// box stock, blind cuts with known volume where a closed form exists.
const std::vector<std::string>& motion_families();

/// What a campaign draws its cases from.
struct CaseSpace {
  std::vector<std::string> families = case_families();  ///< cycled through by the case index
};

/// Families from --families: "classic" (default), "motion", "all", or names separated by commas.
/// Throws morph::InputError naming an unknown family and listing the known ones.
std::vector<std::string> parse_families(const std::string& text);

/// The case `index` of the campaign `seed`: deterministic (same arguments, same job bytes).
StressCase make_case(std::uint64_t seed, std::size_t index, const CaseSpace& space = {});

/// "case_000123".
std::string case_name(std::size_t index);

/// Writes the job as `<dir>/<file_name>` (2-space indented JSON) and the stock mesh, if any, as
/// `<dir>/<stock_file>`; creates `dir`. Returns the job file's path. Throws morph::IoError.
std::string write_case(const StressCase& stress_case, const std::string& dir, const std::string& file_name);

}  // namespace morphmill::stress
