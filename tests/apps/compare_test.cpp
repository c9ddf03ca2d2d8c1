// SPDX-License-Identifier: Apache-2.0
// `morphmill compare` on the bundled design_gouge_excess job: a slot program with a plunge 0.8 mm
// too deep at X30 (G-code line 8, back up on line 9) and an end 0.3 mm short of the design's X50
// (line 10, retract on line 11), against the
// design it was written for (data/meshes/design_gouge_excess.stl, the generator's surface of
// design_gouge_excess_intended.json). Expected places, depths and areas are closed forms.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <nlohmann/json.hpp>

#include "apps/command_support.h"

namespace fs = std::filesystem;

namespace {

const std::string kBinary = MORPHMILL_BINARY;
const std::string kData = MORPHMILL_TEST_DATA;

nlohmann::json read_json(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

Eigen::Vector3d vec(const nlohmann::json& a) {
  return {a[0].get<double>(), a[1].get<double>(), a[2].get<double>()};
}

bool lines_include(const nlohmann::json& made_by, int line) {
  for (const auto& s : made_by)
    if (s["line"].get<int>() == line) return true;
  return false;
}

// Area of the plunge's dent out of the band: the lower half of the ball (radius 3, centre
// (30, 12, 17.2)) where it lies deeper than 0.02 below the slot's cylinder (axis y = 12, z = 18,
// radius 3), by quadrature over the sphere.
double gouge_area_closed_form(double band) {
  const int n = 1200;
  double area = 0;
  for (int i = 0; i < n; ++i) {
    const double theta = M_PI / 2 + (i + 0.5) * (M_PI / 2) / n;  // polar angle from +z: lower half
    for (int j = 0; j < 2 * n; ++j) {
      const double phi = (j + 0.5) * M_PI / n;
      const double y = 3 * std::sin(theta) * std::sin(phi), z = 3 * std::cos(theta) - 0.8;
      if (std::hypot(y, z) - 3 > band) area += 9 * std::sin(theta) * (M_PI / 2 / n) * (M_PI / n);
    }
  }
  return area;
}

class CompareGougeExcess : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    out_ = new fs::path(morphmill_test::scratch_dir("compare_test", "gouge_excess"));
    result_ = new morphmill_test::CommandResult(morphmill_test::run_command(
        kBinary + " compare " + kData + "/jobs/design_gouge_excess.json --out " + out_->string()));
  }
  static void TearDownTestSuite() {
    delete out_;
    delete result_;
  }
  static fs::path* out_;
  static morphmill_test::CommandResult* result_;
};
fs::path* CompareGougeExcess::out_ = nullptr;
morphmill_test::CommandResult* CompareGougeExcess::result_ = nullptr;

TEST_F(CompareGougeExcess, ExitsWithOneAndStatesTheSign) {
  EXPECT_EQ(result_->exit_code, 1) << result_->output;
  EXPECT_NE(result_->output.find("+ excess"), std::string::npos) << result_->output;
  EXPECT_NE(result_->output.find("OUT OF THE BAND"), std::string::npos);
  const auto j = read_json(*out_ / "compare.json");
  EXPECT_NE(j["sign_convention"].get<std::string>().find("- gouge"), std::string::npos);
  EXPECT_EQ(j["band"]["low"].get<double>(), -0.02);
  EXPECT_EQ(j["band"]["high"].get<double>(), 0.1);
  EXPECT_TRUE(fs::exists(*out_ / "machined_vs_design.ply"));
}

TEST_F(CompareGougeExcess, OneGougeWhereThePlungeWentTooDeep) {
  const auto j = read_json(*out_ / "compare.json");
  ASSERT_EQ(j["region_counts"]["gouge"].get<int>(), 1) << j.dump(1);
  for (const auto& r : j["regions"]) {
    if (r["kind"] != "gouge") continue;
    EXPECT_NEAR(r["worst"].get<double>(), -0.8, 0.015);
    EXPECT_LT((vec(r["location"]) - Eigen::Vector3d(30, 12, 14.2)).norm(), 0.3) << r.dump();
    const double expected = gouge_area_closed_form(0.02);
    EXPECT_NEAR(r["area"].get<double>(), expected, 0.1 * expected) << r.dump();
    EXPECT_TRUE(lines_include(r["made_by"], 8) || lines_include(r["made_by"], 9)) << r.dump();
    const int nearest = r["nearest_move"]["line"].get<int>();
    EXPECT_TRUE(nearest == 8 || nearest == 9) << r.dump();
  }
}

TEST_F(CompareGougeExcess, OneExcessWhereThePassStoppedShort) {
  const auto j = read_json(*out_ / "compare.json");
  ASSERT_EQ(j["region_counts"]["excess"].get<int>(), 1) << j.dump(1);
  for (const auto& r : j["regions"]) {
    if (r["kind"] != "excess") continue;
    EXPECT_NEAR(r["worst"].get<double>(), 0.3, 0.015);
    // The far side of the end wall: x = 49.7 + 3, on the slot's axis, between the floor and the top.
    const Eigen::Vector3d at = vec(r["location"]);
    EXPECT_NEAR(at.x(), 52.7, 0.1) << r.dump();
    EXPECT_NEAR(at.y(), 12.0, 0.5) << r.dump();
    EXPECT_GE(at.z(), 15.0);
    EXPECT_LE(at.z(), 20.0);
    // Out of the band where 3 - |p - (50, 12, .)| > 0.1, i.e. cos(angle from +X) > 0.3778: 14.2 mm^2
    // of the shank's wall (height 2) and 17.6 mm^2 of the ball's lower half, plus a sliver of the top face.
    EXPECT_GT(r["area"].get<double>(), 28.0) << r.dump();
    EXPECT_LT(r["area"].get<double>(), 36.0) << r.dump();
    // The end wall is swept by the move to X49.7 (line 10) and the retract from there (line 11).
    EXPECT_TRUE(lines_include(r["made_by"], 10) || lines_include(r["made_by"], 11)) << r.dump();
    const int nearest = r["nearest_move"]["line"].get<int>();
    EXPECT_TRUE(nearest == 10 || nearest == 11) << r.dump();
  }
}

TEST(Compare, TheIntendedProgramIsWithinTheBand) {
  const fs::path out = morphmill_test::scratch_dir("compare_test", "intended");
  const auto result = morphmill_test::run_command(
      kBinary + " compare " + kData + "/jobs/design_gouge_excess_intended.json --design " + kData +
      "/meshes/design_gouge_excess.stl --band -0.02,0.1 --out " + out.string());
  EXPECT_EQ(result.exit_code, 0) << result.output;
  const auto j = read_json(out / "compare.json");
  EXPECT_TRUE(j["within_band"].get<bool>());
  EXPECT_LT(j["per_point"]["max_abs"].get<double>(), 0.02);
}

TEST(Compare, BadBandAndMissingDesignExitWithTwo) {
  const auto bad_band = morphmill_test::run_command(kBinary + " compare " + kData +
                                                    "/jobs/design_gouge_excess.json --band 0.1,0.2");
  EXPECT_EQ(bad_band.exit_code, 2) << bad_band.output;
  EXPECT_NE(bad_band.output.find("--band"), std::string::npos) << bad_band.output;
  const auto no_design =
      morphmill_test::run_command(kBinary + " compare " + kData + "/jobs/single_slot.json");
  EXPECT_EQ(no_design.exit_code, 2) << no_design.output;
  EXPECT_NE(no_design.output.find("names no design"), std::string::npos) << no_design.output;
}

}  // namespace
