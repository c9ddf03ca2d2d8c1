// SPDX-License-Identifier: Apache-2.0
// Job files: every key, the defaults, the warnings, and every error path (each message must name
// the file and the JSON path of the value at fault).
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/topology.h>
#include <morphmill/job_io.h>
#include <morphmill/mesh_io.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "apps/command_support.h"
#include "common/test_meshes.h"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kPi = 3.14159265358979323846;
const std::string kData = MORPHMILL_TEST_DATA;

class JobIo : public morphmill_test::ScratchDirTest {
 protected:
  /// The job file name used in messages; relative paths resolve next to it.
  std::string job_file() const { return path("t.json"); }
  morph::Job parse(const json& j) const { return morphmill::parse_job(j, job_file()); }
  /// The InputError message of parsing `j`, or a marker that makes the test fail.
  std::string error(const json& j) const {
    try {
      parse(j);
    } catch (const morph::InputError& e) {
      return e.what();
    } catch (const std::exception& e) {
      return std::string("wrong exception type: ") + e.what();
    }
    return "no error";
  }
  void expect_error(const json& j, const std::string& json_path_and_problem) const {
    const std::string message = error(j);
    EXPECT_EQ(message.rfind(job_file() + ": ", 0), 0u) << "message does not start with the file: " << message;
    EXPECT_NE(message.find(json_path_and_problem), std::string::npos)
        << "expected '" << json_path_and_problem << "' in: " << message;
  }
};

json minimal() {
  return json::parse(R"({
    "stock": {"type": "box", "min": [0, 0, 0], "max": [10, 10, 10]},
    "tools": {"1": {"type": "sphere", "radius": 1}},
    "paths": [{"tool": 1, "polyline": [[0, 0, 5], [10, 0, 5]]}]
  })");
}

bool has_warning(const morph::Job& job, const std::string& text) {
  for (const morph::Warning& w : job.warnings)
    if (w.message.find(text) != std::string::npos) return true;
  return false;
}

// ---- the bundled jobs and every key

