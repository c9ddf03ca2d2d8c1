// SPDX-License-Identifier: Apache-2.0
// `morphmill info` and `morphmill mesh-info` run as a user runs them: exit codes and messages.
#include <gtest/gtest.h>
#include <morphmill/mesh_io.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "apps/command_support.h"
#include "common/test_meshes.h"

namespace {

namespace fs = std::filesystem;
const std::string kData = MORPHMILL_TEST_DATA;

struct CommandRun {
  int exit_code = -1;
  std::string output;  // stdout
  std::string errors;  // stderr
};

std::string slurp(const fs::path& file) {
  std::ifstream in(file);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

class CliInfo : public morphmill_test::ScratchDirTest {
 protected:
  CommandRun run(const std::string& arguments) const {
    const std::string command = std::string("'") + MORPHMILL_BINARY + "' " + arguments + " > '" +
                                (dir_ / "out").string() + "' 2> '" + (dir_ / "err").string() + "'";
    const int status = std::system(command.c_str());
    CommandRun r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.output = slurp(dir_ / "out");
    r.errors = slurp(dir_ / "err");
    return r;
  }
};

TEST_F(CliInfo, InfoPrintsTheJobAsUnderstood) {
  const CommandRun r = run("info '" + kData + "/jobs/slots.json'");
  ASSERT_EQ(r.exit_code, 0) << r.errors;
  EXPECT_TRUE(r.errors.empty()) << r.errors;
  EXPECT_NE(r.output.find("Job slots"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Stock: box  min (0, 0, 0)  max (100, 60, 20)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("T1    ballend diameter 6, length 40 above the ball's centre"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("Moves: 8 (rapid 1, linear 5, arc 2)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Bounds of the tool point: (-5, 8, 16) .. (105, 30, 25)"), std::string::npos)
      << r.output;
}

// A flat end mill is named by its shape and sizes, with no remark: the generator builds every tool.
TEST_F(CliInfo, InfoNamesAToolByItsShape) {
  const CommandRun r = run("info '" + kData + "/jobs/tool_flat.json'");
  ASSERT_EQ(r.exit_code, 0) << r.errors;
  EXPECT_NE(r.output.find("T1    flat diameter 6, length 20\n"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("cannot build"), std::string::npos) << r.output;
}

TEST_F(CliInfo, InfoJson) {
  const CommandRun r = run("info --json '" + kData + "/jobs/mesh_stock.json'");
  ASSERT_EQ(r.exit_code, 0) << r.errors;
  const nlohmann::json d = nlohmann::json::parse(r.output);
  EXPECT_EQ(d["stock"]["type"], "mesh");
  EXPECT_EQ(d["stock"]["triangles"], 12);
  EXPECT_EQ(d["moves"]["total"], 2);
  EXPECT_EQ(d["tools"][0]["number"], 2);
  EXPECT_EQ(d["tools"][0]["type"], "sphere");
}

TEST_F(CliInfo, MovesOfAGcodeFileAsJson) {
  // The canned-cycle conformance program from the machine origin: its first moves and a cycle.
  const CommandRun r =
      run("info --moves '" + kData + "/gcode/conformance/canned_cycles.ngc' --format json --start 0,0,0");
  ASSERT_EQ(r.exit_code, 0) << r.errors;
  const nlohmann::json d = nlohmann::json::parse(r.output);
  EXPECT_EQ(d["units"], "mm");
  const nlohmann::json& moves = d["moves"];
  ASSERT_GT(moves.size(), 10u);
  EXPECT_EQ(moves[0]["kind"], "rapid");
  EXPECT_EQ(moves[0]["line"], 4);
  EXPECT_EQ(moves[0]["end"], nlohmann::json::parse("[0, 0, 10]"));
  EXPECT_EQ(moves[3]["kind"], "linear");  // G81 feeds to the bottom
  EXPECT_EQ(moves[3]["end"], nlohmann::json::parse("[5, 5, -2]"));
  EXPECT_EQ(moves[3]["line"], 5);
  EXPECT_DOUBLE_EQ(moves[3]["feed"].get<double>(), 100.0);
  // A job's moves, arcs with their centre, axis and sweep; a bad G-code file: exit 2 with its line.
  const CommandRun job = run("info --moves '" + kData + "/jobs/slots.json' --format json");
  ASSERT_EQ(job.exit_code, 0) << job.errors;
  bool arc = false;
  const nlohmann::json job_moves = nlohmann::json::parse(job.output)["moves"];
  for (const nlohmann::json& m : job_moves)
    if (m["kind"] == "arc") arc = m.contains("center") && m.contains("axis") && m.contains("sweep");
  EXPECT_TRUE(arc);
  const CommandRun bad = run("info --moves '" + kData + "/gcode/conformance/refuse_undefined_parameter.ngc'");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.errors.find("refuse_undefined_parameter.ngc:4: named parameter #<width> is not defined"),
            std::string::npos)
      << bad.errors;
}

TEST_F(CliInfo, MeshInfoTable) {
  const CommandRun r = run("mesh-info '" + kData + "/meshes/cube.stl'");
  ASSERT_EQ(r.exit_code, 0) << r.errors;
  EXPECT_NE(r.output.find("Euler characteristic    2\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("closed manifold         yes\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("enclosed volume         1000\n"), std::string::npos) << r.output;
}

TEST_F(CliInfo, MeshInfoJsonOfAnOpenTaggedMesh) {
  morph::TriangleMesh open = morphmill_test::box({0, 0, 0}, {1, 1, 1});
  open.triangles.resize(10);
  open.tags.assign(10, {morph::PatchKind::CutSurface, 1, 2});
  const std::string file = (dir_ / "open.ply").string();
  morphmill::write_mesh(open, file);
  const CommandRun r = run("mesh-info --json '" + file + "'");
  ASSERT_EQ(r.exit_code, 0) << r.errors;  // a report, whatever it says
  const nlohmann::json d = nlohmann::json::parse(r.output);
  EXPECT_EQ(d["boundary_edges"], 4);
  EXPECT_EQ(d["euler_characteristic"], 1);
  EXPECT_EQ(d["closed_manifold"], false);
  EXPECT_FALSE(d.contains("genus"));
  EXPECT_EQ(d["face_tags"]["cut_surface"], 10);
  const CommandRun table = run("mesh-info '" + file + "'");
  EXPECT_NE(table.output.find("closed manifold         no\n"), std::string::npos) << table.output;
}

TEST_F(CliInfo, BadInputExitsWithTwoAndNamesFileAndProblem) {
  const std::string missing = (dir_ / "missing.json").string();
  CommandRun r = run("info '" + missing + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.errors.find(missing), std::string::npos) << r.errors;
  EXPECT_NE(r.errors.find("No such file"), std::string::npos) << r.errors;

  const std::string bad = write_text("bad.json", R"({"stock": {"type": "box", "min": [0,0,0], "max": [1,1,1]},
                      "tools": {"1": {"type": "sphere", "radius": 1}},
                      "paths": [{"tool": 1, "polyline": [[0,0,0], [1,0]]}]})");
  r = run("info '" + bad + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.errors.find(bad + ": paths[0].polyline[1]: expected 3 numbers"), std::string::npos) << r.errors;
  EXPECT_TRUE(r.output.empty()) << r.output;

  const std::string garbage = write_text("garbage.ply", "solid nonsense\n");
  r = run("mesh-info '" + garbage + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.errors.find(garbage + ": not a PLY file"), std::string::npos) << r.errors;

  r = run("mesh-info '" + (dir_ / "part.off").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.errors.find("part.off: unknown mesh format '.off'"), std::string::npos) << r.errors;

  r = run("mesh-info '" + (dir_ / "absent.stl").string() + "' --json");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.errors.find("absent.stl"), std::string::npos) << r.errors;
}

TEST_F(CliInfo, UsageErrorsAndHelp) {
  EXPECT_EQ(run("info").exit_code, 2);
  EXPECT_EQ(run("mesh-info a.stl b.stl").exit_code, 2);
  EXPECT_EQ(run("info --frobnicate x.json").exit_code, 2);
  const CommandRun help = run("info --help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("--json"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("docs/job-format.md"), std::string::npos) << help.output;
  const CommandRun mesh_help = run("mesh-info --help");
  EXPECT_EQ(mesh_help.exit_code, 0);
  EXPECT_NE(mesh_help.output.find("non-manifold"), std::string::npos) << mesh_help.output;
}

}  // namespace
