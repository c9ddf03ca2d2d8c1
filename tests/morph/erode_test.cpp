// SPDX-License-Identifier: Apache-2.0
// Tests of the surface generator (morph/erode.h) against the exact field of morph/sweep_distance.h:
// closed-form volumes, pieces and the tolerance both ways, on sphere and ball-end jobs.
#include <gtest/gtest.h>
#include <morph/erode.h>
#include <morph/exceptions.h>
#include <morph/gcode.h>
#include <morph/mesh_distance.h>
#include <morph/sweep_distance.h>
#include <morph/topology.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <random>

#include "common/test_tools.h"

namespace {

using Eigen::Vector3d;
using morph::Job;
using morph::PatchKind;
using morph::Tool;
using morph::ToolType;

using morphmill_test::ballend_tool;
using morphmill_test::sphere_tool;

Job box_job(const Vector3d& lo, const Vector3d& hi, const Tool& tool,
            const std::vector<std::vector<Vector3d>>& polylines, double tolerance) {
  Job job;
  job.name = "test";
  job.stock.type = morph::StockType::Box;
  job.stock.box = Eigen::AlignedBox3d(lo, hi);
  job.tools[tool.number] = tool;
  job.tolerance = tolerance;
  int line = 1;
  for (const auto& points : polylines) {
    morph::Path path;
    path.source = "test";
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
      morph::Move m;
      m.kind = morph::MoveKind::Linear;
      m.start = points[i];
      m.end = points[i + 1];
      m.tool = tool.number;
      m.line = ++line;
      path.moves.push_back(m);
    }
    ++line;
    job.paths.push_back(path);
  }
  return job;
}

/// Largest |f| over the vertices, edge midpoints and centroids of the output (the exact field
/// f is 1-Lipschitz, so |f| bounds the distance to the exact surface from below and equals it
/// away from creases; at creases f is the max of two exact distances).
double largest_field_error(const morph::TriangleMesh& mesh, const morph::ErosionField& field) {
  double worst = 0.0;
  for (const Vector3d& v : mesh.vertices) worst = std::max(worst, std::abs(field.value(v)));
  for (const auto& t : mesh.triangles) {
    const Vector3d& a = mesh.vertices[t[0]];
    const Vector3d& b = mesh.vertices[t[1]];
    const Vector3d& c = mesh.vertices[t[2]];
    for (const Vector3d& p :
         {Vector3d((a + b) / 2), Vector3d((b + c) / 2), Vector3d((c + a) / 2), Vector3d((a + b + c) / 3)})
      worst = std::max(worst, std::abs(field.value(p)));
  }
  return worst;
}

/// Erodes the job and expects a closed manifold of `components` pieces within its tolerance.
void expect_closed_within_tolerance(const Job& job, std::size_t components) {
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold())
      << topology.boundary_edges << " open, " << topology.non_manifold_edges << " non-manifold edges, "
      << topology.non_manifold_vertices << " non-manifold vertices";
  EXPECT_EQ(topology.components, components);
  EXPECT_LE(largest_field_error(result.mesh, morph::ErosionField(job)), job.tolerance);
}

/// Points of the exact surface: random points near the stock projected onto f = 0 by Newton
/// steps on the exact field. Returns the largest distance from them to the output mesh.
double largest_coverage_gap(const morph::TriangleMesh& mesh, const morph::ErosionField& field,
                            const Eigen::AlignedBox3d& region, int samples, int* accepted_out = nullptr) {
  morph::MeshDistance distance(mesh);
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0;
  int accepted = 0;
  for (int s = 0; s < samples; ++s) {
    Vector3d p = region.min() + region.sizes().cwiseProduct(Vector3d(unit(rng), unit(rng), unit(rng)));
    bool converged = false;
    for (int it = 0; it < 30; ++it) {
      const double f = field.value(p);
      if (std::abs(f) < 1e-9) {
        converged = true;
        break;
      }
      const double h = 1e-6;
      Vector3d grad;
      for (int c = 0; c < 3; ++c) {
        Vector3d e = Vector3d::Zero();
        e[c] = h;
        grad[c] = (field.value(p + e) - field.value(p - e)) / (2 * h);
      }
      if (grad.squaredNorm() < 1e-12) break;
      p -= f * grad / grad.squaredNorm();
    }
    if (!converged) continue;
    ++accepted;
    worst = std::max(worst, distance.distance(p));
  }
  if (accepted_out) *accepted_out = accepted;
  return worst;
}

void expect_within_tolerance_both_ways(const Job& job, const morph::TriangleMesh& mesh, int samples = 3000) {
  const morph::ErosionField field(job);
  const double tol = job.tolerance;
  const double field_error = largest_field_error(mesh, field);
  EXPECT_LE(field_error, tol);
  std::cout << "  triangles " << mesh.triangles.size() << ", largest |f| on the output " << field_error
            << '\n';
  Eigen::AlignedBox3d region = job.stock.box;
  region.min().array() -= 1.0;
  region.max().array() += 1.0;
  int accepted = 0;
  const double gap = largest_coverage_gap(mesh, field, region, samples, &accepted);
  EXPECT_LE(gap, tol);
  std::cout << "  largest distance from " << accepted << " exact surface points to the output " << gap
            << '\n';
  EXPECT_GT(accepted, samples / 4);
}

