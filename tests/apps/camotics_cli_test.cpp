// SPDX-License-Identifier: Apache-2.0
// The CAMotics projects from the command line, as a machinist runs them: the generator builds
// their flat, conical, tapered and snub-nose tools; `verify --reference-only` checks the
// reference against the exact surface alone and says the generator was not run; and the report names every
// tool with its shape and sizes, the programs with the tools their moves used and the G-code reader's
// warnings. The full projects at their automatic voxel are the `slow` tests at the end (docs/camotics.md has
// their figures).
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

// The tapered tool is built like any other; erode's exit code is the soundness of what it built.
TEST_F(CamoticsCli, ErodeBuildsATaperedTool) {
  const auto r = morphmill("erode '" + project("slant_test") + "' -o '" + path("slant.ply") + "' --json '" +
                           path("slant.json") + "' -q");
  const nlohmann::json json = nlohmann::json::parse(slurp(path("slant.json")));
  const bool sound = json["closed_manifold"].get<bool>() && json["self_intersecting_pairs"].get<int>() == 0;
  EXPECT_TRUE(sound) << json.dump();
  EXPECT_EQ(r.exit_code, sound ? 0 : 1) << r.output;
  EXPECT_EQ(fs::exists(path("slant.ply")), sound);
  EXPECT_GT(json["triangles"].get<int>(), 1000);
  EXPECT_EQ(json["pieces"], 1);
}

// --reference-only: the reference against the exact surface, and the report says the generator
// was not run (nulls, not zeros that read as a perfect generator).
TEST_F(CamoticsCli, VerifyChecksTheReferenceAloneAndSaysTheGeneratorWasNotRun) {
  const auto r = morphmill("verify '" + project("slant_test") + "' --output '" + path("slant") +
                           "' --voxel 0.5 --samples 2000 --reference-only");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("verdict HOLDS"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("generator: not run (--reference-only was given)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("reference against the exact surface: yes"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(path("slant/morph.ply")));
  EXPECT_TRUE(fs::exists(path("slant/reference_vs_exact.png")));

  const nlohmann::json json = nlohmann::json::parse(slurp(path("slant/deviation.json")));
  EXPECT_EQ(json["verdict"]["holds"], true);
  EXPECT_EQ(json["reference_check"]["converges"], true);
  EXPECT_EQ(json["reference_check"]["reference_only_requested"], true);
  EXPECT_LE(json["reference_check"]["resolvable_max"].get<double>(),
            json["reference_check"]["bound"].get<double>());
  EXPECT_NEAR(json["reference_check"]["bound"].get<double>(), std::sqrt(3.0) * 0.5, 1e-12);
  EXPECT_TRUE(json["deviation"]["generator_to_exact"].is_null());
  EXPECT_TRUE(json["triangles"]["generator"].is_null());
  EXPECT_GT(json["deviation"]["reference_to_exact"]["count"].get<int>(), 1000);
  ASSERT_EQ(json["tools"].size(), 1u);
  EXPECT_EQ(json["tools"][0]["type"], "tapered");

  const std::string report = slurp(path("slant/report.md"));
  EXPECT_NE(report.find("**Verdict: HOLDS for the reference alone (generator not run: --reference-only was "
                        "given; reference against the exact surface holds)**"),
            std::string::npos)
      << report;
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
