// SPDX-License-Identifier: Apache-2.0
#include "campaigns/stress.h"

#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <morph/stock.h>
#include <morphmill/job_io.h>
#include <morphmill/self_intersections.h>
#include <sys/resource.h>
#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>

#include <unistd.h>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <thread>

#include "campaigns/stress_cases.h"
#include "cli/memory_cap.h"
#include "cli/stop_signals.h"
#include "io/build_info.h"
#include "verify/verify.h"

namespace morphmill::stress {

namespace fs = std::filesystem;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double process_peak_rss_mib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // KiB on Linux
}

double stage_seconds(const VerifyOutcome& outcome, const std::string& name) {
  for (const auto& stage : outcome.stages)
    if (stage.name == name) return stage.seconds;
  return 0.0;
}

void fail(CaseResult& result, const std::string& invariant) {
  if (std::find(result.failures.begin(), result.failures.end(), invariant) == result.failures.end())
    result.failures.push_back(invariant);
}

/// JSON has no NaN: unmeasured values are written as null and read back as NaN.
nlohmann::json number_or_null(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json();
}
double number_from(const nlohmann::json& json) {
  return json.is_number() ? json.get<double>() : kNaN;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw morph::IoError(path.string() + ": cannot read");
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// A reader (or a kill) sees the old file or the new one, never a part.
void write_text(const fs::path& path, const std::string& text) {
  morph::write_file_atomically(path.string(), text);
}

nlohmann::json read_json(const fs::path& path) {
  try {
    return nlohmann::json::parse(read_text(path));
  } catch (const nlohmann::json::exception& e) {
    throw morph::InputError(path.string() + ": " + e.what());
  }
}

/// "1, 5, 9" for up to `shown` indices, then "... (N more)".
std::string index_list(const std::vector<std::size_t>& indices, std::size_t shown = 40) {
  std::string text;
  for (std::size_t i = 0; i < indices.size() && i < shown; ++i)
    text += (i ? ", " : "") + std::to_string(indices[i]);
  if (indices.size() > shown) text += fmt::format(", ... ({} more)", indices.size() - shown);
  return text;
}

/// Case indices from the case_NNNNNN*.json names in dir (none if dir does not exist).
std::vector<std::size_t> indices_in(const fs::path& dir) {
  std::set<std::size_t> found;
  std::error_code error;
  if (!fs::is_directory(dir, error)) return {};
  for (const auto& entry : fs::directory_iterator(dir, error)) {
    const std::string name = entry.path().filename().string();
    if (name.size() != 16 || name.rfind("case_", 0) != 0 || entry.path().extension() != ".json") continue;
    try {
      found.insert(std::stoul(name.substr(5, 6)));
    } catch (const std::exception&) {
    }
  }
  return {found.begin(), found.end()};
}

/// The finished cases' results kept in dir/cases/ (each written atomically when its case ended).
std::vector<CaseResult> finished_results(const fs::path& dir) {
  std::vector<CaseResult> results;
  for (std::size_t index : indices_in(dir / "cases")) {
    const fs::path file = dir / "cases" / (case_name(index) + ".json");
    results.push_back(case_from_json(read_json(file), file.string()));
  }
  return results;
}

/// The kinds of deviation the summary reports the worst of, with the bound each is held to.
struct DeviationKind {
  const char* name;
  double CaseResult::*value;
  const char* bound_name;
};

const DeviationKind kDeviationKinds[] = {
    {"generator_to_exact", &CaseResult::generator_to_exact, "tolerance"},
    {"exact_to_generator", &CaseResult::exact_to_generator, "tolerance"},
    {"reference_to_exact", &CaseResult::reference_to_exact, "sqrt(3) voxel"},
    {"generator_to_reference", &CaseResult::generator_to_reference, "tolerance + sqrt(3) voxel"},
    {"reference_to_generator", &CaseResult::reference_to_generator, "tolerance + sqrt(3) voxel"},
};

double bound_of(const CaseResult& r, const std::string& bound_name) {
  if (bound_name == "tolerance") return r.tolerance;
  if (bound_name == "sqrt(3) voxel") return std::sqrt(3.0) * r.voxel_size;
  return r.agreement_bound;
}

struct Worst {
  double value = kNaN, bound = kNaN, ratio = kNaN;
  std::size_t index = 0;
  bool found = false;
};

Worst worst_of(const std::vector<CaseResult>& results, const DeviationKind& kind) {
  Worst worst;
  for (const auto& r : results) {
    const double value = r.*(kind.value);
    if (!std::isfinite(value)) continue;
    const double bound = bound_of(r, kind.bound_name);
    const double ratio = value / bound;
    if (!worst.found || ratio > worst.ratio) worst = {value, bound, ratio, r.index, true};
  }
  return worst;
}

std::string fixed(double value, int digits = 4) {
  return std::isfinite(value) ? fmt::format("{:.{}g}", value, digits) : std::string("-");
}

}  // namespace

const std::vector<std::string>& invariant_names() {
  static const std::vector<std::string> names = {
      "no_exception",                // erode, reference and deviation ran without throwing
      "memory_bounded",              // reference within its cap; process peak RSS below the limit
      "closed_manifold",             // the generator's output is a closed oriented 2-manifold
      "no_self_intersections",       // generator 2: no two of its triangles cross (exact predicates)
      "pieces_known",                // the generator finds the piece count known by construction
      "reference_pieces_known",      // so does the reference
      "pieces_match_reference",      // same count, volumes within half a voxel times the area
      "volume_known",                // the generator's volume is the closed form's (tolerance x stock area)
      "genus_known",                 // the generator's pieces have the genus known by construction
      "generator_within_tolerance",  // generator <-> exact surface, both ways, within the tolerance
      "sides_agree",                 // two-sided generator <-> reference within tolerance + sqrt(3) voxel
  };
  return names;
}