TEST(ErodeSphere, SinglePassWithinToleranceBothWays) {
  const Job job = box_job({0, 0, 0}, {20, 10, 10}, sphere_tool(2.0), {{{4, 5, 9}, {16, 5, 9}}}, 0.01);
  const morph::ErodeResult result = morph::erode(job);
  ASSERT_FALSE(result.mesh.empty());
  EXPECT_EQ(result.mesh.tags.size(), result.mesh.triangles.size());
  EXPECT_EQ(result.stats.moves, 1u);
  EXPECT_EQ(result.stats.moves_touching_stock, 1u);
  expect_within_tolerance_both_ways(job, result.mesh);
  EXPECT_EQ(morph::fallbacks_fired(result.stats), 0u);
}

TEST(ErodeBallEnd, RampsPlungesAndLevelMovesWithinTolerance) {
  const Job job = box_job({0, 0, -10}, {30, 20, 0}, ballend_tool(1.5, 12.0),
                          {{{-3, 4, -1}, {12, 4, -2}, {12, 4, -5}, {20, 9, -3}, {27, 14, -3}, {27, 14, 2}},
                           {{5, 16, 3}, {5, 16, -2}, {25, 16, -2}}},
                          0.01);
  const morph::ErodeResult result = morph::erode(job);
  ASSERT_FALSE(result.mesh.empty());
  expect_within_tolerance_both_ways(job, result.mesh);
}

TEST(ErodeSphere, ProvenanceOfEveryFace) {
  const Job job = box_job({0, 0, 0}, {20, 10, 10}, sphere_tool(1.5),
                          {{{3, 3, 9}, {10, 6, 9.5}, {17, 3, 9}}, {{3, 8, 11}, {17, 8, 11}}}, 0.01);
  const morph::ErodeResult result = morph::erode(job);
  const auto moves = job.moves();
  const Tool& tool = job.tools.at(1);
  const morph::TriangleMesh& mesh = result.mesh;
  ASSERT_EQ(mesh.tags.size(), mesh.triangles.size());
  std::size_t side = 0, front = 0, stock = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const morph::FaceTag& tag = mesh.tags[t];
    const Vector3d c = (mesh.vertices[mesh.triangles[t][0]] + mesh.vertices[mesh.triangles[t][1]] +
                        mesh.vertices[mesh.triangles[t][2]]) /
                       3.0;
    switch (tag.kind) {
      case PatchKind::StockFace: {
        ++stock;
        ASSERT_GE(tag.source, 0);
        ASSERT_LT(tag.source, 6);
        // Box faces are numbered -x, +x, -y, +y, -z, +z.
        const int axis = tag.source / 2;
        const double plane = tag.source % 2 ? job.stock.box.max()[axis] : job.stock.box.min()[axis];
        EXPECT_NEAR(c[axis], plane, 1e-9);
        break;
      }
      case PatchKind::SideSweep:
      case PatchKind::FrontSweep: {
        (tag.kind == PatchKind::SideSweep ? side : front)++;
        ASSERT_GE(tag.source, 0);
        ASSERT_LT(tag.source, static_cast<int>(moves.size()));
        const morph::Move& m = *moves[tag.source];
        EXPECT_EQ(tag.line, m.line);
        // The face lies on the surface of that move's own sweep; a cap on the tool's own sphere
        // about an end of the move.
        EXPECT_LE(std::abs(morph::swept_signed_distance(tool, m, c)), job.tolerance);
        if (tag.kind == PatchKind::FrontSweep) {
          EXPECT_NEAR(std::min((c - m.start).norm(), (c - m.end).norm()), tool.radius, job.tolerance);
        }
        break;
      }
      default:
        ADD_FAILURE() << "face " << t << " has kind " << morph::to_string(tag.kind);
    }
  }
  EXPECT_GT(side, 0u);
  EXPECT_GT(front, 0u);
  EXPECT_GT(stock, 0u);
}

TEST(Erode, SameBytesWhateverTheThreads) {
  const Job job = box_job({0, 0, -10}, {30, 20, 0}, ballend_tool(1.5, 12.0),
                          {{{-3, 4, -1}, {12, 4, -2}, {12, 4, -5}, {20, 9, -3}, {27, 14, -3}}}, 0.02);
  morph::ErodeOptions sequential, parallel;
  sequential.policy = morph::ExecutionPolicy::Sequential;
  parallel.policy = morph::ExecutionPolicy::Parallel;
  const morph::ErodeResult a = morph::erode(job, sequential);
  const morph::ErodeResult b = morph::erode(job, parallel);
  ASSERT_EQ(a.mesh.vertices.size(), b.mesh.vertices.size());
  ASSERT_EQ(a.mesh.triangles, b.mesh.triangles);
  ASSERT_EQ(a.mesh.tags, b.mesh.tags);
  for (std::size_t v = 0; v < a.mesh.vertices.size(); ++v)
    ASSERT_EQ(a.mesh.vertices[v], b.mesh.vertices[v]) << "vertex " << v;
}

TEST(Erode, MovesThatMissTheStockLeaveNoTrace) {
  const Job job = box_job({0, 0, 0}, {10, 10, 10}, sphere_tool(1.0), {{{0, 0, 12}, {10, 10, 12}}}, 0.01);
  const morph::ErodeResult result = morph::erode(job);
  EXPECT_EQ(result.stats.moves_touching_stock, 0u);
  for (const morph::FaceTag& tag : result.mesh.tags) EXPECT_EQ(tag.kind, PatchKind::StockFace);
  EXPECT_NEAR(morph::surface_area(result.mesh), 600.0, 1e-9);
  EXPECT_NEAR(morph::enclosed_volume(result.mesh), 1000.0, 1e-9);
}

