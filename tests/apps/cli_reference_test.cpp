// SPDX-License-Identifier: Apache-2.0
// `morphmill reference --json`: the summary carries the common keys of docs/summary-schema.md
// (format, format_version, provenance, units) like verify's, compare's and deviation's, and its
// figures match the closed form of the job.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "apps/command_support.h"

namespace {

using morphmill_test::run_command;
const std::string kData = MORPHMILL_TEST_DATA;

class CliReference : public morphmill_test::ScratchDirTest {};

TEST_F(CliReference, JsonSummaryCarriesProvenanceAndTheClosedFormVolume) {
  const std::string job = kData + "/jobs/single_slot.json";
  const auto r = run_command(std::string("'") + MORPHMILL_BINARY + "' reference '" + job +
                             "' --voxel 0.25 -o '" + path("ref.ply") + "' --json '" + path("ref.json") + "'");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(path("ref.json"));
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["format"], "morphmill-reference");
  EXPECT_EQ(summary["format_version"], 1);
  EXPECT_EQ(summary["units"], "mm");
  const nlohmann::json& provenance = summary["provenance"];
  EXPECT_EQ(provenance["program"], "morphmill");
  EXPECT_FALSE(provenance["version"].get<std::string>().empty());
  EXPECT_NE(provenance["command_line"].get<std::string>().find("--voxel 0.25"), std::string::npos);
  EXPECT_EQ(provenance["units"], "mm");
  EXPECT_EQ(provenance["options"]["command"], "reference");
  EXPECT_DOUBLE_EQ(provenance["options"]["voxel"].get<double>(), 0.25);
  ASSERT_EQ(provenance["inputs"].size(), 1u);
  EXPECT_EQ(provenance["inputs"][0]["sha256"], run_command("sha256sum '" + job + "'").output.substr(0, 64));
  EXPECT_EQ(provenance["inputs"][0]["bytes"], std::filesystem::file_size(job));
  // A 40 x 20 x 10 block less a radius-2 ball-end slot along x, its tip at z = 8 (the ball's centre
  // on the top face): per unit length the slot removes a half disc, 2 pi.
  const double exact_volume = 40.0 * 20.0 * 10.0 - 40.0 * 2.0 * M_PI;
  EXPECT_NEAR(summary["volume"].get<double>(), exact_volume, 0.005 * exact_volume);
  EXPECT_DOUBLE_EQ(summary["voxel_size"].get<double>(), 0.25);
  EXPECT_EQ(summary["outputs"]["mesh"], path("ref.ply"));
}

}  // namespace