TEST_F(JobIo, LoadsSlotsJob) {
  const morph::Job job = morphmill::load_job(kData + "/jobs/slots.json");
  EXPECT_EQ(job.name, "slots");
  EXPECT_NE(job.description.find("serpentine"), std::string::npos);
  EXPECT_EQ(job.units, morph::Units::Millimetre);
  EXPECT_EQ(job.tolerance, 0.01);
  EXPECT_EQ(job.stock.type, morph::StockType::Box);
  EXPECT_EQ(job.stock.box.min(), Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(job.stock.box.max(), Eigen::Vector3d(100, 60, 20));
  ASSERT_EQ(job.tools.size(), 1u);
  const morph::Tool& tool = job.tools.at(1);
  EXPECT_EQ(tool.number, 1);
  EXPECT_EQ(tool.type, morph::ToolType::BallEnd);
  EXPECT_EQ(tool.radius, 3.0);
  EXPECT_EQ(tool.length, 40.0);
  ASSERT_EQ(job.paths.size(), 2u);

  const morph::Path& slot = job.paths[0];
  EXPECT_EQ(slot.name, "slot");
  EXPECT_EQ(slot.source, "paths[0].polyline");
  ASSERT_EQ(slot.moves.size(), 1u);
  EXPECT_EQ(slot.moves[0].kind, morph::MoveKind::Linear);
  EXPECT_EQ(slot.moves[0].start, Eigen::Vector3d(-5, 30, 17));
  EXPECT_EQ(slot.moves[0].end, Eigen::Vector3d(105, 30, 17));
  EXPECT_EQ(slot.moves[0].line, 2);  // the index + 1 of the point the move ends at
  EXPECT_EQ(slot.moves[0].tool, 1);

  // pocket.nc: G1 Z16, G1 X70, G3, G1 X30, G2, G1 X70, G0 Z25 (the rapids before it only set
  // the start position).
  const morph::Path& pocket = job.paths[1];
  EXPECT_EQ(pocket.name, "pocket");
  EXPECT_NE(pocket.source.find("pocket.nc"), std::string::npos);
  ASSERT_EQ(pocket.moves.size(), 7u);
  const morph::MoveKind expected_kinds[] = {
      morph::MoveKind::Linear, morph::MoveKind::Linear, morph::MoveKind::Arc,  morph::MoveKind::Linear,
      morph::MoveKind::Arc,    morph::MoveKind::Linear, morph::MoveKind::Rapid};
  const int expected_lines[] = {9, 10, 11, 12, 13, 14, 15};
  for (std::size_t i = 0; i < 7; ++i) {
    EXPECT_EQ(pocket.moves[i].kind, expected_kinds[i]) << "move " << i;
    EXPECT_EQ(pocket.moves[i].line, expected_lines[i]) << "move " << i;
    EXPECT_EQ(pocket.moves[i].tool, 1);
  }
  EXPECT_GT(pocket.moves[2].sweep, 0.0);  // G3: counter-clockwise
  EXPECT_LT(pocket.moves[4].sweep, 0.0);  // G2: clockwise
  EXPECT_NEAR(std::abs(pocket.moves[2].sweep), kPi, 1e-12);
}

TEST_F(JobIo, DescribeSlotsJob) {
  const json d = morphmill::describe_job(morphmill::load_job(kData + "/jobs/slots.json"));
  EXPECT_EQ(d["name"], "slots");
  EXPECT_EQ(d["units"], "mm");
  EXPECT_EQ(d["stock"]["type"], "box");
  EXPECT_EQ(d["stock"]["volume"].get<double>(), 100.0 * 60.0 * 20.0);
  ASSERT_EQ(d["tools"].size(), 1u);
  EXPECT_EQ(d["tools"][0]["type"], "ballend");
  EXPECT_EQ(d["moves"]["total"], 8);
  EXPECT_EQ(d["moves"]["by_kind"]["rapid"], 1);
  EXPECT_EQ(d["moves"]["by_kind"]["linear"], 5);
  EXPECT_EQ(d["moves"]["by_kind"]["arc"], 2);
  // Slot 110; pocket: plunge 9, three 40 mm rows, two half circles of radius 4, retract 9.
  EXPECT_NEAR(d["path_length"]["total"].get<double>(), 110 + 9 + 3 * 40 + 2 * kPi * 4 + 9, 1e-9);
  EXPECT_NEAR(d["path_length"]["by_kind"]["arc"].get<double>(), 8 * kPi, 1e-9);
  EXPECT_NEAR(d["paths"][1]["length"].get<double>(), 9 + 3 * 40 + 8 * kPi + 9, 1e-9);
  EXPECT_EQ(d["paths"][0]["name"], "slot");
  // The G3 arc about (70, 12) reaches x = 74, the G2 about (30, 20) x = 26: inside the slot's x
  // range, so the box is the slot's x extent, the pocket's y range up to the slot, z 16..25.
  const json& b = d["bounds"];
  const double tol = 0.01;
  EXPECT_NEAR(b["min"][0].get<double>(), -5, tol);
  EXPECT_NEAR(b["min"][1].get<double>(), 8, tol);
  EXPECT_NEAR(b["min"][2].get<double>(), 16, tol);
  EXPECT_NEAR(b["max"][0].get<double>(), 105, tol);
  EXPECT_NEAR(b["max"][1].get<double>(), 30, tol);
  EXPECT_NEAR(b["max"][2].get<double>(), 25, tol);
  const json& pb = d["paths"][1]["bounds"];
  EXPECT_NEAR(pb["max"][0].get<double>(), 74, tol);  // the arc's extreme, not an end point
  EXPECT_NEAR(pb["min"][0].get<double>(), 26, tol);
  EXPECT_TRUE(d["warnings"].is_array());
}

TEST_F(JobIo, LoadsMeshStockJob) {
  const morph::Job job = morphmill::load_job(kData + "/jobs/mesh_stock.json");
  EXPECT_EQ(job.stock.type, morph::StockType::Mesh);
  EXPECT_EQ(job.stock.mesh.triangles.size(), 12u);
  EXPECT_EQ(fs::path(job.stock.mesh_path).filename(), "block.stl");
  EXPECT_TRUE(fs::exists(job.stock.mesh_path));
  EXPECT_DOUBLE_EQ(morph::volume(job.stock), 100.0 * 60.0 * 20.0);
  ASSERT_EQ(job.paths.size(), 1u);
  ASSERT_EQ(job.paths[0].moves.size(), 2u);
  EXPECT_EQ(job.paths[0].moves[0].tool, 2);  // one tool: "tool" may be left out
  EXPECT_EQ(job.paths[0].moves[1].line, 3);
}

TEST_F(JobIo, DefaultsAndOptionalKeys) {
  json j = minimal();
  morph::Job job = parse(j);
  EXPECT_EQ(job.name, "t");  // the file stem
  EXPECT_EQ(job.units, morph::Units::Millimetre);
  EXPECT_EQ(job.tolerance, 0.01);
  EXPECT_TRUE(job.description.empty());
  EXPECT_TRUE(job.warnings.empty());
  EXPECT_EQ(job.file, job_file());

  j["units"] = "inch";
  job = parse(j);
  EXPECT_EQ(job.units, morph::Units::Inch);
  EXPECT_DOUBLE_EQ(job.tolerance, 0.01 / 25.4);  // 0.01 mm in inches
  j["tolerance"] = 0.002;
  j["name"] = "named";
  j["description"] = "free text";
  job = parse(j);
  EXPECT_EQ(job.tolerance, 0.002);
  EXPECT_EQ(job.name, "named");
  EXPECT_EQ(job.description, "free text");
}

TEST_F(JobIo, CylinderStock) {
  json j = minimal();
  j["stock"] = {{"type", "cylinder"}, {"base", {1, 2, 3}}, {"axis", {0, 0, 2}}, {"radius", 5}, {"height", 7}};
  morph::Job job = parse(j);
  EXPECT_EQ(job.stock.type, morph::StockType::Cylinder);
  EXPECT_EQ(job.stock.base, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(job.stock.axis, Eigen::Vector3d(0, 0, 1));  // normalised
  EXPECT_EQ(job.stock.radius, 5.0);
  EXPECT_EQ(job.stock.height, 7.0);
  j["stock"].erase("axis");
  j["stock"]["base"] = {0, 0, 0};
  job = parse(j);
  EXPECT_EQ(job.stock.axis, Eigen::Vector3d::UnitZ());  // default axis
  j["stock"]["axis"] = {1, 1, 0};
  job = parse(j);
  EXPECT_NEAR(job.stock.axis.x(), std::sqrt(0.5), 1e-15);
}

TEST_F(JobIo, EveryToolType) {
  json j = minimal();
  j["tools"] = json::parse(R"({
    "1": {"type": "sphere", "radius": 1, "description": "the paper's B"},
    "2": {"type": "ballend", "radius": 3, "length": 40},
    "3": {"type": "flat", "radius": 2, "length": 20},
    "4": {"type": "bullnose", "radius": 4, "length": 30, "corner_radius": 1},
    "5": {"type": "conical", "radius": 5, "length": 25, "angle": 90, "tip_radius": 0.1},
    "6": {"type": "conical", "radius": 5, "length": 25, "angle": 60}
  })");
  const morph::Job job = parse(j);
  ASSERT_EQ(job.tools.size(), 6u);
  EXPECT_EQ(job.tools.at(1).type, morph::ToolType::Sphere);
  EXPECT_EQ(job.tools.at(2).type, morph::ToolType::BallEnd);
  EXPECT_EQ(job.tools.at(3).type, morph::ToolType::Flat);
  EXPECT_EQ(job.tools.at(3).length, 20.0);
  EXPECT_EQ(job.tools.at(4).type, morph::ToolType::Bullnose);
  EXPECT_EQ(job.tools.at(4).corner_radius, 1.0);
  EXPECT_EQ(job.tools.at(5).type, morph::ToolType::Conical);
  EXPECT_EQ(job.tools.at(5).angle, 90.0);
  EXPECT_EQ(job.tools.at(5).tip_radius, 0.1);
  EXPECT_EQ(job.tools.at(6).tip_radius, 0.0);
  // Every shape parses into a profile (what the generator sweeps).
  for (const auto& [number, tool] : job.tools) EXPECT_FALSE(tool.profile.empty()) << number;
  EXPECT_EQ(job.tools.at(1).description, "the paper's B");
  for (const auto& [number, tool] : job.tools) EXPECT_EQ(tool.number, number);
  const json d = morphmill::describe_job(job);
  EXPECT_EQ(d["tools"][3]["corner_radius"], 1.0);
  EXPECT_FALSE(d["tools"][4].contains("generator"));
  EXPECT_EQ(d["tools"][3]["shape"], "bullnose diameter 8, corner radius 1, length 30");
}

TEST_F(JobIo, PolylineKeys) {
  json j = minimal();
  j["paths"] = json::parse(R"([{"tool": "1", "name": "zig", "description": "d", "feed": 250,
    "polyline": [[0, 0, 5], [10, 0, 5], [10, 0, 5], [10, 10, 4.5]]}])");
  const morph::Job job = parse(j);
  const morph::Path& p = job.paths[0];
  EXPECT_EQ(p.name, "zig");
  ASSERT_EQ(p.moves.size(), 2u);  // the repeated point makes no move
  EXPECT_EQ(p.moves[0].line, 2);
  EXPECT_EQ(p.moves[1].line, 4);
  EXPECT_EQ(p.moves[1].start, Eigen::Vector3d(10, 0, 5));
  EXPECT_EQ(p.moves[1].end, Eigen::Vector3d(10, 10, 4.5));
  EXPECT_EQ(p.moves[1].feed, 250.0);
  EXPECT_TRUE(has_warning(job, "paths[0].polyline[2]: repeats the previous point"));
}

