// SPDX-License-Identifier: Apache-2.0
#pragma once
// `morphmill stress`: runs the generator, the reference and the deviation measurement on many
// random cases (stress_cases.h), checks invariants on each, writes every failing case as a job
// that reproduces it, and summarises. Shards of one campaign can run apart and be merged.
#include <morph/progress.h>

#include <atomic>
#include <cstdint>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "campaigns/stress_cases.h"

namespace morphmill::stress {

struct StressOptions {
  std::size_t cases = 100;  ///< cases of the whole campaign (indices 0 .. cases-1)
  std::uint64_t seed = 1;
  std::string out_dir;
  std::size_t shard_index = 0;  ///< this run does the cases k with k % shard_count == shard_index
  std::size_t shard_count = 1;
  int threads = 0;                         ///< worker threads; 0 = all cores
  std::string families = "classic";        ///< --families: classic, motion, all or names (parse_families)
  std::size_t face_samples = 2000;         ///< area-uniform deviation samples per surface (plus every vertex)
  double reference_memory_cap_mib = 1024;  ///< per case: the reference refuses to need more
  double max_peak_rss_mib = 4096;          ///< the process's peak resident memory must stay below
  /// Continue the campaign already in out_dir (keep its finished cases, run the others) instead of
  /// starting afresh; its recorded options must equal these. Starts afresh if out_dir has none.
  bool resume = false;
  /// Explicit cancellation: once this holds a non-zero signal number, no further case starts; the
  /// cases in flight finish, and the summary says the run was stopped and what is missing.
  const std::atomic<int>* stop_signal = nullptr;
  morph::Progress* progress = nullptr;  ///< stage "stress: cases"
};

/// A campaign that did not run every case: a stopped run, or a merge missing shards or cases.
/// The message names the shards and cases missing (exit code 4, docs/stress.md).
struct IncompleteCampaign : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The identity of a campaign: everything that changes its results (the options --cases, --seed,
/// --families, --samples, --reference-memory-cap, --max-rss; the program's version and
/// source commit; the case
/// generator's version) and the shard count. Keys are named as the user knows them ("--samples").
/// Shards of one campaign have equal identities; `campaign.json` of a shard adds its "--shard".
nlohmann::json campaign_identity(const StressOptions& options);

/// Throws morph::InputError when a campaign.json records a generator other than 2 (generator 1
/// and auto were removed; such a campaign cannot be continued with --resume).
void check_recorded_generator(const nlohmann::json& campaign, const std::string& file);

/// The first key whose values differ, described as "--samples is 2000 in A but 500 in B"; "" if
/// the identities are equal.
std::string campaign_difference(const nlohmann::json& a, const std::string& a_name, const nlohmann::json& b,
                                const std::string& b_name);

/// The invariants checked on every case, in report order.
const std::vector<std::string>& invariant_names();

/// What one case measured and which invariants failed.
struct CaseResult {
  std::size_t index = 0;
  std::string family, variant;
  int expected_pieces = -1;
  std::optional<double> expected_volume;
  double tolerance = 0, voxel_size = 0, agreement_bound = 0;
  std::size_t generator_pieces = 0, reference_pieces = 0, generator_triangles = 0;
  /// Pieces of either side too small for the reference's voxels, judged by the exact field
  /// (VerifyOutcome::pieces_below_resolution).
  std::size_t pieces_below_resolution = 0;
  double generator_volume = 0, reference_volume = 0;
  std::size_t self_intersecting_pairs = 0;        ///< of the generator's triangles (exact)
  std::map<std::string, std::size_t> fallbacks;   ///< how often each generator fallback fired
  int expected_genus = -1, generator_genus = -1;  ///< sum over the pieces; -1: not known / not closed
  /// Largest |deviation| (job units) of each kind; NaN when not measured.
  double generator_to_exact = 0, exact_to_generator = 0, reference_to_exact = 0;
  double generator_to_reference = 0, reference_to_generator = 0;
  double seconds = 0, generator_seconds = 0, reference_seconds = 0, deviation_seconds = 0;
  double reference_memory_mib = 0;    ///< the reference's own grids and buffers
  double peak_rss_mib = 0;            ///< the process's peak resident memory after the case
  std::vector<std::string> failures;  ///< names from invariant_names()
  std::string error;                  ///< exception message, if one was thrown
};

nlohmann::json case_to_json(const CaseResult& result);
/// Throws morph::InputError naming `where` if the JSON lacks a field.
CaseResult case_from_json(const nlohmann::json& json, const std::string& where);

/// Runs one case (no files). Never throws for a failure of the case itself: it is recorded.
CaseResult run_case(std::uint64_t seed, std::size_t index, const StressOptions& options);

/// The cases' space of a campaign: its families (checked: InputError when unknown).
CaseSpace case_space(const StressOptions& options);

/// Summary of a campaign (or of merged shards): counts, failures by invariant and by family, the
/// worst deviation of each kind, and every case's result sorted by index.
struct Summary {
  nlohmann::json campaign;  ///< campaign_identity() of the runs combined
  std::uint64_t seed = 0;
  std::size_t cases = 0;                                    ///< of the whole campaign
  std::vector<std::pair<std::size_t, std::size_t>> shards;  ///< (index, count) of the runs combined
  double wall_seconds = 0;                                  ///< sum over the runs combined
  double peak_rss_mib = 0;                                  ///< largest over the runs combined
  int threads = 0;
  std::vector<CaseResult> results;
  /// Cases this summary should have covered (its shards' cases) that did not finish, increasing.
  std::vector<std::size_t> missing;
  /// Why cases are missing, one line each: "interrupted by SIGTERM", "shard 3/4 missing", ...
  std::vector<std::string> incomplete;
  bool merged = false;  ///< written by stress-merge

  std::size_t failed_cases() const;
  bool complete() const { return missing.empty(); }
  /// "partial: 30 of 40 cases, missing 3, 7, ..." ("" when complete).
  std::string partial_line() const;
};

nlohmann::json summary_to_json(const Summary& summary);
Summary summary_from_json(const nlohmann::json& json, const std::string& where);
/// summary.md: the tables a person reads.
std::string summary_markdown(const Summary& summary);

/// Runs the campaign's shard in options.out_dir. First removes the old verdict (summary.json,
/// summary.md) and, unless resuming, the old cases; writes campaign.json (the identity and the
/// shard), then each finished case's result as cases/case_NNNNNN.json the moment it finishes
/// (failing cases also as failures/case_NNNNNN.json + stock mesh), and the verdict last:
/// summary.md, then summary.json. Every file is written to a temporary name and renamed.
/// Throws morph::InputError for bad options (shard out of range, no cases, a resume with other
/// options than the campaign's), morph::IoError if the output cannot be written.
Summary run_stress(const StressOptions& options);

/// Combines the shard directories of one campaign into out_dir, which must be empty, absent or a
/// previous merge (replaced whole). Throws morph::InputError for shards of different campaigns
/// (naming the option that differs) or overlapping shards, and IncompleteCampaign when shards or
/// cases are missing (naming them, and the cases in flight of a shard killed while running)
/// unless `partial`, which merges what finished into a summary that says what is missing.
Summary merge_stress(const std::vector<std::string>& shard_dirs, const std::string& out_dir,
                     bool partial = false);

/// Writes summary.md, then summary.json, into dir (each atomically).
void write_summary(const Summary& summary, const std::string& dir);

/// The case indices of shard `shard_index` of `shard_count`: k in [0, cases) with k % shard_count ==
/// shard_index, increasing.
std::vector<std::size_t> shard_cases(std::size_t cases, std::size_t shard_index, std::size_t shard_count);

/// Parses "i/n" (0 <= i < n); throws morph::InputError otherwise.
std::pair<std::size_t, std::size_t> parse_shard(const std::string& text);

}  // namespace morphmill::stress