CaseSpace case_space(const StressOptions& options) {
  return CaseSpace{parse_families(options.families)};
}

CaseResult run_case(std::uint64_t seed, std::size_t index, const StressOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CaseResult result;
  result.index = index;
  result.generator_to_exact = result.exact_to_generator = result.reference_to_exact = kNaN;
  result.generator_to_reference = result.reference_to_generator = kNaN;
  const fs::path running = fs::path(options.out_dir) / "running";
  fs::path job_path;
  std::string stock_file, gcode_file;
  try {
    const StressCase c = make_case(seed, index, case_space(options));
    result.family = c.family;
    result.expected_genus = c.expected_genus;
    result.variant = c.variant;
    result.expected_pieces = c.expected_pieces;
    result.expected_volume = c.expected_volume;
    result.voxel_size = c.voxel_size;
    stock_file = c.stock_file;
    gcode_file = c.gcode_file;
    // The job goes through its file, so what ran is exactly what the failure file reproduces; it
    // stays in running/ while the case runs, so a crash leaves the cases in flight behind.
    job_path = write_case(c, running.string(), case_name(index) + ".json");
    const morph::Job job = load_job(job_path.string());
    result.tolerance = job.tolerance;
    EvaluateOptions evaluate;
    evaluate.voxel_size = c.voxel_size;
    evaluate.face_samples = options.face_samples;
    evaluate.reference_memory_cap_bytes =
        static_cast<std::size_t>(options.reference_memory_cap_mib * 1048576.0);
    evaluate.generator_memory_cap_bytes = memory_cap_bytes(default_memory_cap_gib());
    const Evaluation evaluation = evaluate_job(job, evaluate);
    const VerifyOutcome& o = evaluation.outcome;
    result.agreement_bound = o.agreement_bound;
    result.generator_pieces = o.morph_pieces.size();
    result.reference_pieces = o.reference_pieces.size();
    result.pieces_below_resolution = o.pieces_below_resolution;
    result.generator_triangles = o.morph_triangles;
    for (const morph::StepCount& step : o.generator_steps)
      if (step.fallback) result.fallbacks[step.name] = step.count;
    result.generator_volume = o.morph_topology.volume;
    if (o.morph_topology.closed_manifold())
      result.generator_genus = static_cast<int>(
          (2 * static_cast<long>(o.morph_topology.components) - o.morph_topology.euler_characteristic) / 2);
    for (const auto& piece : o.reference_pieces) result.reference_volume += piece.volume;
    result.generator_to_exact = o.morph_to_exact.stats.count ? o.morph_to_exact.stats.max_abs : kNaN;
    result.exact_to_generator = o.exact_to_morph.count ? o.exact_to_morph.max_abs : kNaN;
    result.reference_to_exact = o.reference_to_exact.stats.count ? o.reference_to_exact.stats.max_abs : kNaN;
    result.generator_to_reference =
        o.morph_to_reference.stats.count ? o.morph_to_reference.stats.max_abs : kNaN;
    result.reference_to_generator =
        o.reference_to_morph.stats.count ? o.reference_to_morph.stats.max_abs : kNaN;
    result.generator_seconds = stage_seconds(o, "generator (morph)");
    result.reference_seconds = stage_seconds(o, "reference (OpenVDB)");
    result.deviation_seconds = stage_seconds(o, "deviation (Embree)");
    result.reference_memory_mib = static_cast<double>(evaluation.reference_stats.memory_bytes) / 1048576.0;

    if (!o.morph_topology.closed_manifold()) fail(result, "closed_manifold");
    if (o.generator_skipped.empty()) {
      // Cases run in parallel already: the check runs on this thread.
      result.self_intersecting_pairs = find_self_intersections(evaluation.morph_mesh, 1, false).pairs;
      if (result.self_intersecting_pairs > 0) fail(result, "no_self_intersections");
    }
    if (c.expected_pieces >= 0) {
      // A family's count is what its passes leave at the scale of the tool. The exact solid may
      // leave more: a chip far below the voxels (stress seed 103, case 3171: a sliver 0.007 mm
      // thick where two end caps meet a cylinder's rim, exact material by the exact field). Such
      // a chip counts here only when verify's piece rule has not found it exact material.
      const double unseen = std::pow(2.0 * o.voxel_size, 3);
      const auto chips =
          static_cast<std::size_t>(std::count_if(o.morph_pieces.begin(), o.morph_pieces.end(),
                                                 [&](const auto& piece) { return piece.volume < unseen; }));
      const auto expected = static_cast<std::size_t>(c.expected_pieces);
      if (result.generator_pieces != expected &&
          !(o.pieces_match && result.generator_pieces - chips == expected))
        fail(result, "pieces_known");
      if (result.reference_pieces != static_cast<std::size_t>(c.expected_pieces))
        fail(result, "reference_pieces_known");
    }
    if (!o.pieces_match) fail(result, "pieces_match_reference");
    if (c.expected_volume) {
      // Within the tolerance everywhere, the volume is within tolerance x area of the truth.
      const double bound = job.tolerance * morph::surface_area(job.stock);
      if (!(std::abs(result.generator_volume - *c.expected_volume) <= bound)) fail(result, "volume_known");
    }
    if (c.expected_genus >= 0 && result.generator_genus != c.expected_genus) fail(result, "genus_known");
    if (!o.generator_within_tolerance) fail(result, "generator_within_tolerance");
    if (!o.sides_agree) fail(result, "sides_agree");
  } catch (const morph::LimitError& e) {
    fail(result, "memory_bounded");
    result.error = std::string("LimitError: ") + e.what();
  } catch (const std::exception& e) {
    fail(result, "no_exception");
    result.error = e.what();
  } catch (...) {
    fail(result, "no_exception");
    result.error = "unknown exception";
  }
  result.peak_rss_mib = process_peak_rss_mib();
  if (result.peak_rss_mib > options.max_peak_rss_mib) fail(result, "memory_bounded");
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // Keep the job (and stock mesh) of a failing case, or of one where a generator fallback fired
  // (their target is zero), as a standalone reproduction.
  const bool fallback_fired = std::any_of(result.fallbacks.begin(), result.fallbacks.end(),
                                          [](const auto& f) { return f.second > 0; });
  if (!result.failures.empty() || fallback_fired) {
    try {
      const StressCase c = make_case(seed, index, case_space(options));
      const fs::path kept = fs::path(options.out_dir) / (result.failures.empty() ? "fallbacks" : "failures");
      write_case(c, kept.string(), case_name(index) + ".json");
      write_text(kept / (case_name(index) + ".result.json"), case_to_json(result).dump(2) + "\n");
    } catch (const std::exception& e) {
      result.error += std::string(result.error.empty() ? "" : "; ") + "writing the reproduction: " + e.what();
    }
  }
  std::error_code ignored;
  if (!job_path.empty()) fs::remove(job_path, ignored);
  if (!stock_file.empty()) fs::remove(running / stock_file, ignored);
  if (!gcode_file.empty()) fs::remove(running / gcode_file, ignored);
  return result;
}