TEST_F(JobIo, GcodeKeysUnitsAndStart) {
  write_text("mm.nc", "G21 G90\nG1 X25.4 Y0 Z0 F254\nG1 X50.8 M123\n");
  json j = minimal();
  j["units"] = "inch";
  j["paths"] = json::parse(R"([{"tool": 1, "gcode": "mm.nc", "start": [0, 0, 1]}])");
  const morph::Job job = parse(j);
  const morph::Path& p = job.paths[0];
  ASSERT_EQ(p.moves.size(), 2u);
  EXPECT_EQ(p.moves[0].start, Eigen::Vector3d(0, 0, 1));  // from "start"
  EXPECT_NEAR(p.moves[0].end.x(), 1.0, 1e-15);            // 25.4 mm in an inch job
  EXPECT_NEAR(p.moves[1].end.x(), 2.0, 1e-15);
  EXPECT_NEAR(p.moves[0].feed, 10.0, 1e-12);
  EXPECT_EQ(p.moves[1].line, 3);
  // The G-code reader's warnings join the job's, with their file and line.
  bool found = false;
  for (const morph::Warning& w : job.warnings)
    if (w.line == 3 && w.file.find("mm.nc") != std::string::npos) found = true;
  EXPECT_TRUE(found);
}

TEST_F(JobIo, GcodeMachineSetUpKeys) {
  // G55 offsets from the job, T2 changed on T alone, the '/' line run, a var file for G28.
  write_text("setup.nc", "G21 G90 F100\nG55 G0 X0 Y0 Z0\nT2\n/G1 X1\nG28\nM2\n");
  write_text("machine.var", "5161 7\n5162 8\n5163 9\n");
  json j = minimal();
  j["tools"]["2"] = json::parse(R"({"type": "sphere", "radius": 2})");
  j["paths"] = json::parse(
      R"([{"tool": 1, "gcode": "setup.nc", "start": [0, 0, 0], "work_offsets": {"G55": [10, 20, 30]},
      "tool_change_on_t": true, "block_delete": false, "var_file": "machine.var"}])");
  const morph::Job job = parse(j);
  const morph::Path& p = job.paths[0];
  ASSERT_EQ(p.moves.size(), 3u);
  EXPECT_EQ(p.moves[0].end, Eigen::Vector3d(10, 20, 30));
  EXPECT_EQ(p.moves[1].end, Eigen::Vector3d(11, 20, 30));
  EXPECT_EQ(p.moves[1].tool, 2);
  EXPECT_EQ(p.moves[2].end, Eigen::Vector3d(7, 8, 9));
  j["paths"][0]["work_offsets"] = json::parse(R"({"G60": [0, 0, 0]})");
  expect_error(j, "paths[0].work_offsets.G60: expected one of G54");
  j["paths"][0]["work_offsets"] = json::parse("{}");
  j["paths"][0]["tool_change_on_t"] = 1;
  expect_error(j, "paths[0].tool_change_on_t: expected true or false");
}