// Closed form of a sphere pass: the removed volume of a capsule fully inside the box is
// pi r^2 L + 4/3 pi r^3, and its surface is an inner shell (a cavity): two surface components.
TEST(ErodeSphere, CavityOfAPassInsideTheBoxIsClosedWithExactVolume) {
  const double r = 2.0, L = 12.0;
  const Job job = box_job({0, 0, 0}, {20, 10, 10}, sphere_tool(r), {{{4, 5, 5}, {4 + L, 5, 5}}}, 0.01);
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_EQ(topology.components, 2u);
  EXPECT_EQ(morph::topology_report(result.mesh).boundary_edges, 0u);
  const double removed = M_PI * r * r * L + 4.0 / 3.0 * M_PI * r * r * r;
  const double removed_area = 2.0 * M_PI * r * L + 4.0 * M_PI * r * r;
  // Every point within the tolerance of the exact surface bounds the volume error by area * tol.
  EXPECT_NEAR(topology.volume, 2000.0 - removed, removed_area * job.tolerance);
  EXPECT_LE(largest_field_error(result.mesh, morph::ErosionField(job)), job.tolerance);
}

// A pass whose sphere pokes out of the top face: the removed volume is the capsule below z = 10.
TEST(ErodeSphere, PassThroughTheTopFaceIsClosedWithExactVolume) {
  const double r = 2.0, L = 12.0, depth_above = 1.0;  // centre 1 below the top face
  const Job job = box_job({0, 0, 0}, {20, 10, 10}, sphere_tool(r), {{{4, 5, 9}, {4 + L, 5, 9}}}, 0.01);
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_EQ(topology.components, 1u);
  // Disc minus the circular segment above the face, times L; ball minus its cap above the face.
  const double segment =
      r * r * std::acos(depth_above / r) - depth_above * std::sqrt(r * r - depth_above * depth_above);
  const double cap_height = r - depth_above;
  const double removed = (M_PI * r * r - segment) * L + 4.0 / 3.0 * M_PI * r * r * r -
                         M_PI * cap_height * cap_height * (3 * r - cap_height) / 3.0;
  const double removed_area = 2.0 * M_PI * r * L + 4.0 * M_PI * r * r;  // bounds the curved area
  EXPECT_NEAR(topology.volume, 2000.0 - removed, removed_area * job.tolerance);
}

// data/jobs/single_slot.json: a ball-end pass whose ball centre runs exactly in the top face
// (tip 2 below it), through the whole block. The slot's half-cylinder edge lies exactly on the top
// face and the tie-break shifts the trimming curves of both sides off the grid line by one tie:
// the seams must still close. Removed: a half cylinder of radius r across the block.
TEST(ErodeBallEnd, SlotWithBallCentreInTheTopFaceIsClosedWithExactVolume) {
  const double r = 2.0, width = 40.0;
  const Job job =
      box_job({0, 0, 0}, {width, 20, 10}, ballend_tool(r, 20.0), {{{-5, 10, 8}, {45, 10, 8}}}, 0.01);
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_EQ(topology.components, 1u);
  EXPECT_EQ(morph::topology_report(result.mesh).boundary_edges, 0u);
  const double removed = 0.5 * M_PI * r * r * width;
  const double cut_area = M_PI * r * width + M_PI * r * r;  // half cylinder and its two end half discs
  EXPECT_NEAR(topology.volume, width * 20.0 * 10.0 - removed, cut_area * job.tolerance);
  EXPECT_LE(largest_field_error(result.mesh, morph::ErosionField(job)), job.tolerance);
}

// A descending, turning ball-end path whose end ball has its centre exactly in the top face: the
// front sweeps are spheres whose sampled point may lie on their upper half (trimmed away), where
// only the sphere's own normal tells outward from inward; a lune wound inward leaves its seams open.
TEST(ErodeBallEnd, DescendingTurnAndEndInTheTopFaceAreClosed) {
  const Job job = box_job({0, 0, -20}, {80, 60, 0}, ballend_tool(3.0, 30.0),
                          {{{20, 30, 1}, {40, 30, -1}, {60, 32, -3}}}, 0.01);
  expect_closed_within_tolerance(job, 1u);
}

// Two full-depth ball-end slots exactly 2r apart: their body rulings coincide, facing each other.
// The wall between them has no thickness, so the block falls into two pieces and the shared
// plane bounds neither (it is interior to the union of the sweeps).
TEST(ErodeBallEnd, SlotsTouchingFaceToFaceSplitTheBlockInTwo) {
  const double r = 2.5, depth = 4.0;
  const Job job = box_job({0, 0, 0}, {20, 10, depth}, ballend_tool(r, 10.0),
                          {{{7.5, -4, -r}, {7.5, 14, -r}}, {{12.5, 14, -r}, {12.5, -4, -r}}}, 0.01);
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold()) << topology.boundary_edges << " open edges";
  EXPECT_EQ(topology.components, 2u);
  // The slots' bodies remove the block between x = 5 and x = 15 over its whole height, the two
  // outer walls within the tolerance.
  EXPECT_NEAR(topology.volume, 10.0 * 10.0 * depth, job.tolerance * 2 * 10.0 * depth);
}

