// SPDX-License-Identifier: Apache-2.0
// End-to-end checks of `morphmill verify`: the verdict and files on a job with a closed form, the
// report opened in a real browser (headless Chromium), and exit code 2 for broken input.
#include <gtest/gtest.h>

#include "apps/command_support.h"

#include <vdb_ref/reference.h>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

namespace fs = std::filesystem;

namespace {

using morphmill_test::CommandResult;
CommandResult run(const std::string& command) {
  return morphmill_test::run_command(command);
}

fs::path scratch(const std::string& name) {
  return morphmill_test::scratch_dir("verify_test", name);
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

const std::string kBinary = MORPHMILL_BINARY;
const std::string kData = MORPHMILL_TEST_DATA;

// One verify run shared by the tests below (it is the slow part).
class VerifySingleSlot : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    out_ = new fs::path(scratch("single_slot"));
    result_ = new CommandResult(run(kBinary + " verify " + kData + "/jobs/single_slot.json --out " +
                                    out_->string() + " --voxel 0.25 --samples 20000"));
  }
  static void TearDownTestSuite() {
    delete out_;
    delete result_;
  }
  static fs::path* out_;
  static CommandResult* result_;
};
fs::path* VerifySingleSlot::out_ = nullptr;
CommandResult* VerifySingleSlot::result_ = nullptr;

}  // namespace

TEST_F(VerifySingleSlot, VerdictHoldsAndEveryFileIsWritten) {
  EXPECT_EQ(result_->exit_code, 0) << result_->output;
  for (const char* file :
       {"morph.ply", "reference.ply", "reference.vdb", "deviation.json", "morph_vs_exact.ply",
        "morph_vs_reference.ply", "reference_vs_exact.ply", "morph_vs_exact.png", "report.md", "report.html"})
    EXPECT_TRUE(fs::exists(*out_ / file)) << file;
}

TEST_F(VerifySingleSlot, JsonMatchesTheClosedForm) {
  const auto json = nlohmann::json::parse(slurp(*out_ / "deviation.json"));
  // A 2 mm deep ball-end slot of radius 2 through a 40 mm long block: a half-disc cross-section.
  const double removed = 0.5 * M_PI * 2.0 * 2.0 * 40.0;
  const double expected = 40.0 * 20.0 * 10.0 - removed;
  ASSERT_EQ(json["pieces"]["generator"].size(), 1u);
  EXPECT_NEAR(json["pieces"]["generator"][0]["volume"].get<double>(), expected, 0.01 * 40 * 2 * M_PI);
  EXPECT_NEAR(json["pieces"]["reference"][0]["volume"].get<double>(), expected, 0.005 * expected);
  EXPECT_LE(json["deviation"]["generator_to_exact"]["max_abs"].get<double>(), 0.01);
  EXPECT_TRUE(json["verdict"]["holds"].get<bool>());
}

TEST_F(VerifySingleSlot, DeviationIsSignedWithBandsAndRegions) {
  const auto json = nlohmann::json::parse(slurp(*out_ / "deviation.json"));
  EXPECT_NE(json["sign_convention"].get<std::string>().find("- gouge"), std::string::npos);
  const auto& exact = json["deviation"]["generator_to_exact"];
  // Generator 2's tool polytope straddles the exact tool (its chords pushed out by half their
  // sagitta, tool_polytope.h), so the slot's facets lie on both sides of the exact surface: excess
  // (+) and gouge (-), each within the tolerance.
  EXPECT_GT(exact["max"].get<double>(), 1e-4);
  EXPECT_LE(exact["max"].get<double>(), 0.01);
  EXPECT_LT(exact["min"].get<double>(), -1e-4);
  EXPECT_GE(exact["min"].get<double>(), -0.01);
  // Seen from the exact surface, the same: exact points inside the generator's solid (-) and out.
  EXPECT_LT(json["deviation"]["exact_to_generator"]["min"].get<double>(), -1e-4);
  EXPECT_GT(json["deviation"]["exact_to_generator"]["max"].get<double>(), 1e-4);
  EXPECT_EQ(exact["band"]["low"].get<double>(), -0.01);
  EXPECT_DOUBLE_EQ(exact["share_within_band"].get<double>(), 1.0);
  std::size_t binned = exact["band_histogram"]["underflow"].get<std::size_t>() +
                       exact["band_histogram"]["overflow"].get<std::size_t>();
  for (const auto& c : exact["band_histogram"]["counts"]) binned += c.get<std::size_t>();
  EXPECT_EQ(binned, exact["count"].get<std::size_t>());
  // Within tolerance everywhere on the refined surface too: no region against the exact surface.
  EXPECT_EQ(json["regions"]["count"]["exact_surface"].get<int>(), 0) << json["regions"].dump(1);
  EXPECT_GT(json["regions"]["resolution"].get<double>(), 0.0);
}