TEST_F(JobIo, GcodeToolLengthOffsetsComeFromTheJobsTools) {
  // Tool 1 is 25 long, tool 2 31.5 (the tool table's Z): G43 H applies them to the gauge line.
  json j = minimal();
  j["tools"]["1"]["length_offset"] = 25.0;
  j["tools"]["2"] = json::parse(R"({"type": "sphere", "radius": 2, "length_offset": 31.5})");
  write_text("g43.nc",
             "G21 G90 F100\nG0 X0 Y0 Z10\nG43 H1\nG1 Z-1\nT2 M6\nG43 H2\nG1 X5 Z-1\nG43 H1\nG1 X6 Z-1\nM2\n");
  j["paths"] = json::parse(R"([{"tool": 1, "gcode": "g43.nc"}])");
  const morph::Job job = parse(j);
  const morph::Path& p = job.paths[0];
  ASSERT_EQ(p.moves.size(), 3u);
  EXPECT_EQ(p.moves[0].start, Eigen::Vector3d(0, 0, -15));  // gauge line at 10, tip 25 below
  EXPECT_EQ(p.moves[0].end, Eigen::Vector3d(0, 0, -1));     // with G43 H1 Z-1 is the tip
  EXPECT_EQ(p.moves[1].end, Eigen::Vector3d(5, 0, -1));     // tool 2 with its own offset
  EXPECT_EQ(p.moves[2].end, Eigen::Vector3d(6, 0, -7.5));   // tool 2 with tool 1's offset: 6.5 lower
  // The same tools, a program without G43: the tip is at the programmed point, not 25 lower.
  write_text("plain.nc", "G21 G90 F100\nG0 X0 Y0 Z10\nG1 Z-1\nM2\n");
  j["paths"][0]["gcode"] = "plain.nc";
  const morph::Job plain = parse(j);
  ASSERT_EQ(plain.paths[0].moves.size(), 1u);
  EXPECT_EQ(plain.paths[0].moves[0].end, Eigen::Vector3d(0, 0, -1));
}

