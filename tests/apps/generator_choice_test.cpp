// SPDX-License-Identifier: Apache-2.0
// --generator: one place decides what each generator builds, and verify runs the one chosen. A
// flat end mill is beyond generator 1 (verify checks the reference alone and says why) and within
// generator 2 (verify checks its surface against the exact one and the reference).
#include <gtest/gtest.h>

#include <morph/exceptions.h>
#include <morph/mesh.h>
#include <morph/stock.h>
#include <morph/tool.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include <morph/erode2.h>
#include <morphmill/job_io.h>

#include "apps/command_support.h"
#include "verify/generator_choice.h"

namespace fs = std::filesystem;

namespace {

morph::Job flat_slot_job() {
  morph::Job job;
  job.stock.type = morph::StockType::Box;
  job.stock.box = Eigen::AlignedBox3d(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(16, 10, 4));
  morph::Tool tool = morph::flat_tool(1.5, 8.0);
  tool.number = 1;
  job.tools[1] = tool;
  morph::Path path;
  morph::Move move;
  move.start = Eigen::Vector3d(3, 5, 2.5);
  move.end = Eigen::Vector3d(13, 5, 2.5);
  move.tool = 1;
  move.line = 1;
  path.moves.push_back(move);
  job.paths.push_back(path);
  job.tolerance = 0.05;
  return job;
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace

TEST(GeneratorChoice, EachGeneratorSaysWhatItCannotBuild) {
  morph::Job job = flat_slot_job();
  const std::string why = morphmill::why_generator_cannot_build(job, 1);
  EXPECT_NE(why.find("which generator 1 cannot build"), std::string::npos) << why;
  EXPECT_EQ(morphmill::why_generator_cannot_build(job, 2), "");
  job.stock.type = morph::StockType::Cylinder;
  job.stock.base = Eigen::Vector3d(8, 5, 0);
  job.stock.radius = 5.0;
  job.stock.height = 4.0;
  EXPECT_EQ(morphmill::why_generator_cannot_build(job, 2), "");
  job.stock.type = morph::StockType::Mesh;
  EXPECT_EQ(morphmill::why_generator_cannot_build(job, 2), "");
  EXPECT_EQ(morphmill::why_generator_cannot_build(job, morphmill::kAutoGenerator), "");
  EXPECT_THROW(morphmill::why_generator_cannot_build(job, 3), morph::InputError);
  EXPECT_THROW(morphmill::check_generator(-1), morph::InputError);
}

TEST(GeneratorChoice, GeneratorTwoFlatSlotVolumeIsTheClosedForm) {
  const morph::Job job = flat_slot_job();
  morph::ErodeOptions options;
  const morph::ErodeResult result = morphmill::run_generator(job, options, 2).result;
  // A flat end mill's level pass 1.5 deep: the slot 10 x 3 plus the two half discs, 1.5 deep.
  const double removed = (10.0 * 3.0 + M_PI * 1.5 * 1.5) * 1.5;
  // Within the tolerance everywhere: the volume within tolerance x the cut's area (floor and walls).
  const double cut_area = (10.0 * 3.0 + M_PI * 1.5 * 1.5) + (2 * 10.0 + 2 * M_PI * 1.5) * 1.5;
  EXPECT_NEAR(morph::enclosed_volume(result.mesh), 16.0 * 10.0 * 4.0 - removed, job.tolerance * cut_area);
}

TEST(GeneratorChoice, VerifyRunsTheGeneratorChosen) {
  const fs::path dir = morphmill_test::scratch_dir("generator_choice", "verify");
  fs::create_directories(dir);
  const fs::path job = dir / "flat_slot.json";
  std::ofstream(job) << R"({"stock": {"type": "box", "min": [0, 0, 0], "max": [16, 10, 4]},
    "tools": {"1": {"type": "flat", "radius": 1.5, "length": 8}},
    "paths": [{"tool": 1, "polyline": [[3, 5, 2.5], [13, 5, 2.5]]}], "tolerance": 0.05})";
  const std::string binary = MORPHMILL_BINARY;
  const std::string common = " --voxel 0.3 --samples 500 -q --json ";
  const auto two =
      morphmill_test::run_command(binary + " verify " + job.string() + " -o " + (dir / "g2").string() +
                                  " --generator 2" + common + (dir / "g2.json").string());
  EXPECT_EQ(two.exit_code, 0) << two.output;
  const auto report = nlohmann::json::parse(slurp(dir / "g2.json"));
  EXPECT_TRUE(report.at("pieces").at("generator").is_array()) << report.dump();
  EXPECT_EQ(report.at("provenance").at("options").at("generator"), "2");
  EXPECT_EQ(report.at("generator").at("used"), 2);
  EXPECT_LE(report.at("deviation").at("generator_to_exact").at("max_abs").get<double>(), 0.05);
  EXPECT_EQ(report.at("tools").at(0).at("generator_builds"), true);  // generator 2 builds every shape
  // Generator 1 cannot build the flat end mill: the reference alone, and the verdict says so.
  const auto one =
      morphmill_test::run_command(binary + " verify " + job.string() + " -o " + (dir / "g1").string() +
                                  " --generator 1" + common + (dir / "g1.json").string());
  EXPECT_EQ(one.exit_code, 1) << one.output;
  const auto skipped = nlohmann::json::parse(slurp(dir / "g1.json"));
  EXPECT_TRUE(skipped.at("pieces").at("generator").is_null()) << skipped.dump();
  EXPECT_EQ(skipped.at("tools").at(0).at("generator_builds"), false);
  // The default is generator 2, asked for by no option and chosen by no rule.
  const auto plain = morphmill_test::run_command(binary + " erode " + job.string() + " -o " +
                                                 (dir / "default.ply").string() + " --json " +
                                                 (dir / "default.json").string());
  EXPECT_EQ(plain.exit_code, 0) << plain.output;
  const auto by_default = nlohmann::json::parse(slurp(dir / "default.json"));
  EXPECT_EQ(by_default.at("generator_asked"), "2");
  EXPECT_EQ(by_default.at("generator"), 2);
  EXPECT_EQ(by_default.at("generator_choice"), "");
  // Auto hands it to generator 2 and says why.
  const auto chosen =
      morphmill_test::run_command(binary + " erode " + job.string() + " -o " + (dir / "auto.ply").string() +
                                  " --json " + (dir / "auto.json").string() + " --generator auto");
  EXPECT_EQ(chosen.exit_code, 0) << chosen.output;
  const auto summary = nlohmann::json::parse(slurp(dir / "auto.json"));
  EXPECT_EQ(summary.at("generator_asked"), "auto");
  EXPECT_EQ(summary.at("generator"), 2);
  // Where generator 2's CPU time went: every stage named, none negative, and the carving's three
  // stages ran (a flat end mill's slot has facets to cull and carve, and a stock to cut).
  const auto& stages = summary.at("stage_cpu_seconds");
  for (const char* stage : {"cull", "kept_facets", "stock_faces", "conform", "limit_and_emit"})
    EXPECT_GE(stages.at(stage).get<double>(), 0.0) << stage;
  EXPECT_GT(stages.at("cull").get<double>() + stages.at("kept_facets").get<double>(), 0.0) << stages.dump();
  EXPECT_NE(summary.at("generator_choice")
                .get<std::string>()
                .find("generator 1 builds spheres and ball ends only, and the move at line"),
            std::string::npos)
      << summary.dump();
  const auto bad = morphmill_test::run_command(binary + " verify " + job.string() + " -o " +
                                               (dir / "g3").string() + " --generator 3");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("--generator"), std::string::npos) << bad.output;
}