nlohmann::json case_to_json(const CaseResult& r) {
  return {{"index", r.index},
          {"family", r.family},
          {"variant", r.variant},
          {"expected_pieces", r.expected_pieces},
          {"expected_volume", r.expected_volume ? nlohmann::json(*r.expected_volume) : nlohmann::json()},
          {"tolerance", r.tolerance},
          {"voxel_size", r.voxel_size},
          {"agreement_bound", r.agreement_bound},
          {"pieces",
           {{"generator", r.generator_pieces},
            {"reference", r.reference_pieces},
            {"below_resolution", r.pieces_below_resolution}}},
          {"volume", {{"generator", r.generator_volume}, {"reference", r.reference_volume}}},
          {"generator_triangles", r.generator_triangles},
          {"genus", {{"expected", r.expected_genus}, {"generator", r.generator_genus}}},
          {"self_intersecting_pairs", r.self_intersecting_pairs},
          {"fallbacks", r.fallbacks},
          {"deviation",
           {{"generator_to_exact", number_or_null(r.generator_to_exact)},
            {"exact_to_generator", number_or_null(r.exact_to_generator)},
            {"reference_to_exact", number_or_null(r.reference_to_exact)},
            {"generator_to_reference", number_or_null(r.generator_to_reference)},
            {"reference_to_generator", number_or_null(r.reference_to_generator)}}},
          {"seconds",
           {{"total", r.seconds},
            {"generator", r.generator_seconds},
            {"reference", r.reference_seconds},
            {"deviation", r.deviation_seconds}}},
          {"reference_memory_mib", r.reference_memory_mib},
          {"peak_rss_mib", r.peak_rss_mib},
          {"failures", r.failures},
          {"error", r.error}};
}

CaseResult case_from_json(const nlohmann::json& j, const std::string& where) {
  try {
    CaseResult r;
    r.index = j.at("index").get<std::size_t>();
    r.family = j.at("family").get<std::string>();
    r.variant = j.at("variant").get<std::string>();
    r.expected_pieces = j.at("expected_pieces").get<int>();
    if (j.at("expected_volume").is_number()) r.expected_volume = j["expected_volume"].get<double>();
    r.tolerance = j.at("tolerance").get<double>();
    r.voxel_size = j.at("voxel_size").get<double>();
    r.agreement_bound = j.at("agreement_bound").get<double>();
    r.generator_pieces = j.at("pieces").at("generator").get<std::size_t>();
    r.reference_pieces = j.at("pieces").at("reference").get<std::size_t>();
    r.pieces_below_resolution = j.at("pieces").value("below_resolution", std::size_t{0});
    r.generator_volume = j.at("volume").at("generator").get<double>();
    r.reference_volume = j.at("volume").at("reference").get<double>();
    r.self_intersecting_pairs = j.value("self_intersecting_pairs", std::size_t{0});
    r.fallbacks = j.value("fallbacks", std::map<std::string, std::size_t>{});
    if (j.contains("genus")) {
      r.expected_genus = j["genus"].at("expected").get<int>();
      r.generator_genus = j["genus"].at("generator").get<int>();
    }
    r.generator_triangles = j.at("generator_triangles").get<std::size_t>();
    const auto& d = j.at("deviation");
    r.generator_to_exact = number_from(d.at("generator_to_exact"));
    r.exact_to_generator = number_from(d.at("exact_to_generator"));
    r.reference_to_exact = number_from(d.at("reference_to_exact"));
    r.generator_to_reference = number_from(d.at("generator_to_reference"));
    r.reference_to_generator = number_from(d.at("reference_to_generator"));
    const auto& s = j.at("seconds");
    r.seconds = s.at("total").get<double>();
    r.generator_seconds = s.at("generator").get<double>();
    r.reference_seconds = s.at("reference").get<double>();
    r.deviation_seconds = s.at("deviation").get<double>();
    r.reference_memory_mib = j.at("reference_memory_mib").get<double>();
    r.peak_rss_mib = j.at("peak_rss_mib").get<double>();
    r.failures = j.at("failures").get<std::vector<std::string>>();
    r.error = j.at("error").get<std::string>();
    return r;
  } catch (const nlohmann::json::exception& e) {
    throw morph::InputError(where + ": not a stress case result: " + e.what());
  }
}