TEST_F(JobIo, UnknownKeysAreWarningsWithSuggestions) {
  json j = minimal();
  j["tolerence"] = 0.1;
  j["_comment"] = "keys starting with an underscore are comments";
  j["stock"]["colour"] = "red";
  j["tools"]["1"]["length"] = 10;  // not a sphere key
  j["paths"][0]["tol"] = 1;
  const morph::Job job = parse(j);
  EXPECT_EQ(job.tolerance, 0.01);  // the misspelt key did not count
  ASSERT_EQ(job.warnings.size(), 4u);
  EXPECT_TRUE(has_warning(job, "tolerence: unknown key, ignored (did you mean 'tolerance'?)"));
  EXPECT_TRUE(has_warning(job, "stock.colour: unknown key"));
  EXPECT_TRUE(has_warning(job, "tools.1.length: unknown key"));
  EXPECT_TRUE(has_warning(job, "paths[0].tol: unknown key"));
  for (const morph::Warning& w : job.warnings) EXPECT_EQ(w.file, job_file());
  const json d = morphmill::describe_job(job);
  EXPECT_EQ(d["warnings"].size(), 4u);
}

// ---- errors

TEST_F(JobIo, TheIssueExampleMessage) {
  json j = minimal();
  j["paths"] = json::array();
  for (int i = 0; i < 3; ++i) j["paths"].push_back({{"tool", 1}, {"polyline", {{0, 0, 0}, {1, 0, 0}}}});
  j["paths"][2]["polyline"] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}, {5, 0}};
  try {
    morphmill::parse_job(j, "slots.json");
    FAIL() << "no error";
  } catch (const morph::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("slots.json: paths[2].polyline[5]: expected 3 numbers", 0), 0u)
        << e.what();
  }
}

TEST_F(JobIo, TopLevelErrors) {
  expect_error(json::array({1, 2}), "expected an object, got array [1,2]");
  json j = minimal();
  j.erase("stock");
  expect_error(j, "missing required key 'stock'");
  j = minimal();
  j.erase("tools");
  expect_error(j, "missing required key 'tools'");
  j = minimal();
  j.erase("paths");
  expect_error(j, "missing required key 'paths'");
  j = minimal();
  j["units"] = "cm";
  expect_error(j, "units: expected \"mm\" or \"inch\", got \"cm\"");
  j["units"] = 1;
  expect_error(j, "units: expected a string, got number 1");
  for (const json& bad : {json(0), json(-0.5), json("0.1")}) {
    j = minimal();
    j["tolerance"] = bad;
    expect_error(j, "tolerance: ");
  }
  j["tolerance"] = 0;
  expect_error(j, "tolerance: must be greater than 0, got 0");
  j = minimal();
  j["name"] = 5;
  expect_error(j, "name: expected a string");
  j = minimal();
  j["description"] = json::array();
  expect_error(j, "description: expected a string");
}