TEST_F(VerifySingleSlot, EveryOutputCarriesProvenanceAndUnits) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  const std::string job = kData + "/jobs/single_slot.json";
  const std::string job_hash = run("sha256sum " + job).output.substr(0, 64);
  const auto json = nlohmann::json::parse(slurp(*out_ / "deviation.json"));
  EXPECT_EQ(json["format"], "morphmill-verify");
  EXPECT_EQ(json["units"], "mm");
  const auto& provenance = json["provenance"];
  ASSERT_GE(provenance["inputs"].size(), 1u);
  EXPECT_EQ(provenance["inputs"][0]["path"], job);
  EXPECT_EQ(provenance["inputs"][0]["sha256"], job_hash);
  EXPECT_EQ(provenance["options"]["voxel"].get<double>(), 0.25);
  EXPECT_NE(provenance["command_line"].get<std::string>().find("--samples 20000"), std::string::npos);
  EXPECT_FALSE(provenance["version"].get<std::string>().empty());
  for (const char* file : {"morph.ply", "reference.ply", "morph_vs_exact.ply", "reference_vs_exact.ply"}) {
    const std::string text = slurp(*out_ / file);
    const std::string header = text.substr(0, text.find("end_header"));
    EXPECT_NE(header.find("comment units: mm\n"), std::string::npos) << file;
    EXPECT_NE(header.find("sha256 " + job_hash), std::string::npos) << file;
  }
  EXPECT_NE(slurp(*out_ / "morph_vs_exact.ply").find("property double quality"), std::string::npos);
  const std::string vtp = slurp(*out_ / "morph_vs_exact.vtp");
  EXPECT_NE(vtp.find("<PointData Scalars=\"deviation_exact\">"), std::string::npos);
  EXPECT_NE(vtp.find("location=\"vtkDataArray\">mm</InformationKey>"), std::string::npos);
  const auto grids = vdb_ref::read_grid_metadata((*out_ / "reference.vdb").string());
  ASSERT_EQ(grids.size(), 1u);
  std::map<std::string, std::string> meta(grids[0].entries.begin(), grids[0].entries.end());
  EXPECT_EQ(meta["units"], "mm");
  EXPECT_EQ(meta["voxel_size"], "0.25");
  EXPECT_NE(meta["morphmill_provenance"].find(job_hash), std::string::npos);
  const std::string report = slurp(*out_ / "report.md");
  EXPECT_NE(report.find("### Provenance"), std::string::npos);
  EXPECT_NE(report.find(job_hash), std::string::npos);
}

TEST_F(VerifySingleSlot, ReportLoadsInAHeadlessBrowser) {
  const fs::path report = *out_ / "report.html";
  ASSERT_TRUE(fs::exists(report));
  const CommandResult browser =
      run("chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
          "--disable-background-networking "
          "--disable-component-update --disable-sync --user-data-dir=" +
          scratch("chromium_profile").string() + " --virtual-time-budget=10000 --dump-dom file://" +
          report.string());
  ASSERT_EQ(browser.exit_code, 0) << browser.output;
  // The page's own script counts the pictures the browser decoded.
  std::smatch match;
  ASSERT_TRUE(std::regex_search(browser.output, match, std::regex("data-images-loaded=\"(\\d+)/(\\d+)\"")))
      << browser.output.substr(0, 2000);
  EXPECT_EQ(match[1], match[2]);
  EXPECT_EQ(match[2], "8");  // plain views of both sides, iso/top/front/close-up against the exact
                             // surface, and the two other heatmaps
  for (const char* heading : {"Stages", "Pieces", "Signed deviation", "Histogram", "Worst moves",
                              "Regions out of the band", "Decisive place", "Verdict", "Provenance"})
    EXPECT_NE(browser.output.find(std::string("<h3>") + heading), std::string::npos) << heading;
  EXPECT_GE(std::count(browser.output.begin(), browser.output.end(), '<'), 100);
}