namespace {

/// The families of --families as one canonical text: "classic", "motion", "all" or the names.
std::string families_text(const std::string& given) {
  if (given == "classic" || given == "motion" || given == "all" || given.empty())
    return given.empty() ? "classic" : given;
  std::string text;
  for (const auto& name : parse_families(given)) text += (text.empty() ? "" : ",") + name;
  return text;
}

}  // namespace

void check_recorded_generator(const nlohmann::json& campaign, const std::string& file) {
  // Campaigns before generators had names recorded 0 (auto), 1 or 2, and none recorded nothing (1).
  const auto it = campaign.find("--generator");
  if (it != campaign.end() && (*it == "2" || *it == 2)) return;
  throw morph::InputError(file + ": the campaign ran --generator " +
                          (it == campaign.end() ? std::string("1") : it->dump()) +
                          ", which was removed (the one generator left is 2): start a new campaign");
}

nlohmann::json campaign_identity(const StressOptions& options) {
  return {{"program", "morphmill"},
          {"version", program_version()},
          {"source_commit", source_commit()},
          {"case_generator", kCaseGeneratorVersion},
          {"--cases", options.cases},
          {"--seed", options.seed},
          {"--generator", "2"},  // the only generator since 1 and auto were removed
          {"--families", families_text(options.families)},
          {"--samples", options.face_samples},
          {"--reference-memory-cap", options.reference_memory_cap_mib},
          {"--max-rss", options.max_peak_rss_mib},
          {"shards", options.shard_count}};
}

std::string campaign_difference(const nlohmann::json& a, const std::string& a_name, const nlohmann::json& b,
                                const std::string& b_name) {
  std::set<std::string> keys;
  for (const auto& [key, value] : a.items()) keys.insert(key);
  for (const auto& [key, value] : b.items()) keys.insert(key);
  for (const auto& key : keys) {
    const nlohmann::json left = a.contains(key) ? a[key] : nlohmann::json("(absent)");
    const nlohmann::json right = b.contains(key) ? b[key] : nlohmann::json("(absent)");
    if (left != right)
      return fmt::format("{} is {} in {} but {} in {}", key, left.dump(), a_name, right.dump(), b_name);
  }
  return "";
}

std::string Summary::partial_line() const {
  if (missing.empty()) return "";
  return fmt::format("partial: {} of {} cases, missing {}", results.size(), results.size() + missing.size(),
                     index_list(missing));
}

std::size_t Summary::failed_cases() const {
  return static_cast<std::size_t>(
      std::count_if(results.begin(), results.end(), [](const CaseResult& r) { return !r.failures.empty(); }));
}

nlohmann::json summary_to_json(const Summary& s) {
  nlohmann::json j;
  j["campaign"] = s.campaign;
  j["merged"] = s.merged;
  j["complete"] = s.complete();
  j["partial"] = s.partial_line();
  j["missing_cases"] = s.missing;
  j["incomplete"] = s.incomplete;
  j["seed"] = s.seed;
  j["cases"] = s.cases;
  j["shards"] = nlohmann::json::array();
  for (const auto& [index, count] : s.shards) j["shards"].push_back({{"index", index}, {"count", count}});
  j["cases_run"] = s.results.size();
  j["failed_cases"] = s.failed_cases();
  j["wall_seconds"] = s.wall_seconds;
  j["peak_rss_mib"] = s.peak_rss_mib;
  j["threads"] = s.threads;
  nlohmann::json by_invariant = nlohmann::json::object();
  for (const auto& name : invariant_names()) by_invariant[name] = 0;
  nlohmann::json by_family = nlohmann::json::object();
  double seconds_sum = 0, seconds_max = 0;
  for (const auto& r : s.results) {
    for (const auto& f : r.failures)
      by_invariant[f] = (by_invariant.contains(f) ? by_invariant[f].get<int>() : 0) + 1;
    if (!by_family.contains(r.family)) by_family[r.family] = {{"cases", 0}, {"failed", 0}};
    auto& family = by_family[r.family];
    family["cases"] = family["cases"].get<int>() + 1;
    family["failed"] = family["failed"].get<int>() + (r.failures.empty() ? 0 : 1);
    seconds_sum += r.seconds;
    seconds_max = std::max(seconds_max, r.seconds);
  }
  j["failures_by_invariant"] = by_invariant;
  j["cases_by_family"] = by_family;
  j["case_seconds"] = {{"mean", s.results.empty() ? 0.0 : seconds_sum / s.results.size()},
                       {"max", seconds_max}};
  for (const auto& kind : kDeviationKinds) {
    const Worst w = worst_of(s.results, kind);
    j["worst_deviation"][kind.name] = {{"value", number_or_null(w.value)},
                                       {"bound", number_or_null(w.bound)},
                                       {"bound_is", kind.bound_name},
                                       {"ratio_to_bound", number_or_null(w.ratio)},
                                       {"case", w.found ? nlohmann::json(w.index) : nlohmann::json()}};
  }
  j["results"] = nlohmann::json::array();
  for (const auto& r : s.results) j["results"].push_back(case_to_json(r));
  return j;
}

