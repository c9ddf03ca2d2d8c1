// SPDX-License-Identifier: Apache-2.0
// `morphmill stress`: deterministic case generators whose known piece counts agree with the
// OpenVDB reference, shards that partition a campaign, merges that add up, and a CI-sized campaign
// through the real binary.
#include <gtest/gtest.h>

#include <morph/exceptions.h>
#include <morph/mesh.h>
#include <morphmill/job_io.h>
#include <vdb_ref/reference.h>
#include "apps/command_support.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "campaigns/stress.h"
#include "campaigns/stress_cases.h"

namespace fs = std::filesystem;
using namespace morphmill::stress;

namespace {

fs::path scratch(const std::string& name) {
  return morphmill_test::scratch_dir("stress_test", name);
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

using morphmill_test::CommandResult;
CommandResult run(const std::string& command) {
  return morphmill_test::run_command(command);
}

CaseResult fake_result(std::size_t index, std::vector<std::string> failures, double generator_to_exact) {
  CaseResult r;
  r.index = index;
  r.family = case_families()[index % case_families().size()];
  r.variant = "synthetic";
  r.tolerance = 0.01;
  r.voxel_size = 0.5;
  r.agreement_bound = 0.01 + std::sqrt(3.0) * 0.5;
  r.generator_to_exact = generator_to_exact;
  r.exact_to_generator = r.reference_to_exact = r.generator_to_reference = r.reference_to_generator = 0.001;
  r.failures = std::move(failures);
  return r;
}

}  // namespace

TEST(StressCases, SameSeedAndIndexGiveTheSameJobBytes) {
  for (std::size_t index : {0u, 1u, 5u, 13u, 27u, 101u, 999u}) {
    const StressCase a = make_case(42, index), b = make_case(42, index);
    EXPECT_EQ(a.job.dump(), b.job.dump()) << index;
    EXPECT_EQ(a.expected_pieces, b.expected_pieces);
    EXPECT_EQ(a.stock_file, b.stock_file);
    const fs::path dir_a = scratch("bytes_a"), dir_b = scratch("bytes_b");
    write_case(a, dir_a.string(), "job.json");
    write_case(b, dir_b.string(), "job.json");
    EXPECT_EQ(slurp(dir_a / "job.json"), slurp(dir_b / "job.json"));
    if (!a.stock_file.empty()) {
      EXPECT_EQ(slurp(dir_a / a.stock_file), slurp(dir_b / b.stock_file));
    }
  }
  // Another seed draws other jobs.
  EXPECT_NE(make_case(42, 3).job.dump(), make_case(43, 3).job.dump());
}

TEST(StressCases, CampaignCoversEveryFamilyStockAndTool) {
  std::set<std::string> families, stocks, tools;
  for (std::size_t index = 0; index < 200; ++index) {
    const StressCase c = make_case(1, index);
    families.insert(c.family);
    stocks.insert(c.job["stock"]["type"].get<std::string>());
    tools.insert(c.job["tools"]["1"]["type"].get<std::string>());
    EXPECT_GT(c.voxel_size, 0);
    // The description names the seed and the index, so a failure file says where it came from.
    const std::string description = c.job["description"];
    EXPECT_NE(description.find("case " + std::to_string(index) + " of seed 1"), std::string::npos)
        << description;
  }
  EXPECT_EQ(families.size(), case_families().size());
  EXPECT_EQ(stocks, (std::set<std::string>{"box", "cylinder", "mesh"}));
  EXPECT_EQ(tools, (std::set<std::string>{"sphere", "ballend"}));
}

TEST(StressCases, StockMeshesAreClosedAndOutward) {
  int meshes = 0;
  for (std::size_t index = 0; index < 120 && meshes < 6; ++index) {
    const StressCase c = make_case(5, index);
    if (!c.stock_mesh) continue;
    ++meshes;
    const auto bounds = morph::bounds(*c.stock_mesh);
    const double volume = morph::enclosed_volume(*c.stock_mesh);
    if (c.stock_file.find("octahedron") != std::string::npos) {
      const double a = bounds.sizes().x() / 2;  // |x| + |y| + |z| <= a has volume 4/3 a^3
      EXPECT_NEAR(volume, 4.0 / 3.0 * a * a * a, 1e-9 * a * a * a) << c.stock_file;
    } else {
      EXPECT_NEAR(volume, bounds.sizes().prod(), 1e-9 * bounds.sizes().prod()) << c.stock_file;
    }
  }
  EXPECT_GT(meshes, 0);
}

// The counts known by construction, checked against the OpenVDB reference (independent of the
// generator) on the first case of every family.
TEST(StressCases, KnownPieceCountsMatchTheReference) {
  const fs::path dir = scratch("pieces");
  for (std::size_t index = 0; index < case_families().size(); ++index) {
    const StressCase c = make_case(11, index);
    ASSERT_GE(c.expected_pieces, 1) << c.family;
    const std::string path = write_case(c, dir.string(), case_name(index) + ".json");
    const morph::Job job = morphmill::load_job(path);
    vdb_ref::ReferenceOptions options;
    options.voxel_size = c.voxel_size;
    const vdb_ref::ReferenceResult reference = vdb_ref::compute_reference(job, options);
    EXPECT_EQ(reference.pieces.size(), static_cast<std::size_t>(c.expected_pieces))
        << case_name(index) << " " << c.family << ": " << c.variant;
    if (c.expected_volume) {
      // Nothing is cut: the level set's volume is the stock's to within half a voxel over the area.
      EXPECT_NEAR(reference.volume(), *c.expected_volume, 0.5 * c.voxel_size * reference.area()) << c.family;
    }
  }
}

// Seed 59, case 133 of version 1: a third pass of the overlap family reached past the box's side,
// cut it below the top and sliced a wedge off along the whole pass (2 pieces where 1 was
// expected). Every partial-depth pass now keeps its tool inside the top face.
TEST(StressCases, OverlappingPassesKeepTheirToolOffTheStocksSides) {
  const auto& families = case_families();
  const std::size_t overlap =
      static_cast<std::size_t>(std::find(families.begin(), families.end(), "overlap") - families.begin());
  ASSERT_LT(overlap, families.size());
  std::size_t checked = 0;
  for (std::size_t index = overlap; index < 2000; index += families.size()) {
    const StressCase c = make_case(59, index);
    if (c.variant.find("at different depths") == std::string::npos || c.job["stock"]["type"] != "box")
      continue;
    const double radius = c.job["tools"]["1"]["radius"].get<double>();
    const double y0 = c.job["stock"]["min"][1].get<double>(), y1 = c.job["stock"]["max"][1].get<double>();
    for (const auto& path : c.job["paths"])
      for (const auto& point : path["polyline"]) {
        const double y = point[1].get<double>();
        EXPECT_LT(y + radius, y1) << case_name(index) << ": " << c.variant;
        EXPECT_GT(y - radius, y0) << case_name(index) << ": " << c.variant;
      }
    ++checked;
  }
  EXPECT_GT(checked, 20u);
}

// Seed 103, case 3171: four sphere passes over a cylinder, which the family says leave one piece.
// The exact solid leaves two slivers more, 0.007 mm thick, where end caps meet the cylinder's rim;
// the generator finds them (3 pieces), the 0.43 mm voxels do not. Chips under (2 voxels)³ that
// verify's piece rule finds exact material do not count against the family's count.
TEST(StressCases, AnExactChipBelowTheVoxelsIsNotAMiscount) {
  StressOptions options;
  options.face_samples = 500;
  const CaseResult r = run_case(103, 3171, options);
  EXPECT_EQ(r.family, "overlap");
  EXPECT_EQ(r.expected_pieces, 1);
  EXPECT_EQ(r.generator_pieces, 3u);
  EXPECT_EQ(r.reference_pieces, 1u);
  EXPECT_EQ(r.pieces_below_resolution, 2u);
  EXPECT_TRUE(r.failures.empty()) << nlohmann::json(r.failures).dump();
}

TEST(StressShards, ShardsPartitionTheCases) {
  for (std::size_t count : {1u, 2u, 3u, 16u}) {
    std::vector<int> seen(50, 0);
    for (std::size_t shard = 0; shard < count; ++shard)
      for (std::size_t k : shard_cases(50, shard, count)) {
        ASSERT_LT(k, 50u);
        EXPECT_EQ(k % count, shard);
        ++seen[k];
      }
    for (int times : seen) EXPECT_EQ(times, 1) << count;
  }
  EXPECT_EQ(parse_shard("3/16"), (std::pair<std::size_t, std::size_t>{3, 16}));
  EXPECT_THROW(parse_shard("16/16"), morph::InputError);
  EXPECT_THROW(parse_shard("1/0"), morph::InputError);
  EXPECT_THROW(parse_shard("a/b"), morph::InputError);
  EXPECT_THROW(parse_shard("1/2x"), morph::InputError);
}

namespace {

StressOptions campaign_options(std::size_t cases, std::size_t shard_index, std::size_t shard_count) {
  StressOptions options;
  options.cases = cases;
  options.seed = 9;
  options.shard_index = shard_index;
  options.shard_count = shard_count;
  return options;
}

/// A shard directory as `stress` leaves it: campaign.json, cases/ and, if `verdict`, the summary.
void write_shard(const fs::path& dir, const StressOptions& options, const std::vector<CaseResult>& results,
                 bool verdict = true) {
  fs::create_directories(dir / "cases");
  nlohmann::json identity = campaign_identity(options);
  identity["shard"] = std::to_string(options.shard_index) + "/" + std::to_string(options.shard_count);
  std::ofstream(dir / "campaign.json") << identity.dump(2);
  for (const auto& r : results)
    std::ofstream(dir / "cases" / (case_name(r.index) + ".json")) << case_to_json(r);
  if (!verdict) return;
  Summary summary;
  summary.campaign = campaign_identity(options);
  summary.seed = options.seed;
  summary.cases = options.cases;
  summary.shards = {{options.shard_index, options.shard_count}};
  summary.wall_seconds = 5;
  summary.peak_rss_mib = 100;
  summary.results = results;
  write_summary(summary, dir.string());
}

std::string message_of_merge(const std::vector<std::string>& dirs, const fs::path& out) {
  try {
    merge_stress(dirs, out.string());
  } catch (const std::exception& e) {
    return e.what();
  }
  return "(merged)";
}

/// Sets the stop signal once `after` cases have finished (explicit cancellation, as SIGINT does).
struct StopAfter : morph::Progress {
  std::atomic<int>* stop;
  std::size_t after;
  std::atomic<std::size_t> finished{0};
  StopAfter(std::atomic<int>* s, std::size_t a) : stop(s), after(a) {}
  void advance(std::size_t done) override {
    if ((finished += done) >= after) stop->store(SIGINT);
  }
};

/// A summary's results without what depends on the run (times, process memory).
nlohmann::json comparable(const Summary& summary) {
  nlohmann::json results = nlohmann::json::array();
  for (const auto& r : summary.results) {
    nlohmann::json j = case_to_json(r);
    j.erase("seconds");
    j.erase("peak_rss_mib");
    results.push_back(j);
  }
  return results;
}

}  // namespace

TEST(StressShards, MergeAddsUp) {
  const fs::path a = scratch("merge_a"), b = scratch("merge_b"), out = scratch("merge_out");
  CaseResult with_fallbacks = fake_result(4, {}, 0.001);
  with_fallbacks.fallbacks = {{"rounding_flipped_edges", 3}, {"limit_kept_apart", 0}};
  write_shard(a, campaign_options(6, 0, 2),
              {fake_result(0, {}, 0.004), fake_result(2, {"closed_manifold"}, 0.02), with_fallbacks});
  write_shard(b, campaign_options(6, 1, 2),
              {fake_result(1, {"sides_agree", "pieces_known"}, 0.003), fake_result(3, {}, 0.005),
               fake_result(5, {"closed_manifold"}, 0.002)});
  fs::create_directories(a / "failures");
  std::ofstream(a / "failures" / "case_000002.json") << "{}";
  std::ofstream(a / "failures" / "case_000004.json") << "{}";  // stale: case 4 passes
  const Summary merged = merge_stress({a.string(), b.string()}, out.string());
  ASSERT_EQ(merged.results.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(merged.results[i].index, i);
  EXPECT_TRUE(merged.complete());
  EXPECT_EQ(merged.failed_cases(), 3u);
  EXPECT_DOUBLE_EQ(merged.wall_seconds, 10);
  const auto json = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(json["complete"], true);
  EXPECT_EQ(json["partial"], "");
  EXPECT_EQ(json["failures_by_invariant"]["closed_manifold"], 2);
  EXPECT_EQ(json["failures_by_invariant"]["sides_agree"], 1);
  EXPECT_EQ(json["failures_by_invariant"]["pieces_known"], 1);
  EXPECT_EQ(json["failures_by_invariant"]["no_exception"], 0);
  EXPECT_EQ(json["cases_run"], 6);
  // The worst generator -> exact deviation is case 2's 0.02 (twice the tolerance).
  EXPECT_EQ(json["worst_deviation"]["generator_to_exact"]["case"], 2);
  EXPECT_DOUBLE_EQ(json["worst_deviation"]["generator_to_exact"]["ratio_to_bound"].get<double>(), 2.0);
  EXPECT_TRUE(fs::exists(out / "failures" / "case_000002.json"));
  EXPECT_FALSE(fs::exists(out / "failures" / "case_000004.json"));
  EXPECT_TRUE(fs::exists(out / "summary.md"));
  EXPECT_NE(
      slurp(out / "summary.md")
          .find("| generator's fallbacks fired (target 0) | 3 in 1 case(s): rounding_flipped_edges 3 |"),
      std::string::npos);
  EXPECT_EQ(merged.results[4].fallbacks.at("rounding_flipped_edges"), 3u);
  // The round trip keeps every field the summary is made of.
  const Summary again = summary_from_json(json, "summary.json");
  EXPECT_EQ(summary_to_json(again).dump(), json.dump());

  // Overlapping shards are refused.
  EXPECT_THROW(merge_stress({a.string(), a.string()}, scratch("merge_bad").string()), morph::InputError);

  // Merging again into the same --out replaces it whole: no failure file of the old merge stays
  // beside a summary without failures.
  const fs::path c = scratch("merge_c"), d = scratch("merge_d");
  write_shard(c, campaign_options(6, 0, 2),
              {fake_result(0, {}, 0), fake_result(2, {}, 0), fake_result(4, {}, 0)});
  write_shard(d, campaign_options(6, 1, 2),
              {fake_result(1, {}, 0), fake_result(3, {}, 0), fake_result(5, {}, 0)});
  EXPECT_EQ(merge_stress({c.string(), d.string()}, out.string()).failed_cases(), 0u);
  EXPECT_FALSE(fs::exists(out / "failures" / "case_000002.json"));
  // A non-empty --out that is not a merge is refused, and left alone.
  const fs::path precious = scratch("precious");
  std::ofstream(precious / "thesis.tex") << "keep me";
  EXPECT_THROW(merge_stress({c.string(), d.string()}, precious.string()), morph::InputError);
  EXPECT_TRUE(fs::exists(precious / "thesis.tex"));
}

TEST(StressShards, MergeRefusesAnotherCampaignNamingWhatDiffers) {
  const fs::path a = scratch("other_a"), b = scratch("other_b");
  write_shard(a, campaign_options(4, 0, 2), {fake_result(0, {}, 0), fake_result(2, {}, 0)});
  StressOptions other = campaign_options(4, 1, 2);
  other.face_samples = 500;
  write_shard(b, other, {fake_result(1, {}, 0), fake_result(3, {}, 0)});
  std::string message = message_of_merge({a.string(), b.string()}, scratch("other_out"));
  EXPECT_NE(message.find("--samples is 500"), std::string::npos) << message;
  other = campaign_options(4, 1, 2);
  other.max_peak_rss_mib = 100;
  write_shard(b, other, {fake_result(1, {}, 0), fake_result(3, {}, 0)});
  message = message_of_merge({a.string(), b.string()}, scratch("other_out"));
  EXPECT_NE(message.find("--max-rss"), std::string::npos) << message;
  // Another build: the identity's source commit differs.
  write_shard(b, campaign_options(4, 1, 2), {fake_result(1, {}, 0), fake_result(3, {}, 0)});
  nlohmann::json identity = nlohmann::json::parse(slurp(b / "campaign.json"));
  identity["source_commit"] = "0123456789abcdef";
  std::ofstream(b / "campaign.json") << identity.dump();
  message = message_of_merge({a.string(), b.string()}, scratch("other_out"));
  EXPECT_NE(message.find("source_commit"), std::string::npos) << message;
  // campaign_difference names nothing for equal identities.
  EXPECT_EQ(campaign_difference(campaign_identity(other), "a", campaign_identity(other), "b"), "");
}

TEST(StressShards, MergeRefusesAnIncompleteCampaignUnlessPartial) {
  const fs::path a = scratch("partial_a"), out = scratch("partial_out");
  write_shard(a, campaign_options(6, 0, 2),
              {fake_result(0, {}, 0), fake_result(2, {}, 0), fake_result(4, {}, 0)});
  try {
    merge_stress({a.string()}, out.string());
    ADD_FAILURE() << "a merge of 3 cases of 6 was accepted";
  } catch (const IncompleteCampaign& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("3 of 6 cases finished, missing 1, 3, 5"), std::string::npos) << message;
    EXPECT_NE(message.find("shard 1/2 missing"), std::string::npos) << message;
  }
  EXPECT_FALSE(fs::exists(out / "summary.json"));
  const Summary partial = merge_stress({a.string()}, out.string(), true);
  EXPECT_FALSE(partial.complete());
  EXPECT_EQ(partial.partial_line(), "partial: 3 of 6 cases, missing 1, 3, 5");
  EXPECT_NE(slurp(out / "summary.md").find("partial: 3 of 6 cases, missing 1, 3, 5"), std::string::npos);
  const auto json = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(json["partial"], "partial: 3 of 6 cases, missing 1, 3, 5");
  EXPECT_EQ(json["complete"], false);
  EXPECT_EQ(json["missing_cases"], nlohmann::json::array({1, 3, 5}));
  // A refused merge removes the previous merge rather than leave its verdict standing.
  EXPECT_THROW(merge_stress({a.string()}, out.string()), IncompleteCampaign);
  EXPECT_FALSE(fs::exists(out));
}

TEST(StressShards, MergeNamesTheCasesInFlightOfAShardKilledWhileRunning) {
  const fs::path a = scratch("killed_a"), b = scratch("killed_b");
  write_shard(a, campaign_options(6, 0, 2),
              {fake_result(0, {}, 0), fake_result(2, {}, 0), fake_result(4, {}, 0)});
  // Shard 1 was killed: one case finished, case 3 was in flight, no verdict.
  write_shard(b, campaign_options(6, 1, 2), {fake_result(1, {}, 0)}, false);
  fs::create_directories(b / "running");
  std::ofstream(b / "running" / "case_000003.json") << "{}";
  const std::string message = message_of_merge({a.string(), b.string()}, scratch("killed_out"));
  EXPECT_NE(message.find("4 of 6 cases finished, missing 3, 5"), std::string::npos) << message;
  EXPECT_NE(message.find("shard 1/2 (" + b.string() + ") has no verdict"), std::string::npos) << message;
  EXPECT_NE(message.find("in flight when it stopped: 3"), std::string::npos) << message;
  // A stale verdict from an earlier run does not hide it: a run removes the verdict first (below).
}

// Cancellation is explicit: once the stop is set no case starts, the cases in flight finish, the
// summary says what is missing; --resume runs only those and gives the uninterrupted campaign.
TEST(StressRun, StopsCleanlyAndResumesToTheSameCampaign) {
  const fs::path dir = scratch("resume"), fresh = scratch("resume_fresh");
  StressOptions options = campaign_options(4, 0, 1);
  options.threads = 1;
  options.face_samples = 200;
  options.out_dir = dir.string();
  std::atomic<int> stop{0};
  StopAfter stop_after(&stop, 1);
  options.stop_signal = &stop;
  options.progress = &stop_after;
  const Summary stopped = run_stress(options);
  EXPECT_EQ(stopped.results.size(), 1u);
  EXPECT_FALSE(stopped.complete());
  EXPECT_EQ(stopped.missing, (std::vector<std::size_t>{1, 2, 3}));
  const auto json = nlohmann::json::parse(slurp(dir / "summary.json"));
  EXPECT_EQ(json["partial"], "partial: 1 of 4 cases, missing 1, 2, 3");
  EXPECT_NE(json["incomplete"].dump().find("interrupted by SIGINT"), std::string::npos) << json["incomplete"];
  EXPECT_FALSE(fs::exists(dir / "running"));
  EXPECT_TRUE(fs::exists(dir / "cases" / "case_000000.json"));
  const std::string kept = slurp(dir / "cases" / "case_000000.json");

  options.stop_signal = nullptr;
  options.progress = nullptr;
  options.resume = true;
  const Summary resumed = run_stress(options);
  EXPECT_TRUE(resumed.complete());
  ASSERT_EQ(resumed.results.size(), 4u);
  EXPECT_EQ(slurp(dir / "cases" / "case_000000.json"), kept) << "case 0 ran again";

  options.resume = false;
  options.out_dir = fresh.string();
  const Summary uninterrupted = run_stress(options);
  EXPECT_EQ(comparable(resumed), comparable(uninterrupted));
}

TEST(StressRun, ANewRunRemovesTheOldVerdictFirstAndResumeChecksTheCampaign) {
  const fs::path dir = scratch("verdict");
  write_shard(dir, campaign_options(4, 0, 1),
              {fake_result(0, {}, 0), fake_result(1, {}, 0), fake_result(2, {}, 0), fake_result(3, {}, 0)});
  fs::create_directories(dir / "failures");
  std::ofstream(dir / "failures" / "case_000001.json") << "{}";
  // Stopped before any case: what is left must say so, not the old "no failures, 4 of 4".
  StressOptions options = campaign_options(4, 0, 1);
  options.out_dir = dir.string();
  std::atomic<int> stop{SIGTERM};
  options.stop_signal = &stop;
  const Summary summary = run_stress(options);
  EXPECT_TRUE(summary.results.empty());
  const auto json = nlohmann::json::parse(slurp(dir / "summary.json"));
  EXPECT_EQ(json["complete"], false);
  EXPECT_EQ(json["cases_run"], 0);
  EXPECT_NE(json["incomplete"].dump().find("interrupted by SIGTERM"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "failures" / "case_000001.json"));
  EXPECT_TRUE(fs::is_empty(dir / "cases"));

  // A directory that is not a stress output is not cleared for a run.
  const fs::path precious = scratch("not_stress");
  std::ofstream(precious / "notes.txt") << "keep me";
  StressOptions elsewhere = options;
  elsewhere.out_dir = precious.string();
  EXPECT_THROW(run_stress(elsewhere), morph::InputError);
  EXPECT_TRUE(fs::exists(precious / "notes.txt"));

  // --resume of the campaign in dir with another option is refused, naming it.
  options.resume = true;
  options.face_samples = 99;
  try {
    run_stress(options);
    ADD_FAILURE() << "resumed another campaign";
  } catch (const morph::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--samples is 99"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(fs::exists(dir / "summary.json")) << "a refused resume removed the verdict";
}

// The CI-sized campaign through the binary: every invariant on 50 cases (about 30 s on 2 cores).
TEST(StressCampaign, FiftyCasesPassEveryInvariant) {
  const fs::path out = scratch("campaign");
  const CommandResult result =
      run(std::string(MORPHMILL_BINARY) + " stress --cases 50 --seed 1 --out " + out.string());
  const std::string summary = slurp(out / "summary.md");
  EXPECT_EQ(result.exit_code, 0) << result.output << "\n" << summary;
  ASSERT_TRUE(fs::exists(out / "summary.json")) << result.output;
  const auto json = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(json["cases_run"], 50);
  EXPECT_EQ(json["failed_cases"], 0) << summary;
  for (const auto& [name, count] : json["failures_by_invariant"].items()) EXPECT_EQ(count, 0) << name;
}

// Issue 26's reproduction: one shard of two merged alone is refused, naming the shard and cases.
TEST(StressCampaign, MergeOfOneShardOfTwoIsRefusedNamingWhatIsMissing) {
  const fs::path a = scratch("half"), out = scratch("half_out");
  const std::string binary = MORPHMILL_BINARY;
  ASSERT_EQ(
      run(binary + " stress --cases 8 --seed 7 --samples 200 --shard 0/2 --out " + a.string()).exit_code, 0);
  CommandResult merge = run(binary + " stress-merge " + a.string() + " --out " + out.string());
  EXPECT_EQ(merge.exit_code, 4) << merge.output;
  EXPECT_NE(merge.output.find("4 of 8 cases finished, missing 1, 3, 5, 7"), std::string::npos)
      << merge.output;
  EXPECT_NE(merge.output.find("shard 1/2 missing"), std::string::npos) << merge.output;
  merge = run(binary + " stress-merge " + a.string() + " --partial --out " + out.string());
  EXPECT_EQ(merge.exit_code, 4) << merge.output;
  EXPECT_NE(slurp(out / "summary.md").find("partial: 4 of 8 cases, missing 1, 3, 5, 7"), std::string::npos);
}

namespace {

/// A shell command: `command` in the background; once DIR/cases holds a finished case, `kill
/// -SIGNAL`; prints "exit=N", the command's exit code.
std::string signal_after_first_case(const std::string& command, const fs::path& dir,
                                    const std::string& signal) {
  return "sh -c '" + command + " >/dev/null 2>&1 & pid=$!; i=0; while [ -z \"$(ls " + dir.string() +
         "/cases 2>/dev/null)\" ] && [ $i -lt 600 ]; do sleep 0.1; i=$((i+1)); done; kill -" + signal +
         " $pid; wait $pid; echo exit=$?'";
}

}  // namespace

// Issue 19's reproduction: SIGTERM (and SIGINT) stop a campaign cleanly, keeping the finished cases
// and writing a summary that says it was interrupted (exit 4, not 0); --resume DIR finishes it.
TEST(StressCampaign, SignalStopsCleanlyAndResumeFinishes) {
  const std::string binary = MORPHMILL_BINARY;
  for (const std::string signal : {"TERM", "INT"}) {
    const fs::path dir = scratch("signal_" + signal);
    const CommandResult stopped = run(signal_after_first_case(
        binary + " stress --cases 100 --seed 99 --threads 1 --samples 200 --out " + dir.string(), dir,
        signal));
    EXPECT_NE(stopped.output.find("exit=4"), std::string::npos) << signal << ": " << stopped.output;
    ASSERT_TRUE(fs::exists(dir / "summary.json")) << signal;
    const auto json = nlohmann::json::parse(slurp(dir / "summary.json"));
    EXPECT_EQ(json["complete"], false);
    EXPECT_GE(json["cases_run"].get<int>(), 1);
    EXPECT_LT(json["cases_run"].get<int>(), 100);
    EXPECT_NE(json["incomplete"].dump().find("interrupted by SIG" + signal), std::string::npos)
        << json["incomplete"];
    EXPECT_NE(slurp(dir / "summary.md").find("partial: "), std::string::npos);
  }
  // Resume a small campaign stopped the same way: only the options in campaign.json are needed.
  const fs::path dir = scratch("signal_resume");
  const CommandResult stopped = run(signal_after_first_case(
      binary + " stress --cases 5 --seed 99 --threads 1 --samples 200 --out " + dir.string(), dir, "TERM"));
  EXPECT_NE(stopped.output.find("exit=4"), std::string::npos) << stopped.output;
  const CommandResult resumed = run(binary + " stress --resume " + dir.string());
  EXPECT_EQ(resumed.exit_code, 0) << resumed.output;
  const auto json = nlohmann::json::parse(slurp(dir / "summary.json"));
  EXPECT_EQ(json["complete"], true);
  EXPECT_EQ(json["cases_run"], 5);
  EXPECT_EQ(json["campaign"]["--samples"], 200);
}

TEST(StressCampaign, BadInputExitsWithTwo) {
  const std::string binary = MORPHMILL_BINARY;
  EXPECT_EQ(run(binary + " stress --cases 4 --shard 4/4 --out " + scratch("bad").string()).exit_code, 2);
  EXPECT_EQ(run(binary + " stress --cases 0 --out " + scratch("bad").string()).exit_code, 2);
  EXPECT_EQ(run(binary + " stress-merge " + scratch("empty").string() + " --out " + scratch("bad").string())
                .exit_code,
            2);
}
