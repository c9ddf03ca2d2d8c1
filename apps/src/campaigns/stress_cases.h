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
  int expected_pieces = -1;  ///< solid pieces of the result known by construction; -1 if not known
  /// Volume of the result known by construction (passes that never enter the stock), job units^3.
  std::optional<double> expected_volume;
  double voxel_size = 0.0;  ///< reference voxel for this case, job units
};

/// The version of the case generator: raise it with every change to make_case() that changes a
/// job, so shards drawn by different generators are never merged as one campaign.
constexpr int kCaseGeneratorVersion = 1;

/// The families in the order the case index cycles through them.
const std::vector<std::string>& case_families();

/// The case `index` of the campaign `seed`: deterministic (same arguments, same job bytes).
StressCase make_case(std::uint64_t seed, std::size_t index);

/// "case_000123".
std::string case_name(std::size_t index);

/// Writes the job as `<dir>/<file_name>` (2-space indented JSON) and the stock mesh, if any, as
/// `<dir>/<stock_file>`; creates `dir`. Returns the job file's path. Throws morph::IoError.
std::string write_case(const StressCase& stress_case, const std::string& dir, const std::string& file_name);

}  // namespace morphmill::stress