Summary summary_from_json(const nlohmann::json& j, const std::string& where) {
  try {
    Summary s;
    if (!j.contains("campaign"))
      throw morph::InputError(where +
                              ": no campaign identity (written by an older morphmill): run the shard again");
    s.campaign = j.at("campaign");
    s.merged = j.at("merged").get<bool>();
    s.missing = j.at("missing_cases").get<std::vector<std::size_t>>();
    s.incomplete = j.at("incomplete").get<std::vector<std::string>>();
    s.seed = j.at("seed").get<std::uint64_t>();
    s.cases = j.at("cases").get<std::size_t>();
    for (const auto& shard : j.at("shards"))
      s.shards.emplace_back(shard.at("index").get<std::size_t>(), shard.at("count").get<std::size_t>());
    s.wall_seconds = j.at("wall_seconds").get<double>();
    s.peak_rss_mib = j.at("peak_rss_mib").get<double>();
    s.threads = j.at("threads").get<int>();
    for (std::size_t i = 0; i < j.at("results").size(); ++i)
      s.results.push_back(case_from_json(j["results"][i], where + ": results[" + std::to_string(i) + "]"));
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw morph::InputError(where + ": not a stress summary: " + e.what());
  }
}

std::string summary_markdown(const Summary& s) {
  std::ostringstream md;
  const std::size_t failed = s.failed_cases();
  md << "# MorphMill stress campaign: seed " << s.seed << "\n\n";
  if (!s.complete()) {
    md << "**" << s.partial_line() << "**\n\n";
    for (const auto& line : s.incomplete) md << "- " << line << "\n";
    md << "\n";
  }
  md << "**" << (failed == 0 ? "No failures" : fmt::format("{} failing case(s)", failed)) << "** in "
     << s.results.size() << " case(s) run of " << s.cases << (s.complete() ? "" : " (incomplete)") << ".\n\n";
  md << "| item | value |\n|---|---|\n";
  md << "| shards | ";
  for (std::size_t i = 0; i < s.shards.size(); ++i)
    md << (i ? ", " : "") << s.shards[i].first << "/" << s.shards[i].second;
  md << " |\n| wall time (s, summed over shards) | " << fmt::format("{:.1f}", s.wall_seconds) << " |\n";
  md << "| peak resident memory (MiB) | " << fmt::format("{:.0f}", s.peak_rss_mib) << " |\n";
  md << "| threads | " << s.threads << " |\n";
  std::size_t crossing_cases = 0, crossing_pairs = 0;
  for (const auto& r : s.results) {
    crossing_cases += r.self_intersecting_pairs > 0;
    crossing_pairs += r.self_intersecting_pairs;
  }
  md << "| generator's self-intersecting triangle pairs | " << crossing_pairs << " in " << crossing_cases
     << " case(s) |\n";
  std::map<std::string, std::size_t> fallbacks;
  std::size_t fallback_cases = 0, fallbacks_fired = 0;
  for (const auto& r : s.results) {
    std::size_t fired = 0;
    for (const auto& [name, count] : r.fallbacks) {
      fallbacks[name] += count;
      fired += count;
    }
    fallback_cases += fired > 0;
    fallbacks_fired += fired;
  }
  md << "| generator's fallbacks fired (target 0) | " << fallbacks_fired << " in " << fallback_cases
     << " case(s)";
  std::string fired_names;
  for (const auto& [name, count] : fallbacks)
    if (count > 0) fired_names += (fired_names.empty() ? "" : ", ") + name + " " + std::to_string(count);
  md << (fired_names.empty() ? "" : ": " + fired_names) << " |\n";
  for (const char* key : {"version", "source_commit", "case_generator", "--generator", "--families",
                          "--samples", "--reference-memory-cap", "--max-rss"})
    if (s.campaign.contains(key)) md << "| " << key << " | " << s.campaign[key].dump() << " |\n";
  md << "\n";

  md << "## Failures by invariant\n\n| invariant | failing cases |\n|---|---|\n";
  std::map<std::string, std::size_t> counts;
  for (const auto& r : s.results)
    for (const auto& f : r.failures) ++counts[f];
  for (const auto& name : invariant_names()) md << "| " << name << " | " << counts[name] << " |\n";

  md << "\n## Cases by family\n\n| family | cases | failed |\n|---|---|---|\n";
  std::map<std::string, std::pair<std::size_t, std::size_t>> families;
  for (const auto& r : s.results) {
    ++families[r.family].first;
    if (!r.failures.empty()) ++families[r.family].second;
  }
  for (const auto& [name, count] : families)
    md << "| " << name << " | " << count.first << " | " << count.second << " |\n";

  md << "\n## Worst deviation of each kind\n\nLargest ratio of the measured maximum |deviation| to the bound "
        "it "
        "is held to (job units).\n\n| kind | value | bound | bound is | ratio | case "
        "|\n|---|---|---|---|---|---|\n";
  for (const auto& kind : kDeviationKinds) {
    const Worst w = worst_of(s.results, kind);
    md << "| " << kind.name << " | " << fixed(w.value) << " | " << fixed(w.bound) << " | " << kind.bound_name
       << " | " << fixed(w.ratio, 3) << " | " << (w.found ? case_name(w.index) : "-") << " |\n";
  }

  if (failed > 0) {
    md << "\n## Failing cases\n\nEach is in failures/ as a job file; `morphmill verify failures/CASE.json "
          "--output OUT "
          "--voxel V` reproduces it (V is in the job's description).\n\n"
          "| case | family | variant | pieces expected / generator / reference | failed invariants | error "
          "|\n"
          "|---|---|---|---|---|---|\n";
    std::size_t listed = 0;
    for (const auto& r : s.results) {
      if (r.failures.empty()) continue;
      if (++listed > 200) {
        md << "| ... | | | | | (" << failed - 200 << " more in summary.json) |\n";
        break;
      }
      std::string failures;
      for (const auto& f : r.failures) failures += (failures.empty() ? "" : ", ") + f;
      std::string error = r.error.substr(0, 160);
      std::replace(error.begin(), error.end(), '|', '/');
      std::replace(error.begin(), error.end(), '\n', ' ');
      md << "| " << case_name(r.index) << " | " << r.family << " | " << r.variant << " | "
         << r.expected_pieces << " / " << r.generator_pieces << " / " << r.reference_pieces << " | "
         << failures << " | " << error << " |\n";
    }
  }
  return md.str();
}

