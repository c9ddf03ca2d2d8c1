// SPDX-License-Identifier: Apache-2.0
// `morphmill study` per tool shape: the OpenVDB reference converges to the exact surface (first
// order in the voxel size at least) for every tool of revolution, and the generator is measured
// on every shape beside it. The small case runs by default; the bundled study over every shape
// (data/studies/tool_shapes.json) is `slow`.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "apps/command_support.h"
#include "campaigns/study.h"

namespace {

namespace fs = std::filesystem;
const std::string kData = MORPHMILL_TEST_DATA;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

morphmill::study::StudyResult run_study_file(const nlohmann::json& study, const fs::path& dir) {
  std::ofstream(dir / "study.json") << study.dump(2);
  morphmill::study::StudyOptions options;
  options.study_path = (dir / "study.json").string();
  options.out_dir = (dir / "out").string();
  return morphmill::study::run_study(options);
}

const morphmill::study::StudyResult::Convergence* fit_of(const morphmill::study::StudyResult& result,
                                                         const std::string& job, const std::string& measure) {
  for (const auto& c : result.convergence)
    if (c.job == job && c.measure == measure) return &c;
  return nullptr;
}

// A V-bit (a sharp tip the level set rounds) over three voxel sizes: the reference converges at
// first order, and the generator, the same surface at every voxel, stays within its tolerance.
TEST(StudyShapes, AVBitConvergesAtFirstOrderAndTheGeneratorIsMeasured) {
  const fs::path dir = morphmill_test::scratch_dir("study_shapes", "vbit");
  const nlohmann::json study = {
      {"name", "vbit"},
      {"jobs", {kData + "/jobs/tool_vbit.json"}},
      {"sweep", {{"voxel_size", {1.0, 0.7, 0.5}}, {"voxel_size_relative_to_tool_radius", false}}},
      {"samples", 3000},
      {"heatmaps", false}};
  const auto result = run_study_file(study, dir);
  ASSERT_TRUE(result.complete());
  ASSERT_EQ(result.rows.size(), 3u);
  for (const auto& row : result.rows) {
    EXPECT_EQ(row.error, "");
    EXPECT_EQ(row.tools, "T1 conical diameter 6, angle 90 deg, length 20");
    EXPECT_EQ(row.generator_skipped, "");
    EXPECT_TRUE(row.verdict) << "at voxel " << row.voxel_size;
    EXPECT_GT(row.reference_max_error, 0.0);
    EXPECT_GT(row.generator_max_error, 0.0);
    EXPECT_LE(row.generator_max_error, row.tolerance);
    EXPECT_EQ(row.generator_triangles, result.rows[0].generator_triangles);  // the voxel is the reference's
    EXPECT_EQ(row.generator_pieces, 1u);
  }
  EXPECT_LT(result.rows[2].reference_max_error, result.rows[0].reference_max_error);
  const auto* max = fit_of(result, "tool_vbit", "max");
  ASSERT_NE(max, nullptr);
  EXPECT_GE(max->fit.order, 0.9) << "first order at least";
  EXPECT_EQ(max->tools, "T1 conical diameter 6, angle 90 deg, length 20");

  const auto json = nlohmann::json::parse(slurp(dir / "out" / "study.json"));
  for (const auto& row : json["rows"]) {
    EXPECT_LE(row["generator"]["max_error"].get<double>(), row["tolerance"].get<double>()) << row.dump();
    EXPECT_GT(row["agreement"].get<double>(), 0.0) << row.dump();
  }
  EXPECT_EQ(json["convergence"][0]["tools"], "T1 conical diameter 6, angle 90 deg, length 20");
  std::istringstream csv(slurp(dir / "out" / "study.csv"));
  std::string header, line;
  std::getline(csv, header);
  std::getline(csv, line);
  EXPECT_NE(header.find(",tools,generator_skipped"), std::string::npos);
  // tool_vbit,voxel_size,1,tolerance,voxel,radius,step-over, then the seven generator fields, filled.
  EXPECT_EQ(line.find(",,,,,,,,"), std::string::npos) << line;
  const std::string html = slurp(dir / "out" / "report.html");
  EXPECT_EQ(html.find("<td>not run</td>"), std::string::npos);
}

// The bundled study: every shape of data/jobs/tool_*.json over five voxel sizes (0.8 .. 0.2 mm).
TEST(SlowStudyShapes, EveryToolShapeConvergesAtFirstOrderAtLeast) {
  const fs::path dir = morphmill_test::scratch_dir("study_shapes", "all");
  nlohmann::json study = nlohmann::json::parse(slurp(kData + "/studies/tool_shapes.json"));
  for (auto& job : study["jobs"]) job = kData + "/studies/" + job.get<std::string>();
  study["heatmaps"] = false;
  const auto result = run_study_file(study, dir);
  ASSERT_TRUE(result.complete());
  std::map<std::string, int> shapes;
  for (const auto& row : result.rows) {
    EXPECT_EQ(row.error, "") << row.job;
    EXPECT_TRUE(row.verdict) << row.job << " at voxel " << row.voxel_size;
    ++shapes[row.job];
  }
  EXPECT_EQ(shapes.size(), 9u);
  for (const auto& [job, rows] : shapes) {
    EXPECT_EQ(rows, 5) << job;
    const auto* max = fit_of(result, job, "max");
    const auto* mean = fit_of(result, job, "mean");
    ASSERT_NE(max, nullptr) << job;
    ASSERT_NE(mean, nullptr) << job;
    EXPECT_GE(max->fit.order, 0.9) << job << " (" << max->tools << ")";
    EXPECT_GE(mean->fit.order, 0.9) << job << " (" << mean->tools << ")";
    EXPECT_GE(max->fit.r_squared, 0.9) << job;
  }
}

}  // namespace
