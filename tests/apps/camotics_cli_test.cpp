// SPDX-License-Identifier: Apache-2.0
// The CAMotics projects from the command line, as a machinist runs them: by default generator 2
// builds the tools generator 1 cannot; with --generator 1 `erode` says which move
// and tool generator 1 cannot build (exit 2), `verify` still checks the reference against
// the exact surface and its exit code tells the truth (1 "NOT VERIFIED" unless --reference-only),
// and the report names every tool with its shape and sizes, the programs with the tools their
// moves used and the G-code reader's warnings. The full projects at their automatic voxel are the
// `slow` tests at the end (docs/camotics.md has their figures).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "apps/command_support.h"

namespace {

namespace fs = std::filesystem;
using morphmill_test::run_command;
const std::string kData = MORPHMILL_TEST_DATA;

std::string project(const std::string& name) {
  return kData + "/camotics/" + name + "/" + name + ".camotics";
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

class CamoticsCli : public morphmill_test::ScratchDirTest {
 protected:
  morphmill_test::CommandResult morphmill(const std::string& arguments) const {
    return run_command(std::string("'") + MORPHMILL_BINARY + "' " + arguments);
  }
};

constexpr const char* kSlantTool =
    "tool 1 (tapered diameter 4, tip diameter 2, taper 10.3048 deg/side, length 5.5)";

TEST_F(CamoticsCli, ErodeNamesTheMoveAndTheToolItCannotBuild) {
  const auto r =
      morphmill("erode '" + project("slant_test") + "' -o '" + path("slant.ply") + "' --generator 1");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("the move at line 3 of " + kData + "/camotics/slant_test/slant_test.nc uses " +
                          kSlantTool + ", which generator 1 cannot build"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("generator 2, the default, builds every tool of revolution"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(path("slant.ply")));
}

// Under --generator auto the tapered tool goes to generator 2, and erode says so; its exit code is
// the soundness of what it built.
TEST_F(CamoticsCli, ErodeHandsATaperedToolToGeneratorTwo) {
  const auto r = morphmill("erode '" + project("slant_test") + "' -o '" + path("slant.ply") + "' --json '" +
                           path("slant.json") + "' -q --generator auto");
  const nlohmann::json json = nlohmann::json::parse(slurp(path("slant.json")));
  EXPECT_EQ(json["generator"], 2) << r.output;
  EXPECT_EQ(json["generator_asked"], "auto");
  EXPECT_NE(json["generator_choice"].get<std::string>().find(
                "generator 1 builds spheres and ball ends only, and the move at line 3 of " + kData +
                "/camotics/slant_test/slant_test.nc uses " + kSlantTool),
            std::string::npos)
      << json.dump();
  const bool sound = json["closed_manifold"].get<bool>() && json["self_intersecting_pairs"].get<int>() == 0;
  EXPECT_EQ(r.exit_code, sound ? 0 : 1) << r.output;
  EXPECT_EQ(fs::exists(path("slant.ply")), sound);
  EXPECT_GT(json["triangles"].get<int>(), 1000);
  EXPECT_EQ(json["pieces"], 1);
}

TEST_F(CamoticsCli, VerifyChecksTheReferenceAndSaysTheGeneratorWasNotRun) {
  const auto r = morphmill("verify '" + project("slant_test") + "' --output '" + path("slant") +
                           "' --voxel 0.5 --samples 2000 --generator 1");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("verdict NOT VERIFIED"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("generator: not run (the move at line 3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find(kSlantTool), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("reference against the exact surface: yes"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("slant/morph.ply")));
  EXPECT_TRUE(fs::exists(path("slant/reference_vs_exact.png")));

  const nlohmann::json json = nlohmann::json::parse(slurp(path("slant/deviation.json")));
  EXPECT_EQ(json["verdict"]["holds"], false);
  EXPECT_EQ(json["reference_check"]["converges"], true);
  EXPECT_EQ(json["reference_check"]["reference_only_requested"], false);
  EXPECT_LE(json["reference_check"]["resolvable_max"].get<double>(),
            json["reference_check"]["bound"].get<double>());
  EXPECT_NEAR(json["reference_check"]["bound"].get<double>(), std::sqrt(3.0) * 0.5, 1e-12);
  // What was not run is null, not a zero that reads as a perfect generator.
  EXPECT_TRUE(json["deviation"]["generator_to_exact"].is_null());
  EXPECT_TRUE(json["triangles"]["generator"].is_null());
  EXPECT_GT(json["deviation"]["reference_to_exact"]["count"].get<int>(), 1000);
  ASSERT_EQ(json["tools"].size(), 1u);
  EXPECT_EQ(json["tools"][0]["type"], "tapered");
  EXPECT_EQ(json["tools"][0]["generator_builds"], false);

  const std::string report = slurp(path("slant/report.md"));
  EXPECT_NE(report.find("**Verdict: NOT VERIFIED (generator not run: the move at line 3"), std::string::npos);
  EXPECT_NE(
      report.find("| T1 | tapered diameter 4, tip diameter 2, taper 10.3048 deg/side, length 5.5 | 17 |"),
      std::string::npos)
      << report;
  EXPECT_NE(report.find("| triangles | not run |"), std::string::npos) << report;
  EXPECT_EQ(report.find("generator -> exact"), std::string::npos) << report;
  EXPECT_NE(report.find("| reference -> exact |"), std::string::npos) << report;
  EXPECT_NE(report.find("| 1 | T3 is selected but never put in the spindle (no M6 follows) |"),
            std::string::npos)
      << report;
}

TEST_F(CamoticsCli, ReferenceOnlyIsAskedForAndThenHolds) {
  const auto r = morphmill("verify '" + project("slant_test") + "' --output '" + path("slant") +
                           "' --voxel 0.5 --samples 2000 --reference-only");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("verdict HOLDS"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("exit 1"), std::string::npos) << r.output;
  const nlohmann::json json = nlohmann::json::parse(slurp(path("slant/deviation.json")));
  EXPECT_EQ(json["verdict"]["holds"], true);
  EXPECT_EQ(json["reference_check"]["reference_only_requested"], true);
}

// heart: two programs on one stock, both cut with the T1 ball nose (cutout.ngc's bare T2 only
// prepares a tool); the report shows both, the tools their moves used and the warning.
TEST_F(CamoticsCli, HeartReportShowsBothProgramsTheirToolsAndTheBareT2) {
  const auto r = morphmill("verify '" + project("heart") + "' --output '" + path("heart") +
                           "' --voxel 2 --samples 500 --reference-only");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("cutout.ngc:7: T2 is selected but never put in the spindle"), std::string::npos)
      << r.output;
  const std::string report = slurp(path("heart/report.md"));
  EXPECT_NE(report.find("| T1 | ballend diameter 2.54, length 15.875 above the ball's centre | 218 |"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| T2 | flat diameter 1.5875, length 25.4 | 0 |"), std::string::npos) << report;
  EXPECT_NE(report.find("| 1 | heart.ngc | 164 | T1 (164) |"), std::string::npos) << report;
  EXPECT_NE(report.find("| 2 | cutout.ngc | 54 | T1 (54) |"), std::string::npos) << report;
  EXPECT_NE(report.find("cutout.ngc | 7 | T2 is selected but never put in the spindle (no M6 follows) |"),
            std::string::npos)
      << report;
}

}  // namespace