void write_summary(const Summary& summary, const std::string& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) throw morph::IoError(dir + ": cannot create the output directory: " + error.message());
  // summary.json is the verdict a merge reads: written last.
  write_text(fs::path(dir) / "summary.md", summary_markdown(summary));
  write_text(fs::path(dir) / "summary.json", summary_to_json(summary).dump(2) + "\n");
}

std::pair<std::size_t, std::size_t> parse_shard(const std::string& text) {
  const auto slash = text.find('/');
  std::size_t index = 0, count = 0;
  try {
    if (slash == std::string::npos) throw std::invalid_argument("no slash");
    std::size_t used = 0;
    index = std::stoul(text.substr(0, slash), &used);
    if (used != slash) throw std::invalid_argument("trailing characters");
    const std::string rest = text.substr(slash + 1);
    count = std::stoul(rest, &used);
    if (used != rest.size()) throw std::invalid_argument("trailing characters");
  } catch (const std::exception&) {
    throw morph::InputError("--shard: expected i/n with whole numbers, got '" + text + "'");
  }
  if (count == 0 || index >= count) throw morph::InputError("--shard: need 0 <= i < n, got '" + text + "'");
  return {index, count};
}

std::vector<std::size_t> shard_cases(std::size_t cases, std::size_t shard_index, std::size_t shard_count) {
  std::vector<std::size_t> indices;
  if (shard_count == 0) return indices;
  for (std::size_t k = shard_index; k < cases; k += shard_count) indices.push_back(k);
  return indices;
}

namespace {

void remove_or_throw(const fs::path& path) {
  std::error_code error;
  fs::remove_all(path, error);
  if (error) throw morph::IoError(path.string() + ": cannot remove: " + error.message());
}

/// Makes out_dir ready for a run: the old verdict goes first (a kill from here on leaves no verdict
/// rather than a stale one), then, unless resuming the same campaign, the old cases. Returns the
/// finished results kept for a resume.
std::vector<CaseResult> prepare_shard_dir(const StressOptions& options, const nlohmann::json& identity) {
  const fs::path dir(options.out_dir);
  std::error_code error;
  // A run replaces a stress output; anything else (a typo naming a home directory) is left alone.
  if (fs::is_directory(dir, error) && !fs::is_empty(dir, error) && !fs::exists(dir / "campaign.json") &&
      !fs::exists(dir / "summary.json"))
    throw morph::InputError("--output " + options.out_dir +
                            " is not empty and not the output of `morphmill stress`: give a new directory");
  // A refused resume leaves everything as it was: checked before anything is removed.
  const fs::path recorded_file = dir / "campaign.json";
  const bool resuming = options.resume && fs::exists(recorded_file);
  if (resuming) {
    const nlohmann::json recorded = read_json(recorded_file);
    const std::string difference =
        campaign_difference(identity, "this run", recorded, recorded_file.string());
    if (!difference.empty())
      throw morph::InputError("--resume: not the campaign in " + options.out_dir + ": " + difference +
                              " (run without --resume to start afresh there)");
  }
  fs::create_directories(dir, error);
  if (error)
    throw morph::IoError(options.out_dir + ": cannot create the output directory: " + error.message());
  remove_or_throw(dir / "summary.json");
  remove_or_throw(dir / "summary.md");
  std::vector<CaseResult> kept;
  if (resuming) {
    for (auto& r : finished_results(dir))
      if (r.index < options.cases && r.index % options.shard_count == options.shard_index)
        kept.push_back(std::move(r));
  } else {
    remove_or_throw(dir / "cases");
    remove_or_throw(dir / "failures");
  }
  remove_or_throw(dir / "running");  // the cases in flight when a run was killed run again
  fs::create_directories(dir / "running", error);
  fs::create_directories(dir / "cases", error);
  if (error)
    throw morph::IoError(options.out_dir + ": cannot create the output directory: " + error.message());
  write_text(recorded_file, identity.dump(2) + "\n");
  return kept;
}

}  // namespace

