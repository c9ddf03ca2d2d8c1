// SPDX-License-Identifier: Apache-2.0
// `morphmill erode` and `mesh-info` on what makes a surface a solid: closed, oriented, 2-manifold
// and free of self-intersections, or exit 1 and no file (unless --allow-open).
#include <gtest/gtest.h>
#include <morphmill/mesh_io.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <regex>

#include "apps/command_support.h"
#include "common/test_meshes.h"

namespace {

namespace fs = std::filesystem;
using morphmill_test::run_command;
const std::string kData = MORPHMILL_TEST_DATA;

class CliErode : public morphmill_test::ScratchDirTest {
 protected:
  morphmill_test::CommandResult morphmill(const std::string& arguments) const {
    return run_command(std::string("'") + MORPHMILL_BINARY + "' " + arguments);
  }
};

TEST_F(CliErode, MeshInfoReportsCrossingShellsAndEachPiecesGenus) {
  morph::TriangleMesh mesh = morphmill_test::box({0, 0, 0}, {1, 1, 1});
  mesh.append(morphmill_test::box({0.5, 0.5, 0.5}, {1.5, 1.5, 1.5}));
  mesh.append(morphmill_test::torus(3.0, 1.0, 24, 8));
  for (std::size_t v = 16; v < mesh.vertices.size(); ++v) mesh.vertices[v].x() += 10.0;
  morphmill::write_mesh(mesh, path("shells.ply"));
  const auto r = morphmill("mesh-info --json '" + path("shells.ply") + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const nlohmann::json report = nlohmann::json::parse(r.output);
  EXPECT_EQ(report["closed_manifold"], true);
  EXPECT_GT(report["self_intersecting_pairs"].get<int>(), 0);
  EXPECT_EQ(report["valid_solid"], false);
  ASSERT_EQ(report["pieces"].size(), 3u);
  EXPECT_EQ(report["pieces"][0]["genus"], 0);
  EXPECT_EQ(report["pieces"][1]["genus"], 0);
  EXPECT_EQ(report["pieces"][2]["genus"], 1);
  for (const auto& pair : report["first_self_intersecting_pairs"]) {
    EXPECT_LT(pair[0].get<int>(), 12);  // one face of each cube
    EXPECT_GE(pair[1].get<int>(), 12);
    EXPECT_LT(pair[1].get<int>(), 24);
  }
  const auto table = morphmill("mesh-info '" + path("shells.ply") + "'");
  EXPECT_NE(table.output.find("valid solid             no"), std::string::npos) << table.output;
  EXPECT_NE(table.output.find("#3: 384 triangles, closed, genus 1"), std::string::npos) << table.output;
}

TEST_F(CliErode, ASoundSurfaceIsWrittenWithExitZero) {
  const auto r = morphmill("erode '" + kData + "/jobs/single_slot.json' -o '" + path("slot.ply") + "'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("closed manifold: yes, self-intersections: 0 pairs"), std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::exists(path("slot.ply")));
}

// Whatever the generator gives on the demo job, the exit code and the file follow what the
// summary says of the surface.
TEST_F(CliErode, TheExitCodeAndTheFileFollowTheSurfacesSoundness) {
  const std::string job = "'" + kData + "/jobs/through_slots.json'";
  const auto r = morphmill("erode " + job + " -o '" + path("part.ply") + "'");
  const std::regex summary("closed manifold: (yes|no).*self-intersections: ([0-9]+) pairs");
  std::smatch match;
  ASSERT_TRUE(std::regex_search(r.output, match, summary)) << r.output;
  const bool sound = match[1] == "yes" && match[2] == "0";
  EXPECT_EQ(r.exit_code, sound ? 0 : 1) << r.output;
  EXPECT_EQ(fs::exists(path("part.ply")), sound);
  if (!sound) {
    EXPECT_NE(r.output.find("--allow-open writes it anyway"), std::string::npos) << r.output;
    const auto forced = morphmill("erode " + job + " -o '" + path("part.ply") + "' --allow-open");
    EXPECT_EQ(forced.exit_code, 1) << forced.output;
    EXPECT_TRUE(fs::exists(path("part.ply")));
  }
}

}  // namespace

namespace {

// The output's place is checked before the long work, so a bad one is bad input (exit 2) even
// when the surface would not have been written.
TEST_F(CliErode, AnOutputThatCannotBeWrittenIsRefusedUpFront) {
  std::filesystem::create_directory(path("dir.ply"));
  for (const std::string& out :
       {std::string("/nonexistent/x.ply"), path("dir.ply"), std::string("/proc/x.ply")}) {
    const auto r = morphmill("erode '" + kData + "/jobs/through_slots.json' -o '" + out + "'");
    EXPECT_EQ(r.exit_code, 2) << out << ": " << r.output;
    EXPECT_NE(r.output.find("cannot write"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("patches kept"), std::string::npos) << "refused only after eroding: " << r.output;
  }
}

}  // namespace
