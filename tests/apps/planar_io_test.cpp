// SPDX-License-Identifier: Apache-2.0
// Planar jobs, drawings and the erode2d / verify2d commands: bundled jobs as built, round trips,
// and bad input named by file and element.
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/planar_erosion.h>
#include <morphmill/planar_io.h>

#include <algorithm>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "command_support.h"

namespace fs = std::filesystem;
using morphmill::load_planar_job;

namespace {

const std::string kPlanar = std::string(MORPHMILL_TEST_DATA) + "/planar/";

std::string temp_dir(const std::string& name) {
  const fs::path dir =
      fs::temp_directory_path() / ("morphmill_planar_" + name + "_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir.string();
}

std::string write_file(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

morphmill_test::CommandResult run_morphmill(const std::vector<std::string>& arguments) {
  std::string command = std::string("'") + MORPHMILL_BINARY + "'";
  for (const std::string& a : arguments) command += " '" + a + "'";
  return morphmill_test::run_command(command);
}

/// The message of the InputError the call throws ("" if none).
template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const morph::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(PlanarJobs, BundledJobsAsBuilt) {
  // Figure 9: one pass entering a 60 x 40 plate to x = 35 with a disc of radius 4.
  const auto fig9 = load_planar_job(kPlanar + "figure9.json");
  const auto r9 = morph::planar::erode(fig9.stock, fig9.moves, fig9.radius);
  EXPECT_NEAR(morph::planar::area(r9.region), 2400.0 - 35.0 * 8.0 - 8.0 * M_PI, 1e-9);
  struct Expect {
    const char* job;
    std::size_t pieces, holes;
  };
  for (const Expect& e :
       {Expect{"figure12", 2, 0}, Expect{"figure13", 5, 0}, Expect{"sheet", 4, 3}, Expect{"pocket", 2, 2}}) {
    const auto job = load_planar_job(kPlanar + e.job + ".json");
    const auto r = morph::planar::erode(job.stock, job.moves, job.radius);
    SCOPED_TRACE(e.job);
    EXPECT_EQ(r.region.pieces.size(), e.pieces);
    EXPECT_EQ(morph::planar::hole_count(r.region), e.holes);
  }
  // The sheet's stock comes from a DXF LWPOLYLINE with a rounded corner (bulge): 200 x 120 minus the
  // corner's square of 15 plus its quarter disc.
  const auto sheet = load_planar_job(kPlanar + "sheet.json");
  EXPECT_NEAR(morph::planar::area(sheet.stock), 24000.0 - 225.0 + 225.0 * M_PI / 4.0, 1e-6);
  // The sheet's three parts are cut free: pieces 2..4 are the rectangle, the disc and the L.
  const auto cut = morph::planar::erode(sheet.stock, sheet.moves, sheet.radius);
  std::vector<double> parts;
  for (std::size_t i = 1; i < cut.region.pieces.size(); ++i)
    parts.push_back(morph::planar::signed_area(cut.region.loops[cut.region.pieces[i].outer]));
  std::sort(parts.begin(), parts.end());
  EXPECT_NEAR(parts[2], 60.0 * 40.0, 1e-6);         // the rectangle, profile at exactly r
  EXPECT_NEAR(parts[1], M_PI * 25.0 * 25.0, 1e-6);  // the disc inside the circle pass
  // The L: a 67 x 5 bar, a 22 x 22 block and, at the path's inner turn, the 3 x 3 square outside the
  // disc about the turn's corner.
  EXPECT_NEAR(parts[0], 67.0 * 5.0 + 22.0 * 22.0 + 9.0 - 9.0 * M_PI / 4.0, 1e-6);
}

TEST(PlanarJobs, GcodeFeedMovesBelowTheCuttingHeightKeepTheirLines) {
  const std::string dir = temp_dir("gcode");
  const std::string job = write_file(dir, "g.json",
                                     R"({"tool": {"radius": 3}, "stock": [{"rectangle": [0, 0, 100, 32]}],
    "trajectory": [{"gcode": ")" + std::string(MORPHMILL_TEST_DATA) +
                                         R"(/jobs/pocket.nc", "cutting_height": 20}]})");
  const auto j = load_planar_job(job);
  ASSERT_FALSE(j.moves.empty());
  bool arc_seen = false;
  for (const auto& m : j.moves) {
    EXPECT_GT(m.from.line, 0);
    if (m.is_arc()) {
      arc_seen = true;
      EXPECT_NEAR(m.radius, 4.0, 1e-9);
    }
  }
  EXPECT_TRUE(arc_seen);
  // The serpentine's passes at y = 8, 16, 24 with radius 3 and the half turns: one piece of stock left
  // around them with the bays between.
  const auto r = morph::planar::erode(j.stock, j.moves, j.radius);
  EXPECT_LT(morph::planar::area(r.region), 3200.0);
  const auto no_height =
      write_file(dir, "h.json", R"({"tool": {"radius": 3}, "stock": [{"rectangle": [0, 0, 1, 1]}],
    "trajectory": [{"gcode": "x.nc"}]})");
  EXPECT_NE(input_error([&] { load_planar_job(no_height); }).find("cutting_height"), std::string::npos);
}

TEST(PlanarJobs, DxfAndSvgRoundTrips) {
  const auto job = load_planar_job(kPlanar + "figure13.json");
  const auto r = morph::planar::erode(job.stock, job.moves, job.radius);
  const std::string dir = temp_dir("roundtrip");
  morphmill::PlanarDrawing drawing;
  drawing.result = &r.region;
  morphmill::write_planar_result(drawing, dir + "/r.dxf");
  morphmill::write_planar_result(drawing, dir + "/r.svg");
  for (const char* name : {"/r.dxf", "/r.svg"}) {
    SCOPED_TRACE(name);
    const auto shapes = std::string(name) == "/r.dxf" ? morphmill::read_dxf_shapes(dir + name)
                                                      : morphmill::read_svg_shapes(dir + name);
    EXPECT_TRUE(shapes.open.empty());
    const auto back = morph::planar::make_region(shapes.closed);
    EXPECT_EQ(back.pieces.size(), r.region.pieces.size());
    EXPECT_NEAR(morph::planar::area(back), morph::planar::area(r.region), 1e-6);
    EXPECT_NEAR(morph::planar::perimeter(back), morph::planar::perimeter(r.region), 1e-6);
  }
}

TEST(PlanarJobs, BadInputNamesTheFileAndTheElement) {
  const std::string dir = temp_dir("bad");
  const std::string dxf = write_file(dir, "spline.dxf",
                                     "0\nSECTION\n2\nENTITIES\n0\nLINE\n10\n0\n20\n0\n11\n1\n21\n0\n"
                                     "0\nSPLINE\n8\n0\n0\nENDSEC\n0\nEOF\n");
  EXPECT_NE(input_error([&] {
              morphmill::read_dxf_shapes(dxf);
            }).find("spline.dxf:15: DXF entity SPLINE is not supported"),
            std::string::npos)
      << input_error([&] { morphmill::read_dxf_shapes(dxf); });
  const std::string cubic =
      write_file(dir, "cubic.svg", "<svg>\n<path d=\"M0,0 L1,0 C1,1 2,2 3,3 Z\"/>\n</svg>\n");
  EXPECT_NE(input_error([&] {
              morphmill::read_svg_shapes(cubic);
            }).find("cubic.svg:2: <path>: path command 'C' is not supported"),
            std::string::npos)
      << input_error([&] { morphmill::read_svg_shapes(cubic); });
  const std::string ellipse = write_file(dir, "e.svg", "<svg><path d=\"M0,0 A2,1 0 0 1 4,0 Z\"/></svg>");
  EXPECT_NE(input_error([&] { morphmill::read_svg_shapes(ellipse); }).find("elliptical arcs"),
            std::string::npos);
  const std::string bowtie = write_file(dir, "bowtie.json", R"({"tool": {"radius": 1},
    "stock": [{"polygon": [[0, 0], [10, 10], [10, 0], [0, 10]]}], "trajectory": []})");
  EXPECT_NE(input_error([&] {
              load_planar_job(bowtie);
            }).find("bowtie.json: stock: loop 0, element 0 meets loop 0, element 2"),
            std::string::npos)
      << input_error([&] { load_planar_job(bowtie); });
  const std::string radius = write_file(dir, "radius.json", R"({"tool": {"radius": 0},
    "stock": [{"rectangle": [0, 0, 1, 1]}], "trajectory": []})");
  EXPECT_NE(
      input_error([&] { load_planar_job(radius); }).find("radius.json: tool.radius: must be positive, got 0"),
      std::string::npos);
  const std::string open_stock = write_file(dir, "open.svg", "<svg><path d=\"M0,0 L10,0 L10,10\"/></svg>");
  const std::string open_job = write_file(
      dir, "open.json", R"({"tool": {"radius": 1}, "stock": [{"svg": "open.svg"}], "trajectory": []})");
  EXPECT_NE(input_error([&] { load_planar_job(open_job); }).find("open.svg:1: an open outline"),
            std::string::npos)
      << input_error([&] { load_planar_job(open_job); });
  const std::string point =
      write_file(dir, "point.json", R"({"tool": {"radius": 1}, "stock": [{"rectangle": [0, 0, 1, 1]}],
    "trajectory": [{"polyline": [[0, 0], [1]]}]})");
  EXPECT_NE(input_error([&] {
              load_planar_job(point);
            }).find("point.json: trajectory[0].polyline[1]: expected [x, y] or [x, y, bulge]"),
            std::string::npos);
}

TEST(PlanarCommands, Erode2dWritesEachFormatAndVerify2dHolds) {
  const std::string dir = temp_dir("cli");
  for (const char* ext : {"svg", "dxf", "json"}) {
    const auto run = run_morphmill({"erode2d", kPlanar + "figure13.json", "-o", dir + "/part." + ext});
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_TRUE(fs::exists(dir + "/part." + ext));
  }
  const auto verify = run_morphmill({"verify2d", kPlanar + "sheet.json", "-o", dir + "/sheet"});
  EXPECT_EQ(verify.exit_code, 0) << verify.output;
  EXPECT_NE(verify.output.find("verdict HOLDS"), std::string::npos) << verify.output;
  for (const char* f :
       {"result.svg", "deviation.svg", "dilation.svg", "classical.svg", "report.json", "report.md"})
    EXPECT_TRUE(fs::exists(dir + "/sheet/" + f)) << f;
  const auto bad = run_morphmill({"erode2d", kPlanar + "figure13.json", "-o", dir + "/part.png"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("unknown output format '.png'"), std::string::npos) << bad.output;
}