Summary run_stress(const StressOptions& options) {
  if (options.cases == 0) throw morph::InputError("--cases must be at least 1");
  if (options.shard_count == 0 || options.shard_index >= options.shard_count)
    throw morph::InputError(
        fmt::format("--shard: need 0 <= i < n, got {}/{}", options.shard_index, options.shard_count));
  if (options.threads < 0) throw morph::InputError("--threads must not be negative");
  case_space(options);  // --families is checked before anything is written
  nlohmann::json identity = campaign_identity(options);
  identity["shard"] = fmt::format("{}/{}", options.shard_index, options.shard_count);
  std::vector<CaseResult> kept = prepare_shard_dir(options, identity);

  const std::vector<std::size_t> indices =
      shard_cases(options.cases, options.shard_index, options.shard_count);
  std::set<std::size_t> done;
  for (const auto& r : kept) done.insert(r.index);
  std::vector<std::size_t> to_run;
  for (std::size_t k : indices)
    if (!done.count(k)) to_run.push_back(k);

  Summary summary;
  summary.campaign = campaign_identity(options);
  summary.seed = options.seed;
  summary.cases = options.cases;
  summary.shards = {{options.shard_index, options.shard_count}};
  const int threads = options.threads > 0
                          ? options.threads
                          : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  summary.threads = threads;
  std::vector<std::optional<CaseResult>> ran(to_run.size());
  const fs::path cases_dir = fs::path(options.out_dir) / "cases";
  const auto stopped = [&] { return options.stop_signal && options.stop_signal->load() != 0; };
  const auto start = std::chrono::steady_clock::now();
  if (options.progress) options.progress->begin("stress: cases", to_run.size());
  {
    // Cases in parallel; each case's own stages share the same workers (TBB nests). Cancellation is
    // explicit: a stop lets no further case start and lets the cases in flight finish, so no task
    // group is ever unwound while nested tasks read a case's arrays.
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    tbb::parallel_for(
        tbb::blocked_range<std::size_t>(0, to_run.size(), 1),
        [&](const tbb::blocked_range<std::size_t>& range) {
          for (std::size_t i = range.begin(); i != range.end(); ++i) {
            if (stopped()) return;
            CaseResult result = run_case(options.seed, to_run[i], options);
            // The case's result file marks it finished (for --resume and a merge of a killed shard).
            write_text(cases_dir / (case_name(result.index) + ".json"), case_to_json(result).dump(2) + "\n");
            ran[i] = std::move(result);
            if (options.progress) options.progress->advance(1);
          }
        },
        tbb::simple_partitioner());
  }
  if (options.progress) options.progress->end();
  summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary.peak_rss_mib = process_peak_rss_mib();
  summary.results = std::move(kept);
  for (auto& r : ran)
    if (r) summary.results.push_back(std::move(*r));
  std::sort(summary.results.begin(), summary.results.end(),
            [](const CaseResult& a, const CaseResult& b) { return a.index < b.index; });
  done.clear();
  for (const auto& r : summary.results) done.insert(r.index);
  for (std::size_t k : indices)
    if (!done.count(k)) summary.missing.push_back(k);
  if (!summary.missing.empty())
    summary.incomplete.push_back(
        fmt::format("shard {}/{} stopped ({}) after {} of {} cases; `morphmill stress --resume {}` runs the "
                    "others",
                    options.shard_index, options.shard_count,
                    stopped() ? std::string("interrupted by ") + signal_name(options.stop_signal->load())
                              : "not finished",
                    summary.results.size(), indices.size(), options.out_dir));
  std::error_code error;
  fs::remove(fs::path(options.out_dir) / "running", error);  // empty unless something crashed
  write_summary(summary, options.out_dir);
  return summary;
}

namespace {

/// One shard directory as the merge sees it.
struct ShardRun {
  std::string dir;
  nlohmann::json identity;  ///< campaign.json without "shard"
  std::size_t index = 0, count = 0;
  std::vector<CaseResult> results;
  std::vector<std::string> incomplete;  ///< why some of its cases are missing
};

ShardRun read_shard(const std::string& dir) {
  ShardRun shard;
  shard.dir = dir;
  const fs::path campaign_file = fs::path(dir) / "campaign.json";
  if (!fs::exists(campaign_file))
    throw morph::InputError(dir +
                            ": no campaign.json: not the output of `morphmill stress` (or of one "
                            "older than campaign identities: run it again)");
  shard.identity = read_json(campaign_file);
  try {
    std::tie(shard.index, shard.count) = parse_shard(shard.identity.at("shard").get<std::string>());
  } catch (const nlohmann::json::exception& e) {
    throw morph::InputError(campaign_file.string() + ": no shard: " + e.what());
  }
  shard.identity.erase("shard");
  const fs::path verdict = fs::path(dir) / "summary.json";
  if (fs::exists(verdict)) {
    Summary summary = summary_from_json(read_json(verdict), verdict.string());
    const std::string difference =
        campaign_difference(shard.identity, campaign_file.string(), summary.campaign, verdict.string());
    if (!difference.empty())
      throw morph::InputError(dir + ": the verdict is of another campaign: " + difference);
    shard.results = std::move(summary.results);
    shard.incomplete = std::move(summary.incomplete);
    return shard;
  }
  // No verdict: the shard is still running, or was killed or cancelled while running. Its
  // finished cases are in cases/, the ones in flight in running/.
  shard.results = finished_results(dir);
  const auto in_flight = indices_in(fs::path(dir) / "running");
  shard.incomplete.push_back(fmt::format(
      "shard {}/{} ({}) has no verdict: still running, or killed or cancelled while running; {} case(s) "
      "finished{}",
      shard.index, shard.count, dir, shard.results.size(),
      in_flight.empty() ? std::string() : "; in flight when it stopped: " + index_list(in_flight)));
  return shard;
}

/// True if dir may be replaced by a merge: absent, empty, or a previous merge's output.
bool replaceable_merge_output(const fs::path& dir) {
  std::error_code error;
  if (!fs::exists(dir, error)) return true;
  if (!fs::is_directory(dir, error)) return false;
  if (fs::is_empty(dir, error)) return true;
  if (fs::exists(dir / "campaign.json")) return false;  // a shard
  try {
    return read_json(dir / "summary.json").value("merged", false);
  } catch (const std::exception&) {
    return fs::exists(dir / "MERGING");  // a merge that did not finish
  }
}

}  // namespace