// A stretch of the bundled crossing_rose path: a descending S-curve cut as a closed tunnel below
// the top face. Where consecutive moves turn by about a degree the lune between their tubes is
// far thinner than a grid cell near its poles, at the tunnel's ceiling; the seams there leave
// gaps of a few micrometres whose repair balls meet each other.
TEST(ErodeSphere, ThinLunesOfATunnelCeilingAreClosed) {
  const Job job =
      box_job({0, 0, 0}, {100, 100, 20}, sphere_tool(2.5),
              {{{50, 71.2132, 17},           {49.8157, 70.5356, 16.9971}, {49.6439, 69.8362, 16.9943},
                {49.4851, 69.1158, 16.9914}, {49.34, 68.3754, 16.9886},   {49.2089, 67.6158, 16.9857},
                {49.0923, 66.8381, 16.9829}, {48.9907, 66.0431, 16.98},   {48.9043, 65.2319, 16.9771},
                {48.8337, 64.4055, 16.9743}, {48.7791, 63.5649, 16.9714}, {48.7409, 62.7112, 16.9686},
                {48.7192, 61.8454, 16.9657}, {48.7143, 60.9686, 16.9629}, {48.7263, 60.082, 16.96},
                {48.7556, 59.1866, 16.9571}, {48.8021, 58.2836, 16.9543}, {48.866, 57.374, 16.9514},
                {48.9472, 56.4591, 16.9486}, {49.0459, 55.5399, 16.9457}, {49.162, 54.6176, 16.9429},
                {49.2954, 53.6934, 16.94},   {49.4461, 52.7684, 16.9371}, {49.6139, 51.8437, 16.9343},
                {49.7986, 50.9205, 16.9314}}},
              0.01);
  expect_closed_within_tolerance(job, 2u);  // the block's outside and the tunnel
}

// A ball end plunging and then cutting a level slot from the plunge: the slot's body ruling is
// tangent to the plunge's body cylinder along a vertical line, and the tie band of the tangent
// contact leaves a strip under a tenth of a micrometre wide that no fan closes.
TEST(ErodeBallEnd, SlotLeavingAPlungeTangentiallyIsClosed) {
  const Job job = box_job({0, 0, 0}, {100, 60, 20}, ballend_tool(3.0, 40.0),
                          {{{30, 8, 25}, {30, 8, 16}, {70, 8, 16}}}, 0.01);
  expect_closed_within_tolerance(job, 1u);
}

// A ball end sinking into the top face at a shallow slope (from 0.025 above it to 0.075 deep):
// where it first touches, its cut in the face is a teardrop narrower than the face's grid cells,
// whose nodes are all kept; unless a grid line is put through it, the face has no hole there.
TEST(ErodeBallEnd, SinkingPassCutsItsThinTeardropIntoTheFace) {
  const Job job = box_job({0, 0, 0}, {16.373, 16.078, 9.555}, ballend_tool(2.799, 19.555),
                          {{{-3, 4.57, 9.58}, {19.373, 4.57, 9.48}}}, 0.05);
  expect_closed_within_tolerance(job, 1u);
}

// A sphere ending 0.05 deep in the top disc of a cylinder: its cap cuts a circle of radius 0.46
// into the disc, bending tighter than either grid resolves, so the disc's and the cap's chords
// of it lie up to twice their sagitta apart and need a wider seam match.
TEST(ErodeSphere, ShallowEndInACylinderTopIsClosed) {
  Job job = box_job({0, 0, 0}, {1, 1, 1}, sphere_tool(2.116),
                    {{{-11.849441366549643, 0.953, 10.091}, {11.849441366549643, 0.953, 10.051}}}, 0.02);
  job.stock.type = morph::StockType::Cylinder;
  job.stock.base = Vector3d::Zero();
  job.stock.axis = Vector3d::UnitZ();
  job.stock.radius = 12.515;
  job.stock.height = 7.985;
  expect_closed_within_tolerance(job, 1u);
}

// Two ball-end zigzags crossing at one depth (stress case 817 of seed 1): at the top face one
// path's corner cylinder passes beside the other's corner, so the five surfaces around the hole
// there share no point; its corner is where three of them meet on the exact surface.
TEST(ErodeBallEnd, HoleAmongFiveSurfacesClosesAtACornerOfThree) {
  const double a = 11.888326282659618, b = 4.443826282659618;
  const Job job = box_job({0, 0, 0}, {28.476, 13.587, 6.008}, ballend_tool(2.223, 16.008),
                          {{{a, b, 3.426},
                            {a, 9.143173717340382, 3.426},
                            {14.331326282659617, 9.143173717340382, 3.426},
                            {14.331326282659617, b, 3.426}},
                           {{a, b, 3.426},
                            {16.58767371734038, b, 3.426},
                            {16.58767371734038, 6.886826282659618, 3.426},
                            {a, 6.886826282659618, 3.426}}},
                          0.01);
  expect_closed_within_tolerance(job, 1u);
}