// Auto keeps generator 1's surface when it is sound (single_slot) and otherwise returns generator
// 2's (through_slots: generator 1 leaves it unsound today), counted as a fallback.
TEST(GeneratorChoice, AutoKeepsASoundSurfaceAndReplacesAnUnsoundOne) {
  const morph::ErodeOptions options;
  const std::string jobs = std::string(MORPHMILL_TEST_DATA) + "/jobs/";
  const morph::Job single_slot = morphmill::load_job(jobs + "single_slot.json");
  const morphmill::GeneratedSurface kept =
      morphmill::run_generator(single_slot, options, morphmill::kAutoGenerator);
  EXPECT_EQ(kept.generator, 1) << kept.choice;
  ASSERT_TRUE(kept.soundness.has_value());
  EXPECT_TRUE(kept.soundness->sound()) << kept.soundness->describe();
  EXPECT_EQ(kept.soundness->crossings.pairs, morphmill::check_soundness(kept.result.mesh).crossings.pairs);
  EXPECT_EQ(kept.result.mesh.triangle_count(), morph::erode(single_slot, options).mesh.triangle_count());

  const morph::Job through_slots = morphmill::load_job(jobs + "through_slots.json");
  const morphmill::SurfaceSoundness first =
      morphmill::check_soundness(morph::erode(through_slots, options).mesh);
  ASSERT_FALSE(first.sound())
      << "generator 1 now builds through_slots soundly: pick another job for this test";
  const morphmill::GeneratedSurface replaced =
      morphmill::run_generator(through_slots, options, morphmill::kAutoGenerator);
  EXPECT_EQ(replaced.generator, 2) << replaced.choice;
  EXPECT_NE(replaced.choice.find(first.describe()), std::string::npos) << replaced.choice;
  EXPECT_NE(replaced.choice.find("generator 2 built it instead"), std::string::npos) << replaced.choice;
  ASSERT_FALSE(replaced.result.stats.steps.empty());
  EXPECT_EQ(replaced.result.stats.steps.front().name, "generator_1_unsound");
  EXPECT_TRUE(replaced.result.stats.steps.front().fallback);
  const morphmill::SurfaceSoundness chosen = morphmill::check_soundness(replaced.result.mesh);
  EXPECT_TRUE(chosen.sound()) << chosen.describe();
  EXPECT_EQ(chosen.topology.components, 3u);  // the two slots cut the block into three
  // The very surface generator 2 builds when asked for it.
  const morph::TopologyReport exact_two = morph::topology_report(morph::erode2(through_slots, options).mesh);
  EXPECT_DOUBLE_EQ(chosen.topology.volume, exact_two.volume);
}