TEST_F(VerifySingleSlot, PicturesShowEveryViewAtTheResolutionAsked) {
  ASSERT_EQ(result_->exit_code, 0) << result_->output;
  for (const char* view : {"", "_top", "_front", "_closeup"}) {
    const fs::path png = *out_ / ("morph_vs_exact" + std::string(view) + ".png");
    ASSERT_TRUE(fs::exists(png)) << png;
    // PNG header: width and height, big-endian, at bytes 16..23.
    const std::string bytes = slurp(png).substr(0, 24);
    auto be32 = [&](std::size_t at) {
      return (unsigned(std::uint8_t(bytes[at])) << 24) | (unsigned(std::uint8_t(bytes[at + 1])) << 16) |
             (unsigned(std::uint8_t(bytes[at + 2])) << 8) | unsigned(std::uint8_t(bytes[at + 3]));
    };
    EXPECT_EQ(be32(16), 1200u) << png;
    EXPECT_EQ(be32(20), 900u) << png;
  }
}

// The bundled design job (docs/tutorial.md): a plunge 0.8 mm below the slot floor at (30, 12, 14.2),
// made by G-code line 8, against the design it was written for. Its report's 3D view shows the
// machined part against the design.
class VerifyDesignGouge : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    out_ = new fs::path(scratch("design_gouge_excess"));
    result_ = new CommandResult(run(kBinary + " verify " + kData + "/jobs/design_gouge_excess.json --out " +
                                    out_->string() + " --voxel 0.5 --samples 20000"));
  }
  static void TearDownTestSuite() {
    delete out_;
    delete result_;
  }
  static fs::path* out_;
  static CommandResult* result_;
};
fs::path* VerifyDesignGouge::out_ = nullptr;
CommandResult* VerifyDesignGouge::result_ = nullptr;

// The report loads nothing from the network: no element points at a remote address and no script
// fetches or imports one (three.js itself holds namespace strings such as "http://www.w3.org/...",
// which load nothing); the browser below has no network at all.
TEST_F(VerifyDesignGouge, ReportLoadsNothingFromTheNetwork) {
  ASSERT_EQ(result_->exit_code, 1) << result_->output;  // the design is out of the band
  const std::string page = slurp(*out_ / "report.html");
  for (const char* remote :
       {"src=\"http", "src='http", "href=\"http", "href='http", "<script src=", "<link rel=\"stylesheet\""})
    EXPECT_EQ(page.find(remote), std::string::npos) << remote;
  std::smatch loads;
  EXPECT_FALSE(
      std::regex_search(page, loads,
                        std::regex(R"((fetch|import|importScripts|url|open)\s*\(\s*(["'`])\s*(https?:)?//)",
                                   std::regex::icase)))
      << loads.str();
  EXPECT_NE(page.find("id=\"view3d-data\""), std::string::npos);
}