// A closed {7/3} star of ball-end passes 1.99 deep (stress case 635 of seed 1): all seven tubes
// pass 0.5 from the star's centre and stay within the tolerance of each other over a disc about
// 2 wide around it, so trimming cannot tell their pieces apart there and they overlap; the hole
// is wider than a cell and is closed only by a wider repair.
TEST(ErodeBallEnd, StarOfSevenEqualPassesClosesAtItsPeak) {
  const double z = 7.728999999999999;
  const Job job = box_job({0, 0, 0}, {23.984, 14.847, 9.719}, ballend_tool(2.813, 19.719),
                          {{{9.756275159281216, 7.5261475996330995, z},
                            {13.961781354343469, 6.360973054836591, z},
                            {10.67830148704253, 9.235459798166284, z},
                            {12.389421569625302, 5.220988209086263, z},
                            {12.589569589626853, 9.580329311436273, z},
                            {10.517795237056664, 5.73953966494675, z},
                            {14.050855603023972, 8.301062361894736, z},
                            {9.756275159281216, 7.526147599633102, z}}},
                          0.05);
  expect_closed_within_tolerance(job, 1u);
}

// Two sphere zigzags whose corners lie 0.001 apart along one line (stress case 733 of seed 1):
// the longer pass's tube shows only in a strip 0.001 wide around the shorter pass's end, a gap
// narrower than the weld distance that is closed by triangulating its own boundary loop.
TEST(ErodeSphere, CoincidentPassesEndingApartLeaveNoSliverGap) {
  const double x0 = 8.731503683573631, x1 = 10.757503683573631, x2 = 12.783503683573631,
               x3 = 12.784496316426367, z = 8.607999999999999;
  const double y0 = 4.569003683573634, y1 = 8.621996316426367, y2 = 6.595003683573633, y3 = 8.621003683573633;
  const Job job = box_job({0, 0, 0}, {21.516, 13.191, 9.338}, sphere_tool(1.943),
                          {{{x0, y0, z}, {x0, y1, z}, {x1, y1, z}, {x1, y0, z}, {x2, y0, z}, {x2, y1, z}},
                           {{x0, y0, z}, {x3, y0, z}, {x3, y2, z}, {x0, y2, z}, {x0, y3, z}, {x3, y3, z}}},
                          0.01);
  expect_closed_within_tolerance(job, 1u);
}

