// `morphmill stress`: deterministic case generators whose known piece counts agree with the
// OpenVDB reference, shards that partition a campaign, merges that add up, and a CI-sized campaign
// through the real binary.
#include <gtest/gtest.h>

#include <morph/exceptions.h>
#include <morph/mesh.h>
#include <morphmill/job_io.h>
#include <vdb_ref/reference.h>
#include "apps/command_support.h"

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "../../apps/src/stress.h"
#include "../../apps/src/stress_cases.h"

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

TEST(StressShards, MergeAddsUp) {
  Summary first, second;
  first.seed = second.seed = 9;
  first.cases = second.cases = 6;
  first.shards = {{0, 2}};
  second.shards = {{1, 2}};
  first.wall_seconds = 10;
  second.wall_seconds = 5;
  first.peak_rss_mib = 100;
  second.peak_rss_mib = 300;
  first.results = {fake_result(0, {}, 0.004), fake_result(2, {"closed_manifold"}, 0.02),
                   fake_result(4, {}, 0.001)};
  second.results = {fake_result(1, {"sides_agree", "pieces_known"}, 0.003), fake_result(3, {}, 0.005),
                    fake_result(5, {"closed_manifold"}, 0.002)};
  const fs::path a = scratch("merge_a"), b = scratch("merge_b"), out = scratch("merge_out");
  write_summary(first, a.string());
  write_summary(second, b.string());
  fs::create_directories(a / "failures");
  std::ofstream(a / "failures" / "case_000002.json") << "{}";
  const Summary merged = merge_stress({a.string(), b.string()}, out.string());
  ASSERT_EQ(merged.results.size(), 6u);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(merged.results[i].index, i);
  EXPECT_EQ(merged.failed_cases(), 3u);
  EXPECT_DOUBLE_EQ(merged.wall_seconds, 15);
  EXPECT_DOUBLE_EQ(merged.peak_rss_mib, 300);
  const auto json = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(json["failures_by_invariant"]["closed_manifold"], 2);
  EXPECT_EQ(json["failures_by_invariant"]["sides_agree"], 1);
  EXPECT_EQ(json["failures_by_invariant"]["pieces_known"], 1);
  EXPECT_EQ(json["failures_by_invariant"]["no_exception"], 0);
  EXPECT_EQ(json["cases_run"], 6);
  // The worst generator -> exact deviation is case 2's 0.02 (twice the tolerance).
  EXPECT_EQ(json["worst_deviation"]["generator_to_exact"]["case"], 2);
  EXPECT_DOUBLE_EQ(json["worst_deviation"]["generator_to_exact"]["ratio_to_bound"].get<double>(), 2.0);
  EXPECT_TRUE(fs::exists(out / "failures" / "case_000002.json"));
  EXPECT_TRUE(fs::exists(out / "summary.md"));
  // The round trip keeps every field the summary is made of.
  const Summary again = summary_from_json(json, "summary.json");
  EXPECT_EQ(summary_to_json(again).dump(), json.dump());

  // Overlapping shards, or shards of another campaign, are refused.
  EXPECT_THROW(merge_stress({a.string(), a.string()}, scratch("merge_bad").string()), morph::InputError);
  Summary other = second;
  other.seed = 10;
  const fs::path c = scratch("merge_c");
  write_summary(other, c.string());
  EXPECT_THROW(merge_stress({a.string(), c.string()}, scratch("merge_bad2").string()), morph::InputError);
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

TEST(StressCampaign, BadInputExitsWithTwo) {
  const std::string binary = MORPHMILL_BINARY;
  EXPECT_EQ(run(binary + " stress --cases 4 --shard 4/4 --out " + scratch("bad").string()).exit_code, 2);
  EXPECT_EQ(run(binary + " stress --cases 0 --out " + scratch("bad").string()).exit_code, 2);
  EXPECT_EQ(run(binary + " stress-merge " + scratch("empty").string() + " --out " + scratch("bad").string())
                .exit_code,
            2);
}