TEST_F(JobIo, StockErrors) {
  json j = minimal();
  j["stock"] = "box";
  expect_error(j, "stock: expected an object, got string \"box\"");
  j["stock"] = {{"min", {0, 0, 0}}};
  expect_error(j, "stock: missing required key 'type'");
  j["stock"] = {{"type", "sphere"}};
  expect_error(j, "stock.type: unknown stock type 'sphere' (expected box, cylinder or mesh)");
  j["stock"] = {{"type", "box"}, {"min", {0, 0}}, {"max", {1, 1, 1}}};
  expect_error(j, "stock.min: expected 3 numbers");
  j["stock"] = {{"type", "box"}, {"min", {0, 0, 0}}};
  expect_error(j, "stock: missing required key 'max'");
  j["stock"] = {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {1, "1", 1}}};
  expect_error(j, "stock.max: expected 3 numbers");
  j["stock"] = {{"type", "box"}, {"min", {0, 0, 5}}, {"max", {1, 1, 5}}};
  expect_error(j, "stock.max: must exceed min in every axis, but z max 5 <= min 5");
  j["stock"] = {{"type", "cylinder"}, {"base", {0, 0, 0}}, {"radius", -1}, {"height", 1}};
  expect_error(j, "stock.radius: must be greater than 0, got -1");
  j["stock"] = {{"type", "cylinder"}, {"base", {0, 0, 0}}, {"radius", 1}, {"height", 0}};
  expect_error(j, "stock.height: must be greater than 0");
  j["stock"] = {{"type", "cylinder"}, {"base", {0, 0, 0}}, {"axis", {0, 0, 0}}, {"radius", 1}, {"height", 1}};
  expect_error(j, "stock.axis: must not be the zero vector");
  j["stock"] = {{"type", "cylinder"}, {"radius", 1}, {"height", 1}};
  expect_error(j, "stock: missing required key 'base'");
}

TEST_F(JobIo, MeshStockErrors) {
  json j = minimal();
  j["stock"] = {{"type", "mesh"}};
  expect_error(j, "stock: missing required key 'path'");
  j["stock"]["path"] = "nothere.stl";
  expect_error(j, "stock.path: mesh file 'nothere.stl' not found (looked for '" + path("nothere.stl") + "')");

  morph::TriangleMesh open = morphmill_test::box({0, 0, 0}, {1, 1, 1});
  open.triangles.resize(10);
  morphmill::write_mesh(open, path("open.stl"));
  j["stock"]["path"] = "open.stl";
  expect_error(j, "stock.path: stock mesh '" + path("open.stl") +
                      "' is not a closed oriented manifold (4 boundary edges");

  morph::TriangleMesh inward = morphmill_test::box({0, 0, 0}, {1, 1, 1});
  for (morph::Triangle& t : inward.triangles) std::swap(t[1], t[2]);
  morphmill::write_mesh(inward, path("inward.ply"));
  j["stock"]["path"] = "inward.ply";
  expect_error(j, "stock.path: stock mesh '" + path("inward.ply") + "' is wound inward");

  // One closed, outward-wound shell whose top corner is pushed through the bottom face: a valid
  // manifold that crosses itself.
  morph::TriangleMesh crossing = morphmill_test::box({0, 0, 0}, {1, 1, 1});
  for (Eigen::Vector3d& v : crossing.vertices)
    if (v == Eigen::Vector3d(1, 1, 1)) v = {0.6, 0.6, -0.5};
  ASSERT_TRUE(morph::topology_report(crossing).closed_manifold());
  ASSERT_GT(morph::topology_report(crossing).volume, 0.0);
  morphmill::write_mesh(crossing, path("crossing.ply"));
  j["stock"]["path"] = "crossing.ply";
  expect_error(j, "stock.path: stock mesh '" + path("crossing.ply") + "' intersects itself: ");
  expect_error(j, "pairs of triangles cross (first: triangles ");

  write_text("garbage.obj", "nothing here\n");
  j["stock"]["path"] = "garbage.obj";
  expect_error(j, "stock.path: " + path("garbage.obj") + ": no triangles found");
  j["stock"]["path"] = "mesh.off";
  write_text("mesh.off", "OFF\n");
  expect_error(j, "stock.path: " + path("mesh.off") + ": unknown mesh format '.off'");
}