/// The runs of consecutive linear moves of a program that pass within `reach` of `spot`.
std::vector<std::vector<Vector3d>> runs_near(const morph::GcodeResult& program, const Vector3d& spot,
                                             double reach) {
  auto distance_to = [&](const morph::Move& m) {
    const Vector3d d = m.end - m.start;
    const double t =
        d.squaredNorm() > 0 ? std::clamp((spot - m.start).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
    return (m.start + t * d - spot).norm();
  };
  std::vector<std::vector<Vector3d>> runs;
  bool in_run = false;
  for (const morph::Move& m : program.path.moves) {
    if (m.kind != morph::MoveKind::Linear || distance_to(m) >= reach) {
      in_run = false;
      continue;
    }
    if (!in_run) runs.push_back({m.start});
    runs.back().push_back(m.end);
    in_run = true;
  }
  return runs;
}

std::size_t move_count(const std::vector<std::vector<Vector3d>>& runs) {
  std::size_t moves = 0;
  for (const auto& run : runs) moves += run.size() - 1;
  return moves;
}

// The 106 moves of bear.nc within 2.5 of a point where a seam's corner search converged a
// billionth away from a vertex of the hole's own loop: the new point left an edge no later fan
// could cross, and one edge stayed non-manifold (the only defect of the whole program).
TEST(ErodeBallEnd, BearCornerFoundAtAVertexOfItsHoleIsClosed) {
  const std::string path = std::string(MORPHMILL_SHARED_DIR) + "/gcode/bear.nc";
  if (!std::ifstream(path)) GTEST_SKIP() << "shared gcode not found at " << MORPHMILL_SHARED_DIR;
  const auto runs = runs_near(morph::read_gcode(path), Vector3d(61.4004, 24.6543, -4.4029), 2.5);
  ASSERT_EQ(move_count(runs), 106u);
  const Job job = box_job({0, 0, -20}, {80, 80, 0}, ballend_tool(1.5875, 25.4), runs, 0.01);
  expect_closed_within_tolerance(job, 1u);
}

// The 92 moves of the bundled 3D_Chips program within 6 of a peak where the cuts of three
// passes meet (two neighbours' ball ends and a third pass's body): the seams leave a pentagon
// there whose own triangles sag 0.014 under the ridge, more than the tolerance allows a fill,
// and the pentagon was the whole program's last open hole.
TEST(ErodeBallEnd, ChipsPeakOfThreeCutsIsClosed) {
  const auto runs = runs_near(morph::read_gcode(std::string(MORPHMILL_TEST_DATA) + "/gcode/3D_Chips.ngc"),
                              Vector3d(44.94, 25.93, -1.82), 6.0);
  ASSERT_EQ(move_count(runs), 92u);
  const Job job = box_job({-50, -50, -50}, {50, 50, 0}, ballend_tool(5.0, 50.0), runs, 0.01);
  expect_closed_within_tolerance(job, 1u);
}

// Two rows of the 100k-move raster benchmark (0.104 mm moves of a 1/8 in ball end over a wavy
// surface, rows 1 mm apart, one forward and one back): their joints line up across the cusp
// between the rows, where each joint's thin cap and the next side patch meet the cusp 0.00104
// apart and folded a sliver over (9 non-manifold edges, one per joint).
TEST(ErodeBallEnd, AlignedJointsOfAdjacentRowsLeaveNoFold) {
  auto height = [](double x, double y) { return -6.0 + 3.0 * std::sin(x / 9.0) * std::cos(y / 13.0); };
  std::vector<std::vector<Vector3d>> rows(2);
  for (int k = 0; k <= 1000; ++k) {
    const double x = -2.0 + 104.0 * k / 1000.0;
    if (x < 85.5 || x > 88.0) continue;
    rows[0].push_back(Vector3d(x, 82.5, height(x, 82.5)));
    rows[1].push_back(Vector3d(x, 83.5, height(x, 83.5)));
  }
  std::reverse(rows[1].begin(), rows[1].end());
  ASSERT_EQ(rows[0].size(), 24u);
  const Job job = box_job({0, 0, -20}, {100, 100, 0}, ballend_tool(1.5875, 25.4), rows, 0.01);
  expect_closed_within_tolerance(job, 1u);
}

// Six rows of the 100k-move raster benchmark where they run off the block's side face x = 100,
// with the step-overs beyond it. A row's move ending 0.024 outside the face leaves its tube's
// end profile 0.003 inside it, a sliver within the tie of the next move's tube, where the cusp
// between two rows meets the face: the hole there straddles the stock's edge, and no fan fits
// both the face and the cuts (8 open and 2 non-manifold edges).
// Rows first_row..last_row - 1 of the 100k-move raster benchmark (row r at y = r + 0.5, 1000
// moves 0.104 long across x in [-2, 102], odd rows run backwards), only their points with x in
// [x_min, x_max], joined into one path by the step-overs between rows.
std::vector<Vector3d> raster_rows(int first_row, int last_row, double x_min, double x_max) {
  auto height = [](double x, double y) { return -6.0 + 3.0 * std::sin(x / 9.0) * std::cos(y / 13.0); };
  std::vector<Vector3d> path;
  for (int row = first_row; row < last_row; ++row) {
    const double y = 0.5 + row;
    std::vector<Vector3d> points;
    for (int k = 0; k <= 1000; ++k) {
      const double x = -2.0 + 104.0 * k / 1000.0;
      if (x >= x_min && x <= x_max) points.push_back(Vector3d(x, y, height(x, y)));
    }
    if (row % 2 == 1) std::reverse(points.begin(), points.end());
    path.insert(path.end(), points.begin(), points.end());
  }
  return path;
}

TEST(ErodeBallEnd, RowsRunningOffTheSideFaceLeaveNoHoleAtItsEdge) {
  const std::vector<Vector3d> path = raster_rows(52, 58, 97.0, 200.0);
  ASSERT_EQ(path.size(), 294u);
  const Job job = box_job({0, 0, -20}, {100, 100, 0}, ballend_tool(1.5875, 25.4), {path}, 0.01);
  expect_closed_within_tolerance(job, 1u);
}

// Rows of 0.104-long moves, 1 mm apart, over a block whose +y face lies on the cusp between
// two rows: on the face the rows are within a few hundredths of each other, and the next row's
// tube keeps a strip 0.04 wide between the cusp and the face, inside one grid cell of each of
// its one-cell-long tubes and crossing no grid edge. The strip went missing and left 146 open
// edges along the face until tubes near the stock's boundary took a line through their middle.
TEST(ErodeBallEnd, ShortMovesWithTheirCuspOnAFaceAreClosed) {
  const std::vector<Vector3d> path = raster_rows(48, 50, 52.0, 57.0);
  ASSERT_EQ(path.size(), 96u);
  const Job job = box_job({51, 46, -20}, {58, 49, 0}, ballend_tool(1.5875, 25.4), {path}, 0.01);
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold()) << topology.boundary_edges << " open edges";
  EXPECT_EQ(topology.components, 1u);
  expect_within_tolerance_both_ways(job, result.mesh, 2000);
}

