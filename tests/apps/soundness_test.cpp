// SPDX-License-Identifier: Apache-2.0
// What erode promises of its surface (closed, oriented, no self-intersections) and the retired
// --generator: a flat end mill's slot is built and checked against the exact surface and the
// reference; `--generator 2` still runs, `1` and `auto` are refused with what replaced them.
#include <gtest/gtest.h>

#include <morph/exceptions.h>
#include <morph/mesh.h>
#include <morph/stock.h>
#include <morph/tool.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include <morph/erode.h>
#include <morphmill/job_io.h>
#include <morphmill/mesh_io.h>

#include "apps/command_support.h"
#include "verify/soundness.h"

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

// A closed cube (10 mm) is sound; without one triangle it is open, and says so; a triangle pushed through
// the box makes intersecting pairs.
TEST(Soundness, SaysWhatIsWrong) {
  const morph::TriangleMesh box = morphmill::read_mesh(std::string(MORPHMILL_TEST_DATA) + "/meshes/cube.stl");
  EXPECT_TRUE(morphmill::check_soundness(box).sound());
  EXPECT_EQ(morphmill::check_soundness(box).describe(), "sound");
  morph::TriangleMesh open = box;
  open.triangles.pop_back();
  if (!open.tags.empty()) open.tags.pop_back();
  const morphmill::SurfaceSoundness opened = morphmill::check_soundness(open);
  EXPECT_FALSE(opened.sound());
  EXPECT_EQ(opened.topology.boundary_edges, 3u);
  EXPECT_NE(opened.describe().find("not a closed manifold (3 boundary"), std::string::npos)
      << opened.describe();
  morph::TriangleMesh pierced = box;
  const auto v = static_cast<std::uint32_t>(pierced.vertices.size());
  pierced.vertices.insert(pierced.vertices.end(),
                          {Eigen::Vector3d(5, 5, -1), Eigen::Vector3d(6, 5, 11), Eigen::Vector3d(5, 6, 11)});
  pierced.triangles.push_back({v, v + 1, v + 2});
  if (!pierced.tags.empty()) pierced.tags.push_back(pierced.tags.back());
  const morphmill::SurfaceSoundness crossed = morphmill::check_soundness(pierced);
  EXPECT_FALSE(crossed.sound());
  EXPECT_GE(crossed.crossings.pairs, 2u);  // through the bottom and the top
  EXPECT_NE(crossed.describe().find("intersecting triangle pairs"), std::string::npos) << crossed.describe();
}

TEST(Soundness, FlatSlotVolumeIsTheClosedForm) {
  const morph::Job job = flat_slot_job();
  const morph::ErodeResult result = morph::erode(job);
  // A flat end mill's level pass 1.5 deep: the slot 10 x 3 plus the two half discs, 1.5 deep.
  const double removed = (10.0 * 3.0 + M_PI * 1.5 * 1.5) * 1.5;
  // Within the tolerance everywhere: the volume within tolerance x the cut's area (floor and walls).
  const double cut_area = (10.0 * 3.0 + M_PI * 1.5 * 1.5) + (2 * 10.0 + 2 * M_PI * 1.5) * 1.5;
  EXPECT_NEAR(morph::enclosed_volume(result.mesh), 16.0 * 10.0 * 4.0 - removed, job.tolerance * cut_area);
  EXPECT_TRUE(morphmill::check_soundness(result.mesh).sound());
}

TEST(Soundness, VerifyAndErodeRunTheGeneratorAndRefuseTheRetiredOnes) {
  const fs::path dir = morphmill_test::scratch_dir("soundness", "verify");
  fs::create_directories(dir);
  const fs::path job = dir / "flat_slot.json";
  std::ofstream(job) << R"({"stock": {"type": "box", "min": [0, 0, 0], "max": [16, 10, 4]},
    "tools": {"1": {"type": "flat", "radius": 1.5, "length": 8}},
    "paths": [{"tool": 1, "polyline": [[3, 5, 2.5], [13, 5, 2.5]]}], "tolerance": 0.05})";
  const std::string binary = MORPHMILL_BINARY;
  const std::string common = " --voxel 0.3 --samples 500 -q --json ";
  const auto checked = morphmill_test::run_command(binary + " verify " + job.string() + " -o " +
                                                   (dir / "v").string() + common + (dir / "v.json").string());
  EXPECT_EQ(checked.exit_code, 0) << checked.output;
  const auto report = nlohmann::json::parse(slurp(dir / "v.json"));
  EXPECT_TRUE(report.at("pieces").at("generator").is_array()) << report.dump();
  EXPECT_LE(report.at("deviation").at("generator_to_exact").at("max_abs").get<double>(), 0.05);
  EXPECT_FALSE(report.contains("generator")) << report.dump();
  const auto plain =
      morphmill_test::run_command(binary + " erode " + job.string() + " -o " + (dir / "plain.ply").string() +
                                  " --json " + (dir / "plain.json").string());
  EXPECT_EQ(plain.exit_code, 0) << plain.output;
  const auto summary = nlohmann::json::parse(slurp(dir / "plain.json"));
  EXPECT_FALSE(summary.contains("generator_choice")) << summary.dump();
  // Where the CPU time went: every stage named, none negative, and the carving's three stages ran
  // (a flat end mill's slot has facets to cull and carve, and a stock to cut).
  const auto& stages = summary.at("stage_cpu_seconds");
  for (const char* stage : {"cull", "kept_facets", "stock_faces", "conform", "limit_and_emit"})
    EXPECT_GE(stages.at(stage).get<double>(), 0.0) << stage;
  EXPECT_GT(stages.at("cull").get<double>() + stages.at("kept_facets").get<double>(), 0.0) << stages.dump();
  // --generator 2, as scripts written before the removal name it: the same surface, byte for byte.
  const auto named = morphmill_test::run_command(binary + " erode " + job.string() + " -o " +
                                                 (dir / "named.ply").string() + " --generator 2");
  EXPECT_EQ(named.exit_code, 0) << named.output;
  const auto body = [](const std::string& ply) { return ply.substr(ply.find("end_header")); };
  EXPECT_TRUE(body(slurp(dir / "named.ply")) == body(slurp(dir / "plain.ply")));
  // The retired generators are bad input (exit 2), named with what replaced them; nothing is written.
  for (const std::string retired : {"1", "auto"}) {
    const auto refused =
        morphmill_test::run_command(binary + " erode " + job.string() + " -o " +
                                    (dir / "retired.ply").string() + " --generator " + retired);
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_NE(refused.output.find("generator " + retired + " was removed"), std::string::npos)
        << refused.output;
    EXPECT_FALSE(fs::exists(dir / "retired.ply"));
  }
  const auto bad = morphmill_test::run_command(binary + " verify " + job.string() + " -o " +
                                               (dir / "g3").string() + " --generator 3");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("the only generator is 2"), std::string::npos) << bad.output;
}
