#include "stress.h"

#include <fmt/format.h>
#include <morph/exceptions.h>
#include <morph/stock.h>
#include <morphmill/job_io.h>
#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

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

#include "stress_cases.h"
#include "verify.h"

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

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  if (!out) throw morph::IoError(path.string() + ": cannot write");
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
      "pieces_known",                // the generator finds the piece count known by construction
      "reference_pieces_known",      // so does the reference
      "pieces_match_reference",      // same count, volumes within half a voxel times the area
      "volume_known",                // passes outside the stock: the generator's volume is the stock's
      "generator_within_tolerance",  // generator <-> exact surface, both ways, within the tolerance
      "sides_agree",                 // two-sided generator <-> reference within tolerance + sqrt(3) voxel
  };
  return names;
}

CaseResult run_case(std::uint64_t seed, std::size_t index, const StressOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CaseResult result;
  result.index = index;
  result.generator_to_exact = result.exact_to_generator = result.reference_to_exact = kNaN;
  result.generator_to_reference = result.reference_to_generator = kNaN;
  const fs::path running = fs::path(options.out_dir) / "running";
  fs::path job_path;
  std::string stock_file;
  try {
    const StressCase c = make_case(seed, index);
    result.family = c.family;
    result.variant = c.variant;
    result.expected_pieces = c.expected_pieces;
    result.expected_volume = c.expected_volume;
    result.voxel_size = c.voxel_size;
    stock_file = c.stock_file;
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
    const Evaluation evaluation = evaluate_job(job, evaluate);
    const VerifyOutcome& o = evaluation.outcome;
    result.agreement_bound = o.agreement_bound;
    result.generator_pieces = o.morph_pieces.size();
    result.reference_pieces = o.reference_pieces.size();
    result.generator_triangles = o.morph_triangles;
    result.generator_volume = o.morph_topology.volume;
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
    if (c.expected_pieces >= 0) {
      if (result.generator_pieces != static_cast<std::size_t>(c.expected_pieces))
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
  // Keep the failing case's job (and stock mesh) as a standalone reproduction.
  if (!result.failures.empty()) {
    try {
      const StressCase c = make_case(seed, index);
      const fs::path failures = fs::path(options.out_dir) / "failures";
      write_case(c, failures.string(), case_name(index) + ".json");
      write_text(failures / (case_name(index) + ".result.json"), case_to_json(result).dump(2) + "\n");
    } catch (const std::exception& e) {
      result.error += std::string(result.error.empty() ? "" : "; ") + "writing the failure: " + e.what();
    }
  }
  std::error_code ignored;
  if (!job_path.empty()) fs::remove(job_path, ignored);
  if (!stock_file.empty()) fs::remove(running / stock_file, ignored);
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
          {"pieces", {{"generator", r.generator_pieces}, {"reference", r.reference_pieces}}},
          {"volume", {{"generator", r.generator_volume}, {"reference", r.reference_volume}}},
          {"generator_triangles", r.generator_triangles},
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
    r.generator_volume = j.at("volume").at("generator").get<double>();
    r.reference_volume = j.at("volume").at("reference").get<double>();
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

std::size_t Summary::failed_cases() const {
  return static_cast<std::size_t>(
      std::count_if(results.begin(), results.end(), [](const CaseResult& r) { return !r.failures.empty(); }));
}

nlohmann::json summary_to_json(const Summary& s) {
  nlohmann::json j;
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
  md << "**" << (failed == 0 ? "No failures" : fmt::format("{} failing case(s)", failed)) << "** in "
     << s.results.size() << " case(s) run of " << s.cases << ".\n\n";
  md << "| item | value |\n|---|---|\n";
  md << "| shards | ";
  for (std::size_t i = 0; i < s.shards.size(); ++i)
    md << (i ? ", " : "") << s.shards[i].first << "/" << s.shards[i].second;
  md << " |\n| wall time (s, summed over shards) | " << fmt::format("{:.1f}", s.wall_seconds) << " |\n";
  md << "| peak resident memory (MiB) | " << fmt::format("{:.0f}", s.peak_rss_mib) << " |\n";
  md << "| threads | " << s.threads << " |\n\n";

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
          "--out OUT "
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
  write_text(fs::path(dir) / "summary.json", summary_to_json(summary).dump(2) + "\n");
  write_text(fs::path(dir) / "summary.md", summary_markdown(summary));
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

Summary run_stress(const StressOptions& options) {
  if (options.cases == 0) throw morph::InputError("--cases must be at least 1");
  if (options.shard_count == 0 || options.shard_index >= options.shard_count)
    throw morph::InputError(
        fmt::format("--shard: need 0 <= i < n, got {}/{}", options.shard_index, options.shard_count));
  if (options.threads < 0) throw morph::InputError("--threads must not be negative");
  std::error_code error;
  fs::create_directories(fs::path(options.out_dir) / "running", error);
  if (error)
    throw morph::IoError(options.out_dir + ": cannot create the output directory: " + error.message());
  // A rerun into the same directory must not mix old failure files with the new summary.
  fs::remove_all(fs::path(options.out_dir) / "failures", error);

  const std::vector<std::size_t> indices =
      shard_cases(options.cases, options.shard_index, options.shard_count);
  Summary summary;
  summary.seed = options.seed;
  summary.cases = options.cases;
  summary.shards = {{options.shard_index, options.shard_count}};
  const int threads = options.threads > 0
                          ? options.threads
                          : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  summary.threads = threads;
  summary.results.resize(indices.size());
  const auto start = std::chrono::steady_clock::now();
  if (options.progress) options.progress->begin("stress: cases", indices.size());
  {
    // Cases in parallel; each case's own stages share the same workers (TBB nests).
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                              static_cast<std::size_t>(threads));
    tbb::parallel_for(std::size_t(0), indices.size(), [&](std::size_t i) {
      summary.results[i] = run_case(options.seed, indices[i], options);
      if (options.progress) options.progress->advance(1);
    });
  }
  if (options.progress) options.progress->end();
  summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary.peak_rss_mib = process_peak_rss_mib();
  fs::remove(fs::path(options.out_dir) / "running", error);  // empty unless something crashed
  write_summary(summary, options.out_dir);
  return summary;
}

Summary merge_stress(const std::vector<std::string>& shard_dirs, const std::string& out_dir) {
  if (shard_dirs.empty()) throw morph::InputError("stress-merge: no shard directories given");
  Summary merged;
  std::set<std::size_t> seen;
  for (std::size_t d = 0; d < shard_dirs.size(); ++d) {
    const fs::path file = fs::path(shard_dirs[d]) / "summary.json";
    nlohmann::json json;
    try {
      json = nlohmann::json::parse(read_text(file));
    } catch (const nlohmann::json::exception& e) {
      throw morph::InputError(file.string() + ": " + e.what());
    }
    const Summary shard = summary_from_json(json, file.string());
    if (d == 0) {
      merged.seed = shard.seed;
      merged.cases = shard.cases;
    } else if (shard.seed != merged.seed || shard.cases != merged.cases) {
      throw morph::InputError(
          fmt::format("{}: campaign seed {} with {} cases, but {} has seed {} with {} cases", file.string(),
                      shard.seed, shard.cases, shard_dirs[0], merged.seed, merged.cases));
    }
    for (const auto& r : shard.results)
      if (!seen.insert(r.index).second)
        throw morph::InputError(file.string() + ": " + case_name(r.index) + " is also in an earlier shard");
    merged.shards.insert(merged.shards.end(), shard.shards.begin(), shard.shards.end());
    merged.results.insert(merged.results.end(), shard.results.begin(), shard.results.end());
    merged.wall_seconds += shard.wall_seconds;
    merged.peak_rss_mib = std::max(merged.peak_rss_mib, shard.peak_rss_mib);
    merged.threads = std::max(merged.threads, shard.threads);
  }
  std::sort(merged.results.begin(), merged.results.end(),
            [](const CaseResult& a, const CaseResult& b) { return a.index < b.index; });
  std::error_code error;
  fs::create_directories(fs::path(out_dir) / "failures", error);
  if (error) throw morph::IoError(out_dir + ": cannot create the output directory: " + error.message());
  for (const auto& dir : shard_dirs) {
    const fs::path failures = fs::path(dir) / "failures";
    if (!fs::is_directory(failures)) continue;
    for (const auto& entry : fs::directory_iterator(failures)) {
      fs::copy_file(entry.path(), fs::path(out_dir) / "failures" / entry.path().filename(),
                    fs::copy_options::overwrite_existing, error);
      if (error) throw morph::IoError(entry.path().string() + ": cannot copy: " + error.message());
    }
  }
  write_summary(merged, out_dir);
  return merged;
}

}  // namespace morphmill::stress