// The moves of the 100k-move raster benchmark (1000 per row, 0.104 long) that pass within
// `reach` of `spot`, as runs of consecutive moves.
std::vector<std::vector<Vector3d>> raster_runs_near(const Vector3d& spot, double reach) {
  auto height = [](double x, double y) { return -6.0 + 3.0 * std::sin(x / 9.0) * std::cos(y / 13.0); };
  std::vector<Vector3d> points;
  for (int row = 0; row < 100; ++row) {
    const double y = 0.5 + row;
    for (int k = 0; k <= 1000; ++k) {
      const double s = k / 1000.0;
      const double x = row % 2 == 0 ? -2.0 + 104.0 * s : 102.0 - 104.0 * s;
      points.push_back(Vector3d(x, y, height(x, y)));
    }
  }
  auto distance = [&](const Vector3d& a, const Vector3d& b) {
    const Vector3d ab = b - a;
    const double t = std::clamp((spot - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    return (a + t * ab - spot).norm();
  };
  std::vector<std::vector<Vector3d>> runs;
  bool open = false;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    if (distance(points[k], points[k + 1]) >= reach) {
      open = false;
      continue;
    }
    if (!open) runs.push_back({points[k]});
    runs.back().push_back(points[k + 1]);
    open = true;
  }
  return runs;
}

// Two spots of the 100k-move raster where the cusp between two rows meets a joint's cap: slivers
// a ten-thousandth of the tolerance wide meet at one vertex, which joins two fans of four
// triangles (no edge is open), and no fan around it fits within half the tolerance. Welding the
// slivers into it leaves one fan.
TEST(ErodeBallEnd, ShortMovesOverACuspLeaveNoPinchedVertex) {
  for (const Vector3d& spot : {Vector3d(69.756, 20.664, -6.010), Vector3d(76.309, 92.792, -4.349)}) {
    SCOPED_TRACE(testing::Message() << "near " << spot.transpose());
    const auto runs = raster_runs_near(spot, 2.0);
    std::size_t moves = 0;
    for (const auto& run : runs) moves += run.size() - 1;
    ASSERT_GT(moves, 100u);
    const Job job = box_job({0, 0, -20}, {100, 100, 0}, ballend_tool(1.5875, 25.4), runs, 0.01);
    expect_closed_within_tolerance(job, 1u);
  }
}

// A sphere grazing the top front edge of the block, half a tolerance deep, all along it: what
// is left of its sweep is a strip about 0.035 wide, far narrower than a grid cell of the tube;
// unless a grid line is put through it, the tube loses it and the faces' cuts stay open.
TEST(ErodeSphere, GrazingAnEdgeKeepsTheStripAndIsClosed) {
  const double r = 3.0, tolerance = 0.05, depth = 0.5 * tolerance;
  const double offset = (r - depth) / std::sqrt(2.0);
  const Job job = box_job({0, 0, 0}, {19, 19, 5}, sphere_tool(r),
                          {{{-3, -offset, 5 + offset}, {22, -offset, 5 + offset}}}, tolerance);
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold())
      << topology.boundary_edges << " open, " << topology.non_manifold_edges << " non-manifold edges";
  EXPECT_EQ(topology.components, 1u);
  EXPECT_LE(largest_field_error(result.mesh, morph::ErosionField(job)), job.tolerance);
  // The strip is there: some faces lie on the sweep.
  std::size_t swept = 0;
  for (const morph::FaceTag& tag : result.mesh.tags)
    swept += tag.kind == PatchKind::SideSweep || tag.kind == PatchKind::FrontSweep;
  EXPECT_GT(swept, 0u);
}

// An 11-gon ring cut full depth around an island with a ball end: the island's corners are where
// two passes' body rulings meet on the top and bottom faces. A grid cell holding such a corner
// must put a vertex on it (a chord across it was 3 tolerances off) and must see every pass that
// covers its nodes (a pass skipped inside its bounds made a false root).
TEST(ErodeBallEnd, IslandCornersAreExact) {
  std::vector<Vector3d> ring;
  for (int k = 0; k <= 11; ++k) {
    const double angle = 2.0 * M_PI * (k % 11) / 11.0 + 0.3;
    ring.push_back({8.0 * std::cos(angle), 8.0 * std::sin(angle), -3.381});
  }
  const Job job = box_job({-15, -15, 0}, {14, 14, 4.618}, ballend_tool(2.492, 14.618), {ring}, 0.02);
  expect_closed_within_tolerance(job, 2u);
}

// data/jobs/mesh_stock.json built in code: a sphere dragged along a bent groove through a block
// given as the 12 triangles of data/meshes/block.stl (same vertices, same diagonals). The stock
// triangles' degenerate apex corners and their long shared diagonals must not leave seams open.
// The surface is the same as with the analytic box stock, so both volumes are within the curved
// area times the tolerance of the truth.
TEST(ErodeSphere, GrooveThroughAMeshStockIsClosedAndMatchesTheBoxStock) {
  const double r = 4.0;
  const std::vector<std::vector<Vector3d>> groove{{{-5, 20, 20}, {50, 30, 18}, {105, 40, 20}}};
  const Job box = box_job({0, 0, 0}, {100, 60, 20}, sphere_tool(r), groove, 0.01);
  Job job = box;
  job.stock.type = morph::StockType::Mesh;
  job.stock.mesh.vertices = {{0, 0, 0},  {0, 60, 0},   {100, 60, 0},  {100, 0, 0},
                             {0, 0, 20}, {100, 0, 20}, {100, 60, 20}, {0, 60, 20}};
  job.stock.mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}, {0, 3, 5}, {0, 5, 4},
                              {1, 7, 6}, {1, 6, 2}, {0, 4, 7}, {0, 7, 1}, {3, 2, 6}, {3, 6, 5}};
  ASSERT_NEAR(morph::enclosed_volume(job.stock.mesh), 100.0 * 60.0 * 20.0, 1e-9);
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_EQ(topology.components, 1u);
  EXPECT_EQ(morph::topology_report(result.mesh).boundary_edges, 0u);
  const morph::TopologyReport reference = morph::topology_report(morph::erode(box).mesh);
  EXPECT_TRUE(reference.closed_manifold());
  const double path_length = (groove[0][1] - groove[0][0]).norm() + (groove[0][2] - groove[0][1]).norm();
  const double curved_area = 2.0 * M_PI * r * path_length + 4.0 * M_PI * r * r;  // bounds the groove's
  EXPECT_NEAR(topology.volume, reference.volume, 2.0 * curved_area * job.tolerance);
  EXPECT_LT(topology.volume, 100.0 * 60.0 * 20.0);
  EXPECT_LE(largest_field_error(result.mesh, morph::ErosionField(job)), job.tolerance);
}