Summary merge_stress(const std::vector<std::string>& shard_dirs, const std::string& out_dir, bool partial) {
  if (shard_dirs.empty()) throw morph::InputError("stress-merge: no shard directories given");
  const fs::path out(out_dir);
  for (const auto& dir : shard_dirs) {
    std::error_code error;
    if (fs::exists(out) && fs::equivalent(fs::path(dir), out, error))
      throw morph::InputError("--output " + out_dir + " is one of the shard directories");
  }
  if (!replaceable_merge_output(out))
    throw morph::InputError("--output " + out_dir +
                            " is not empty and not a previous merge: refusing to replace it (give a new "
                            "directory)");
  std::vector<ShardRun> shards;
  for (const auto& dir : shard_dirs) shards.push_back(read_shard(dir));

  Summary merged;
  merged.merged = true;
  merged.campaign = shards.front().identity;
  std::map<std::size_t, std::string> shard_dir_of;
  std::set<std::size_t> seen;
  for (const auto& shard : shards) {
    const std::string difference =
        campaign_difference(shard.identity, shard.dir, merged.campaign, shards.front().dir);
    if (!difference.empty())
      throw morph::InputError("stress-merge: shards of different campaigns: " + difference);
    if (!shard_dir_of.emplace(shard.index, shard.dir).second)
      throw morph::InputError(fmt::format("stress-merge: {} and {} are both shard {}/{}",
                                          shard_dir_of[shard.index], shard.dir, shard.index, shard.count));
    for (const auto& r : shard.results)
      if (!seen.insert(r.index).second)
        throw morph::InputError(shard.dir + ": " + case_name(r.index) + " is also in an earlier shard");
    merged.shards.emplace_back(shard.index, shard.count);
    merged.results.insert(merged.results.end(), shard.results.begin(), shard.results.end());
    merged.incomplete.insert(merged.incomplete.end(), shard.incomplete.begin(), shard.incomplete.end());
  }
  // Wall time, memory and threads come from the verdicts; a shard without one adds none.
  for (const auto& dir : shard_dirs) {
    const fs::path verdict = fs::path(dir) / "summary.json";
    if (!fs::exists(verdict)) continue;
    const nlohmann::json j = read_json(verdict);
    merged.wall_seconds += j.value("wall_seconds", 0.0);
    merged.peak_rss_mib = std::max(merged.peak_rss_mib, j.value("peak_rss_mib", 0.0));
    merged.threads = std::max(merged.threads, j.value("threads", 0));
  }
  merged.seed = merged.campaign.at("--seed").get<std::uint64_t>();
  merged.cases = merged.campaign.at("--cases").get<std::size_t>();
  const std::size_t count = merged.campaign.at("shards").get<std::size_t>();
  std::sort(merged.shards.begin(), merged.shards.end());
  std::sort(merged.results.begin(), merged.results.end(),
            [](const CaseResult& a, const CaseResult& b) { return a.index < b.index; });
  for (std::size_t i = 0; i < count; ++i)
    if (!shard_dir_of.count(i))
      merged.incomplete.push_back(
          fmt::format("shard {}/{} missing: no directory of it given (never started, "
                      "or cancelled before it started); its cases: {}",
                      i, count, index_list(shard_cases(merged.cases, i, count), 12)));
  for (std::size_t k = 0; k < merged.cases; ++k)
    if (!seen.count(k)) merged.missing.push_back(k);

  // Any previous merge goes first: a refused merge must not leave an old verdict standing.
  remove_or_throw(out);
  if (!merged.complete() && !partial) {
    std::string message =
        fmt::format("stress-merge: incomplete campaign: {} of {} cases finished, missing {}",
                    merged.results.size(), merged.cases, index_list(merged.missing));
    for (const auto& line : merged.incomplete) message += "\n  " + line;
    message += "\n  (--partial merges what finished into a summary that says what is missing)";
    throw IncompleteCampaign(message);
  }
  std::error_code error;
  fs::create_directories(out / "failures", error);
  if (error) throw morph::IoError(out_dir + ": cannot create the output directory: " + error.message());
  write_text(out / "MERGING", "a stress-merge is writing here; without summary.json it did not finish\n");
  std::set<std::size_t> failing;
  for (const auto& r : merged.results)
    if (!r.failures.empty()) failing.insert(r.index);
  for (const auto& dir : shard_dirs) {
    const fs::path failures = fs::path(dir) / "failures";
    if (!fs::is_directory(failures)) continue;
    for (const auto& entry : fs::directory_iterator(failures)) {
      const std::string name = entry.path().filename().string();
      // Only the files of cases the merge reports failing: a stale or half-written one stays out.
      std::size_t index = 0;
      try {
        index = std::stoul(name.substr(5, 6));
      } catch (const std::exception&) {
        continue;
      }
      if (name.rfind("case_", 0) != 0 || !failing.count(index) || name.find(".tmp-") != std::string::npos)
        continue;
      fs::copy_file(entry.path(), out / "failures" / name, fs::copy_options::overwrite_existing, error);
      if (error) throw morph::IoError(entry.path().string() + ": cannot copy: " + error.message());
    }
  }
  write_summary(merged, out_dir);
  fs::remove(out / "MERGING", error);
  return merged;
}

}  // namespace morphmill::stress
