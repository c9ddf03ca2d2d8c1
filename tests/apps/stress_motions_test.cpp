// SPDX-License-Identifier: Apache-2.0
// The motion families of `morphmill stress --families motion`: their closed forms against the
// tools' exact integrals and textbook formulas, their known pieces, genus and volumes against the
// OpenVDB reference (independent of every generator), arcs that go where they are meant, tools
// of every shape, and the options on the command line.
#include <gtest/gtest.h>

#include <morph/exceptions.h>
#include <morph/path.h>
#include <morph/topology.h>
#include <morphmill/job_io.h>
#include <vdb_ref/reference.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <string>

#include "apps/command_support.h"
#include "campaigns/stress.h"
#include "campaigns/stress_builder.h"
#include "campaigns/stress_cases.h"

namespace fs = std::filesystem;
using namespace morphmill::stress;

namespace {

fs::path scratch(const std::string& name) {
  return morphmill_test::scratch_dir("stress_motions_test", name);
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

CaseSpace motion_space() {
  return CaseSpace{motion_families()};
}

}  // namespace

// Whole tool below the top: the profile's own closed forms (exact per piece). A ball end at a
// depth within its ball: the circular segment and the spherical cap.
TEST(MotionClosedForms, AgreeWithTheProfilesExactIntegralsAndTheBallsFormulas) {
  const std::vector<morph::Tool> tools = {morph::ball_tool(2.0, 10.0),
                                          morph::flat_tool(1.5, 8.0),
                                          morph::bullnose_tool(2.5, 1.0, 9.0),
                                          morph::conical_tool(2.0, 90.0, 6.0),
                                          morph::tapered_tool(0.5, 2.0, 7.0),
                                          morph::tapered_ball_tool(0.8, 10.0, 9.0),
                                          morph::sphere_tool(1.7)};
  for (const morph::Tool& tool : tools) {
    const double h = tool.profile.height();
    EXPECT_NEAR(section_below(tool, h), tool.profile.section_area(), 1e-8 * tool.profile.section_area())
        << morph::describe(tool);
    EXPECT_NEAR(volume_below(tool, h), tool.profile.volume(), 1e-8 * tool.profile.volume())
        << morph::describe(tool);
  }
  const double r = 2.0, d = 0.7;
  const morph::Tool ball = morph::ball_tool(r, 10.0);
  const double segment = r * r * std::acos((r - d) / r) - (r - d) * std::sqrt(2 * r * d - d * d);
  EXPECT_NEAR(section_below(ball, d), segment, 1e-9);
  EXPECT_NEAR(volume_below(ball, d), M_PI * d * d * (3 * r - d) / 3, 1e-9);
  // A plunge with a tool that only widens upwards removes the tool below the top; a sphere
  // plunged past its equator removes its lower half and the cylinder of its equator.
  EXPECT_NEAR(plunge_volume(ball, 3.5), volume_below(ball, 3.5), 1e-9);
  const morph::Tool sphere = morph::sphere_tool(1.5);
  EXPECT_NEAR(plunge_volume(sphere, 2.5), 2.0 / 3.0 * M_PI * 1.5 * 1.5 * 1.5 + M_PI * 1.5 * 1.5 * 1.0, 1e-6);
}

// Pieces, genus and the closed-form volumes against the OpenVDB level set: every motion family,
// three cases each, tools of every shape.
TEST(MotionCases, KnownPiecesGenusAndVolumesMatchTheReference) {
  const fs::path dir = scratch("reference");
  const std::size_t families = motion_families().size();
  std::set<std::string> with_volume;
  for (std::size_t index = 0; index < 3 * families; ++index) {
    const StressCase c = make_case(22, index, motion_space());  // a volume for each family below
    ASSERT_GE(c.expected_pieces, 1) << c.family;
    ASSERT_GE(c.expected_genus, 0) << c.family;
    const std::string path = write_case(c, dir.string(), case_name(index) + ".json");
    const morph::Job job = morphmill::load_job(path);
    vdb_ref::ReferenceOptions options;
    options.voxel_size = c.voxel_size;
    const vdb_ref::ReferenceResult reference = vdb_ref::compute_reference(job, options);
    const std::string what = case_name(index) + " " + c.family + ": " + c.variant;
    EXPECT_EQ(reference.pieces.size(), static_cast<std::size_t>(c.expected_pieces)) << what;
    const morph::TopologyReport topology = morph::topology_report(reference.mesh);
    if (topology.closed_manifold()) {
      EXPECT_EQ((2 * static_cast<long>(topology.components) - topology.euler_characteristic) / 2,
                c.expected_genus)
          << what;
    }
    if (c.expected_volume) {
      with_volume.insert(c.family);
      // The level set's volume is within half a voxel times its area of the truth; the stock's
      // volume is not (a cut of 5% of it shows).
      EXPECT_NEAR(reference.volume(), *c.expected_volume, 0.5 * c.voxel_size * reference.area()) << what;
      EXPECT_LT(*c.expected_volume, 0.99 * morph::volume(job.stock)) << what;
    }
  }
  for (const char* family :
       {"retrace", "plunge_retract", "submicron", "mixed_tools", "mesh_stock", "fine_steps"})
    EXPECT_EQ(with_volume.count(family), 1u) << family << " never had a closed-form volume";
}

// The sliver stock is a closed, outward box of the box's volume whose top is many triangles.
TEST(MotionCases, MeshStockIsAClosedBoxOfSlivers) {
  const std::size_t families = motion_families().size();
  int seen = 0;
  for (std::size_t index = 0; index < 4 * families; ++index) {
    const StressCase c = make_case(5, index, motion_space());
    if (c.family != "mesh_stock") continue;
    ++seen;
    ASSERT_TRUE(c.stock_mesh.has_value());
    const morph::TriangleMesh& mesh = *c.stock_mesh;
    const morph::TopologyReport topology = morph::topology_report(mesh);
    EXPECT_TRUE(topology.closed_manifold()) << c.variant;
    EXPECT_EQ(topology.components, 1);
    const Eigen::AlignedBox3d box = morph::bounds(mesh);
    EXPECT_NEAR(topology.volume, box.sizes().prod(), 1e-9 * box.sizes().prod()) << c.variant;
    EXPECT_GE(mesh.triangle_count(), 12u + 2u * 6u);  // the top and two sides fanned
    // The thinnest top triangle is a sliver: its smallest altitude under a tenth of a millimetre.
    double thinnest = std::numeric_limits<double>::infinity();
    for (const morph::Triangle& t : mesh.triangles) {
      const Eigen::Vector3d p = mesh.vertices[t[0]], q = mesh.vertices[t[1]], r = mesh.vertices[t[2]];
      if (p.z() < box.max().z() || q.z() < box.max().z() || r.z() < box.max().z()) continue;
      const double longest = std::max({(q - p).norm(), (r - q).norm(), (p - r).norm()});
      thinnest = std::min(thinnest, (q - p).cross(r - p).norm() / longest);
    }
    EXPECT_LT(thinnest, 0.1) << c.variant;
  }
  EXPECT_GE(seen, 3);
}

// The G-code arcs are read as meant: the G18 half circle dips to the cut's depth under its ends,
// the G19 arc turns 300 degrees, the helix descends by whole turns.
TEST(MotionCases, ArcsInEveryPlaneGoWhereTheyAreMeant) {
  const fs::path dir = scratch("arcs");
  std::set<int> planes;  // axis of each arc seen: 0 x (G19), 1 y (G18), 2 z (G17)
  for (std::size_t index = 0, seen = 0; index < 400 && seen < 12; ++index) {
    const StressCase c = make_case(5, index, CaseSpace{{"arcs"}});
    ++seen;
    ASSERT_FALSE(c.gcode_file.empty());
    const morph::Job job = morphmill::load_job(write_case(c, dir.string(), case_name(index) + ".json"));
    const double top = job.stock.box.max().z();
    for (const morph::Path& path : job.paths)
      for (const morph::Move& move : path.moves) {
        if (!move.is_arc()) continue;
        const int axis = move.axis.cwiseAbs().maxCoeff() == std::abs(move.axis.x()) ? 0
                         : std::abs(move.axis.y()) > 0.5                            ? 1
                                                                                    : 2;
        planes.insert(axis);
        double lowest = move.start.z();
        for (int i = 0; i <= 1000; ++i) lowest = std::min(lowest, morph::point_at(move, i / 1000.0).z());
        if (axis == 1) {
          EXPECT_LT(lowest, std::min(move.start.z(), move.end.z()) - 0.1) << c.variant;
        }
        if (axis == 0) {
          EXPECT_NEAR(std::abs(move.sweep), 300.0 * M_PI / 180.0, 1e-9) << c.variant;
        }
        if (axis != 2) {
          EXPECT_LT(lowest, top) << c.variant;
        }
      }
  }
  EXPECT_EQ(planes.size(), 3u) << "arcs in G17, G18 and G19";
}

// The motion families draw every tool shape.
TEST(MotionCases, ToolsAreDrawnOfEveryShape) {
  std::set<std::string> types;
  for (std::size_t index = 0; index < 120; ++index) {
    const StressCase c = make_case(9, index, motion_space());
    for (const auto& [number, tool] : c.job.at("tools").items()) types.insert(tool.at("type"));
  }
  EXPECT_GE(types.size(), 6u);
  EXPECT_EQ(types.count("flat"), 1u);
  // The same seed and index give the same bytes, the G-code program included.
  const StressCase a = make_case(9, 4, motion_space()), b = make_case(9, 4, motion_space());
  EXPECT_EQ(a.job.dump(), b.job.dump());
  EXPECT_EQ(a.gcode_text, b.gcode_text);
}

TEST(MotionCases, FamiliesAreParsedAndUnknownOnesNamed) {
  EXPECT_EQ(parse_families("classic"), case_families());
  EXPECT_EQ(parse_families("motion"), motion_families());
  EXPECT_EQ(parse_families("all").size(), case_families().size() + motion_families().size());
  EXPECT_EQ(parse_families("retrace,spiral,retrace"), (std::vector<std::string>{"retrace", "spiral"}));
  try {
    parse_families("retrace,retraces");
    FAIL() << "an unknown family was accepted";
  } catch (const morph::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown family 'retraces'"), std::string::npos) << e.what();
  }
}

// campaign.json records generator 2 (by name, or by number before names); a campaign of a removed
// generator (1, auto as 0, or none recorded: 1) cannot be continued, and the message says so.
TEST(MotionCampaign, ACampaignOfARemovedGeneratorIsRefused) {
  EXPECT_NO_THROW(check_recorded_generator({{"--generator", "2"}}, "c.json"));
  EXPECT_NO_THROW(check_recorded_generator({{"--generator", 2}}, "c.json"));
  for (const nlohmann::json& old :
       {nlohmann::json{{"--generator", "auto"}}, nlohmann::json{{"--generator", 0}},
        nlohmann::json{{"--generator", "1"}}, nlohmann::json::object()}) {
    try {
      check_recorded_generator(old, "c.json");
      FAIL() << old.dump();
    } catch (const morph::InputError& e) {
      EXPECT_NE(std::string(e.what()).find("c.json: the campaign ran --generator"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("start a new campaign"), std::string::npos) << e.what();
    }
  }
}

// Through the binary: a motion campaign records its generator and families, and a bad family or
// generator is exit 2 before any case runs.
TEST(MotionCampaign, RecordsItsGeneratorAndFamiliesAndRefusesBadOnes) {
  const fs::path out = scratch("campaign");
  const auto bad = morphmill_test::run_command(
      std::string(MORPHMILL_BINARY) + " stress --families retraces --cases 1 -o " + (out / "bad").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("unknown family 'retraces'"), std::string::npos) << bad.output;
  const auto bad_generator = morphmill_test::run_command(
      std::string(MORPHMILL_BINARY) + " stress --generator 3 --cases 1 -o " + (out / "bad3").string());
  EXPECT_EQ(bad_generator.exit_code, 2) << bad_generator.output;
  const auto retired = morphmill_test::run_command(
      std::string(MORPHMILL_BINARY) + " stress --generator 1 --cases 1 -o " + (out / "bad1").string());
  EXPECT_EQ(retired.exit_code, 2) << retired.output;
  EXPECT_NE(retired.output.find("generator 1 was removed"), std::string::npos) << retired.output;
  EXPECT_FALSE(fs::exists(out / "bad1" / "campaign.json"));
  // One submicron case (a pass with a micron move inside): generator 2, the default, builds it.
  const auto ok = morphmill_test::run_command(std::string(MORPHMILL_BINARY) +
                                              " stress --families submicron --cases 1 --samples 200 -q -o " +
                                              (out / "one").string());
  const nlohmann::json campaign = nlohmann::json::parse(slurp(out / "one" / "campaign.json"));
  EXPECT_EQ(campaign.at("--families"), "submicron");
  EXPECT_EQ(campaign.at("--generator"), "2");  // the only one
  const nlohmann::json summary = nlohmann::json::parse(slurp(out / "one" / "summary.json"));
  EXPECT_EQ(summary.at("results").size(), 1u) << ok.output;
  EXPECT_EQ(summary["results"][0].at("family"), "submicron");
}