// A repeated pass coincides with the first everywhere: the output is the same surface.
TEST(ErodeSphere, RepeatedPassGivesTheSameSurface) {
  const std::vector<Vector3d> pass{{4, 5, 9}, {16, 5, 9}};
  const Job once = box_job({0, 0, 0}, {20, 10, 10}, sphere_tool(2.0), {pass}, 0.01);
  const Job twice = box_job({0, 0, 0}, {20, 10, 10}, sphere_tool(2.0), {pass, pass}, 0.01);
  const morph::ErodeResult a = morph::erode(once);
  const morph::ErodeResult b = morph::erode(twice);
  const morph::TopologyReport ta = morph::topology_report(a.mesh), tb = morph::topology_report(b.mesh);
  EXPECT_TRUE(tb.closed_manifold());
  EXPECT_EQ(tb.components, 1u);
  EXPECT_NEAR(tb.volume, ta.volume, 1e-9 * ta.volume);
  EXPECT_NEAR(tb.area, ta.area, 1e-9 * ta.area);
  for (const morph::FaceTag& tag : b.mesh.tags)
    if (tag.kind == PatchKind::SideSweep || tag.kind == PatchKind::FrontSweep) {
      EXPECT_EQ(tag.source, 0);
    }
}

// Two full-depth slots across a block leave three pieces; the removed volume per unit length is
// the disc of the sphere clipped to the block's height.
TEST(ErodeSphere, ThroughSlotsSplitTheBlockIntoThreePieces) {
  const double r = 3.0, h = 5.0, zc = 2.5;
  const Job job = box_job({0, 0, 0}, {30, 10, h}, sphere_tool(r),
                          {{{10, -5, zc}, {10, 15, zc}}, {{20, 15, zc}, {20, -5, zc}}}, 0.01);
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_EQ(topology.components, 3u);
  const double outside = r - zc;  // the disc pokes out by this much above and below
  const double segment =
      r * r * std::acos((r - outside) / r) - (r - outside) * std::sqrt(2 * r * outside - outside * outside);
  const double removed = 2.0 * (M_PI * r * r - 2.0 * segment) * 10.0;
  // Only the curved walls deviate from the exact surface (by at most the tolerance).
  const double wall_area = 2.0 * 10.0 * r * (2.0 * M_PI - 4.0 * std::acos(zc / r));
  EXPECT_NEAR(topology.volume, 30.0 * 10.0 * h - removed, wall_area * job.tolerance);
  expect_within_tolerance_both_ways(job, result.mesh, 1500);
}

// The paper's figures 12/13 in 3D: a trajectory (a U-shaped loop crossed by a straight pass) that
// cuts the block into six disconnected partitions; passes leave and re-enter the stock.
TEST(ErodeSphere, TrajectoryLeavesSixPartitions) {
  const Job job = box_job(
      {0, 0, 0}, {30, 20, 5}, sphere_tool(3.0),
      {{{-5, 5, 2.5}, {35, 5, 2.5}, {35, 15, 2.5}, {-5, 15, 2.5}}, {{15, -5, 2.5}, {15, 25, 2.5}}}, 0.01);
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_EQ(topology.components, 6u);
  EXPECT_LE(largest_field_error(result.mesh, morph::ErosionField(job)), job.tolerance);
}

// A path that crosses itself five times (a pentagram): every crossing trims four side sweeps
// against each other.
TEST(ErodeSphere, SelfCrossingPathIsClosedAndWithinTolerance) {
  std::vector<Vector3d> star;
  for (int k = 0; k <= 5; ++k) {
    const double a = M_PI / 2 + k * 4 * M_PI / 5;
    star.push_back({15 + 10 * std::cos(a), 15 + 10 * std::sin(a), 9.5});
  }
  const Job job = box_job({0, 0, 0}, {30, 30, 10}, sphere_tool(2.0), {star}, 0.01);
  const morph::ErodeResult result = morph::erode(job);
  const morph::TopologyReport topology = morph::topology_report(result.mesh);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_EQ(topology.components, 1u);
  expect_within_tolerance_both_ways(job, result.mesh, 1500);
}

// A pocket's outline ramped down in three laps by a long ball end: its body sweeps along the walls
// the deeper laps leave.
TEST(ErodeBallEnd, RampedPocketIsClosedWithinTolerance) {
  std::vector<Vector3d> ramp;
  for (int lap = 0; lap < 3; ++lap)
    for (const auto& [x, y] : std::vector<std::pair<double, double>>{{5, 5}, {15, 5}, {15, 15}, {5, 15}})
      ramp.push_back({x, y, -0.25 * static_cast<double>(ramp.size())});
  const Job job = box_job({0, 0, -6}, {20, 20, 0}, ballend_tool(1.27, 15.0), {ramp}, 0.01);
  expect_closed_within_tolerance(job, 1);
}

TEST(Erode, RejectsToleranceThatIsNotPositive) {
  const Job ok = box_job({0, 0, 0}, {10, 10, 10}, sphere_tool(1.0), {{{0, 0, 9}, {10, 10, 9}}}, 0.01);
  morph::ErodeOptions negative;
  negative.tolerance = -1.0;
  EXPECT_THROW(morph::erode(ok, negative), morph::InputError);
  Job zero = ok;
  zero.tolerance = 0.0;
  EXPECT_THROW(morph::erode(zero), morph::InputError);
  EXPECT_NO_THROW(morph::erode(ok));
}

}  // namespace