// In a real browser with no network, three.js (inlined) draws the part, and a click on the known
// gouge, its point projected to the canvas with the view's own camera looking down, reads -0.8 mm
// (a gouge), the plunge's move and G-code line; the pixel there is drawn in the map's gouge blue.
TEST_F(VerifyDesignGouge, ThreeDViewClickReadsTheKnownGouge) {
  ASSERT_EQ(result_->exit_code, 1) << result_->output;
  const fs::path report = *out_ / "report.html";
  const CommandResult browser =
      run("chromium --headless --no-sandbox --disable-gpu --enable-unsafe-swiftshader --disable-quic "
          "--no-first-run --disable-background-networking --disable-component-update --disable-sync "
          "--host-resolver-rules='MAP * ~NOTFOUND' --proxy-server=127.0.0.1:9 --user-data-dir=" +
          scratch("chromium_profile_3d").string() +
          " --window-size=1200,2400 --virtual-time-budget=20000 --dump-dom 'file://" + report.string() +
          "#click=30,12,14.2&from=0,0,1'");
  ASSERT_EQ(browser.exit_code, 0) << browser.output.substr(0, 2000);
  std::smatch ready;
  ASSERT_TRUE(std::regex_search(browser.output, ready,
                                std::regex("data-view3d=\"ready (\\d+) triangles, (\\d+) frames")))
      << browser.output.substr(0, 3000);
  EXPECT_GT(std::stoi(ready[1]), 1000);
  EXPECT_GE(std::stoi(ready[2]), 1);
  std::smatch click;
  ASSERT_TRUE(
      std::regex_search(browser.output, click,
                        std::regex("data-click=\"deviation ([-+0-9.e]+) move (-?\\d+) line (-?\\d+) at "
                                   "([-+0-9.e]+),([-+0-9.e]+),([-+0-9.e]+) pixel (\\d+),(\\d+),(\\d+)\"")))
      << browser.output.substr(0, 3000);
  // The ray hit the bottom of the plunge: the ball's tip at z = 17.2 - 3, on a facet of the
  // generator's surface (chordal error within the job's tolerance, 0.01 mm), within a pixel of the
  // point asked for (the whole 60 mm part in view: about 0.12 mm per pixel)...
  const double x = std::stod(click[4]), y = std::stod(click[5]), z = std::stod(click[6]);
  EXPECT_NEAR(x, 30.0, 0.12);
  EXPECT_NEAR(y, 12.0, 0.12);
  EXPECT_NEAR(z, 14.2, 0.02);
  // ...where the design's floor is the intended ball-end slot, a cylinder of radius 3 about
  // y = 12, z = 18 (its STL within the same tolerance): the part is 0.8 mm inside it, a gouge.
  const double deviation = std::stod(click[1]);
  EXPECT_NEAR(deviation, 3.0 - std::hypot(y - 12.0, z - 18.0), 0.011);
  EXPECT_NEAR(deviation, -0.8, 0.02);
  // The plunge (G1 Z14.2, move 2, line 8) and the retract over the same points (G1 Z15, move 3,
  // line 9) leave the same tip; the read-out names one of them, consistently.
  const int move = std::stoi(click[2]), line = std::stoi(click[3]);
  EXPECT_TRUE(line == 8 || line == 9) << line;
  EXPECT_EQ(move, line - 6);
  EXPECT_TRUE(
      std::regex_search(browser.output, std::regex("deviation -0\\.[78][0-9]* mm \\(gouge\\) at \\(")))
      << "the read-out shows the signed value, its unit and its class";
  EXPECT_NE(browser.output.find("made by move " + std::to_string(move) + " (G-code line " +
                                std::to_string(line) + ")"),
            std::string::npos);
  // -0.8 is beyond the colour range (+/-0.1 mm): the map's blue end, shaded; not the background.
  const int red = std::stoi(click[7]), green = std::stoi(click[8]), blue = std::stoi(click[9]);
  EXPECT_GT(blue, red + 40) << red << "," << green << "," << blue;
  EXPECT_GT(blue, green + 20) << red << "," << green << "," << blue;
}

TEST(VerifyBadInput, TruncatedGcodeAndMissingStockMeshExitWithTwo) {
  const fs::path dir = scratch("bad_input");
  {
    std::ofstream gcode(dir / "truncated.nc");
    gcode << "G21 G90\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10 (unterminated comment";
    std::ofstream job(dir / "truncated.json");
    job << R"({"name": "t", "units": "mm", "stock": {"type": "box", "min": [0,0,-5], "max": [20,20,0]},
              "tools": {"1": {"type": "ballend", "radius": 1, "length": 10}},
              "paths": [{"tool": 1, "gcode": "truncated.nc"}], "tolerance": 0.01})";
    std::ofstream missing(dir / "missing_mesh.json");
    missing << R"({"name": "m", "units": "mm", "stock": {"type": "mesh", "path": "nowhere.stl"},
                   "tools": {"1": {"type": "sphere", "radius": 1}},
                   "paths": [{"tool": 1, "polyline": [[0,0,0],[1,0,0]]}], "tolerance": 0.01})";
  }
  const CommandResult truncated =
      run(kBinary + " verify " + (dir / "truncated.json").string() + " --out " + (dir / "out1").string());
  EXPECT_EQ(truncated.exit_code, 2) << truncated.output;
  EXPECT_NE(truncated.output.find("truncated.nc:4"), std::string::npos) << truncated.output;
  const CommandResult missing =
      run(kBinary + " verify " + (dir / "missing_mesh.json").string() + " --out " + (dir / "out2").string());
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("nowhere.stl"), std::string::npos) << missing.output;
}