TEST_F(JobIo, ToolErrors) {
  json j = minimal();
  j["tools"] = json::object();
  expect_error(j, "tools: defines no tools");
  j["tools"] = json::array();
  expect_error(j, "tools: expected an object, got array");
  j["tools"] = {{"one", {{"type", "sphere"}, {"radius", 1}}}};
  expect_error(j, "tools.one: expected a tool number (an integer >= 0), got string \"one\"");
  j["tools"] = {{"-1", {{"type", "sphere"}, {"radius", 1}}}};
  expect_error(j, "tools.-1: expected a tool number");
  j["tools"] = {{"1", 3}};
  expect_error(j, "tools.1: expected an object, got number 3");
  j["tools"] = {{"1", {{"radius", 1}}}};
  expect_error(j, "tools.1: missing required key 'type'");
  j["tools"] = {{"1", {{"type", "drill"}, {"radius", 1}}}};
  expect_error(
      j,
      "tools.1.type: unknown tool type 'drill' (expected sphere, ball/ballend, flat, bullnose, vbit/conical, "
      "tapered/snubnose, tapered_ball, spheroid or apt)");
  j["tools"] = {{"1", {{"type", "sphere"}}}};
  expect_error(j, "tools.1: missing required key 'diameter' (or 'radius')");
  j["tools"] = {{"1", {{"type", "sphere"}, {"radius", -3}}}};
  expect_error(j, "tools.1.radius: must be greater than 0, got -3");
  j["tools"] = {{"1", {{"type", "ballend"}, {"radius", 3}}}};
  expect_error(j, "tools.1: missing required key 'length'");
  j["tools"] = {{"1", {{"type", "ballend"}, {"radius", 3}, {"length", 0}}}};
  expect_error(j, "tools.1.length: must be greater than 0");
  j["tools"] = {{"1", {{"type", "bullnose"}, {"radius", 3}, {"length", 10}}}};
  expect_error(j, "tools.1: missing required key 'corner_radius'");
  j["tools"] = {{"1", {{"type", "bullnose"}, {"radius", 3}, {"length", 10}, {"corner_radius", 4}}}};
  expect_error(j, "tools.1.corner_radius: must not exceed the radius 3");
  j["tools"] = {{"1", {{"type", "conical"}, {"radius", 3}, {"length", 10}, {"angle", 180}}}};
  expect_error(j, "tools.1.angle: must be an included angle between 0 and 180 degrees (exclusive), got 180");
  j["tools"] = {
      {"1", {{"type", "conical"}, {"radius", 3}, {"length", 10}, {"angle", 90}, {"tip_radius", 3}}}};
  expect_error(j, "tools.1.tip_radius: must be less than the radius 3, got 3");
  j["tools"] = {{"1", {{"type", "sphere"}, {"radius", 1}, {"description", 7}}}};
  expect_error(j, "tools.1.description: expected a string");
}