// Auto gives generator 1 a search limit where it would try generator 2: a job that costs generator
// 1 more searches (slots.json with the caller's limit of 100; heart.camotics runs 834 million on
// its own, ten minutes) goes to generator 2, and the choice says why. Without the limit
// generator 1 keeps slots.json. The limit auto sets follows generator 2's estimate.
TEST(GeneratorChoice, AutoStopsGenerator1AtItsSearchLimit) {
  const morph::Job slots = morphmill::load_job(std::string(MORPHMILL_TEST_DATA) + "/jobs/slots.json");
  morph::ErodeOptions options;
  const morph::ErodeResult first = morph::erode(slots, options);
  ASSERT_GT(first.stats.searches, 100u) << "slots.json no longer costs generator 1 searches";
  options.search_limit = 100;
  const morphmill::GeneratedSurface chosen =
      morphmill::run_generator(slots, options, morphmill::kAutoGenerator);
  EXPECT_EQ(chosen.generator, 2) << chosen.choice;
  EXPECT_NE(chosen.choice.find("generator 1 was stopped after 100 searches"), std::string::npos)
      << chosen.choice;
  EXPECT_NE(chosen.choice.find("generator 2 built it instead"), std::string::npos) << chosen.choice;
  const morphmill::SurfaceSoundness sound = morphmill::check_soundness(chosen.result.mesh);
  EXPECT_TRUE(sound.sound()) << sound.describe();

  // Generator 2 over the memory cap is not tried: the caller's search limit then stands.
  // (helix_pocket.json: generator 1 needs about 79 MiB, generator 2 147.)
  const morph::Job helix = morphmill::load_job(std::string(MORPHMILL_TEST_DATA) + "/jobs/helix_pocket.json");
  morph::ErodeOptions capped;
  capped.search_limit = 100;
  capped.memory_cap_bytes = std::size_t{96} << 20;
  ASSERT_LT(morph::estimate_erode2(helix, helix.tolerance).bytes, 2.0 * capped.memory_cap_bytes);
  ASSERT_GT(morph::estimate_erode2(helix, helix.tolerance).bytes, capped.memory_cap_bytes);
  EXPECT_THROW(morphmill::run_generator(helix, capped, morphmill::kAutoGenerator), morph::SearchLimitError);

  morph::Erode2Estimate estimate;
  estimate.sweep_facets = 1e7;
  EXPECT_EQ(morphmill::auto_search_limit(estimate), 50000000u);
  estimate.sweep_facets = 1000;
  EXPECT_EQ(morphmill::auto_search_limit(estimate), 1000000u);
  // slots.json runs about 0.2 searches a facet generator 2 would make: far within auto's limit.
  EXPECT_LT(static_cast<double>(first.stats.searches),
            morphmill::auto_search_limit(morph::estimate_erode2(slots, slots.tolerance)) / 10.0);
}