TEST_F(JobIo, PathErrors) {
  json j = minimal();
  j["paths"] = json::object();
  expect_error(j, "paths: expected an array of paths, got object");
  j["paths"] = json::array();
  expect_error(j, "paths: is empty; a job needs at least one path");
  j["paths"] = {7};
  expect_error(j, "paths[0]: expected an object, got number 7");
  j["paths"] = json::parse(R"([{"tool": 7, "polyline": [[0,0,0],[1,0,0]]}])");
  expect_error(j, "paths[0].tool: tool 7 is not defined in 'tools' (defined: 1)");
  j["paths"] = json::parse(R"([{"tool": 1.5, "polyline": [[0,0,0],[1,0,0]]}])");
  expect_error(j, "paths[0].tool: expected a tool number (an integer >= 0), got number 1.5");
  j["tools"]["2"] = {{"type", "sphere"}, {"radius", 2}};
  j["paths"] = json::parse(R"([{"polyline": [[0,0,0],[1,0,0]]}])");
  expect_error(j,
               "paths[0]: missing required key 'tool' (it may be left out only when the job defines exactly "
               "one tool)");
  j = minimal();
  j["paths"] = json::parse(R"([{"tool": 1, "polyline": [[0,0,0],[1,0,0]]}, {"tool": 1}])");
  expect_error(j, "paths[1]: needs a 'polyline' or a 'gcode' key");
  j["paths"][1] = json::parse(R"({"tool": 1, "polyline": [[0,0,0],[1,0,0]], "gcode": "a.nc"})");
  expect_error(j, "paths[1]: has both 'polyline' and 'gcode'");
  j["paths"][1] = json::parse(R"({"tool": 1, "polyline": []})");
  expect_error(j, "paths[1].polyline: is empty; a polyline needs at least 2 points");
  j["paths"][1] = json::parse(R"({"tool": 1, "polyline": [[0,0,0]]})");
  expect_error(j, "paths[1].polyline: has 1 point");
  j["paths"][1] = json::parse(R"({"tool": 1, "polyline": {"a": 1}})");
  expect_error(j, "paths[1].polyline: expected an array of points");
  j["paths"][1] = json::parse(R"({"tool": 1, "polyline": [[0,0,0],[1,"a",3]]})");
  expect_error(j, "paths[1].polyline[1]: expected 3 numbers, got array [1,\"a\",3]");
  j["paths"][1] = json::parse(R"({"tool": 1, "polyline": [[0,0,0],[1,0,0,0]]})");
  expect_error(j, "paths[1].polyline[1]: expected 3 numbers");
  j["paths"][1] = json::parse(R"({"tool": 1, "feed": -5, "polyline": [[0,0,0],[1,0,0]]})");
  expect_error(j, "paths[1].feed: must be greater than 0, got -5");
  j["paths"][1] = json::parse(R"({"tool": 1, "name": 3, "polyline": [[0,0,0],[1,0,0]]})");
  expect_error(j, "paths[1].name: expected a string");
}

TEST_F(JobIo, GcodePathErrors) {
  json j = minimal();
  j["paths"] = json::parse(R"([{"tool": 1, "gcode": "nothere.nc"}])");
  expect_error(
      j, "paths[0].gcode: G-code file 'nothere.nc' not found (looked for '" + path("nothere.nc") + "')");
  j["paths"][0]["gcode"] = 12;
  expect_error(j, "paths[0].gcode: expected a string, got number 12");
  j["paths"][0]["gcode"] = "";
  expect_error(j, "paths[0].gcode: empty G-code file name");
  write_text("bad.nc", "G21 G90 F100\nG1 X0 Y0 Z0\nG1 X\n");
  j["paths"][0]["gcode"] = "bad.nc";
  expect_error(j, "paths[0].gcode: " + path("bad.nc") + ":3: ");  // the G-code file and line
  write_text("t5.nc", "G21 G90 F100\nG1 X0 Y0 Z0\nT5 M6\nG1 X1\n");
  j["paths"][0]["gcode"] = "t5.nc";
  expect_error(
      j, "paths[0].gcode: 't5.nc' selects tool 5 (T5 M6), which is not defined in 'tools' (defined: 1)");
  j["paths"][0] = json::parse(R"({"tool": 1, "gcode": "t5.nc", "start": [0, 0]})");
  expect_error(j, "paths[0].start: expected 3 numbers");
  fs::create_directories(dir_ / "folder.nc");
  j["paths"][0] = json::parse(R"({"tool": 1, "gcode": "folder.nc"})");
  expect_error(j, "paths[0].gcode: G-code file 'folder.nc' is a directory");
}

TEST_F(JobIo, FileErrors) {
  try {
    morphmill::load_job(path("absent.json"));
    FAIL() << "no error";
  } catch (const morph::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(path("absent.json")), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("No such file"), std::string::npos) << e.what();
  }
  const std::string bad = write_text("bad.json", "{\n  \"stock\": {\"type\": \"box\",,\n}\n");
  try {
    morphmill::load_job(bad);
    FAIL() << "no error";
  } catch (const morph::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(bad + ":2:", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("invalid JSON"), std::string::npos) << e.what();
  }
  // Paths in a loaded job resolve next to the job file, wherever the process runs.
  write_text("p.nc", "G21 G90 F100\nG1 X0 Y0 Z0\nG1 X1\n");
  json j = minimal();
  j["paths"] = json::parse(R"([{"tool": 1, "gcode": "p.nc"}])");
  const std::string file = write_text("rel.json", j.dump());
  EXPECT_EQ(morphmill::load_job(file).paths[0].moves.size(), 1u);
}

}  // namespace
