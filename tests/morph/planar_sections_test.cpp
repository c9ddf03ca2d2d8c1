// SPDX-License-Identifier: Apache-2.0
// The tie between the planar model and the 3D generator: a ball-end tool's body above its tip
// hemisphere is a vertical cylinder, so for level moves at tip height z0 the 3D result's section at
// any height z0 + r < z < stock top is the planar erosion by a disc of radius r. This test cuts the
// generator's surface (morph::erode) with horizontal planes, with its own slicing, and measures the
// section against morph::planar::erode: a test of the 3D generator that shares none of its code.
#include <gtest/gtest.h>
#include <morph/erode.h>
#include <morph/planar_deviation.h>
#include <morph/planar_erosion.h>

#include <cmath>

#include "common/planar_shapes.h"
#include "common/test_tools.h"

namespace {

using Eigen::Vector3d;
using morph::planar::Vec2;

/// The segments where the plane z = h cuts the mesh, each directed with the material on its left
/// (from the triangle's outward normal), as one unordered "loop": crossing parity and the shoelace
/// sum do not need the segments chained.
morph::planar::Region section(const morph::TriangleMesh& mesh, double h) {
  morph::planar::Loop cut;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    Vec2 ends[2];
    int n = 0;
    for (int k = 0; k < 3 && n < 2; ++k) {
      const Vector3d& a = mesh.vertices[tri[k]];
      const Vector3d& b = mesh.vertices[tri[(k + 1) % 3]];
      // A vertex exactly on the plane counts as above it, so each crossing is found once.
      const bool a_above = a.z() >= h, b_above = b.z() >= h;
      if (a_above == b_above) continue;
      const double s = (h - a.z()) / (b.z() - a.z());
      ends[n++] = Vec2(a.x() + s * (b.x() - a.x()), a.y() + s * (b.y() - a.y()));
    }
    if (n != 2 || ends[0] == ends[1]) continue;
    const Vector3d normal = morph::face_normal(mesh, t);
    const Vec2 along(-normal.y(), normal.x());  // material (against the normal) on the left
    if ((ends[1] - ends[0]).dot(along) < 0.0) std::swap(ends[0], ends[1]);
    const auto& tag = mesh.tags[t];
    cut.curves.push_back(morph::planar::make_segment(
        ends[0], ends[1],
        {tag.kind == morph::PatchKind::StockFace || tag.kind == morph::PatchKind::CutSurface
             ? morph::planar::Origin::Stock
             : morph::planar::Origin::Sweep,
         tag.source, tag.line}));
  }
  morph::planar::Region region;
  region.loops.push_back(cut);
  return region;
}

morph::Move level_move(const Vector3d& a, const Vector3d& b, int line) {
  morph::Move m;
  m.kind = morph::MoveKind::Linear;
  m.start = a;
  m.end = b;
  m.tool = 1;
  m.line = line;
  return m;
}

/// A 40 x 30 x 10 block and a 2 mm ball end with its tip at z = 4: a slot entering from outside, a
/// right turn, a half-circle arc move and a stub up to y = 26, all level; `retrace` adds a move back
/// down the stub.
morph::Job sections_job(bool retrace) {
  const double z0 = 4.0;
  morph::Job job;
  job.stock.type = morph::StockType::Box;
  job.stock.box = Eigen::AlignedBox3d(Vector3d(0, 0, 0), Vector3d(40, 30, 10));
  job.tools[1] = morphmill_test::ballend_tool(2.0, 20.0);
  job.tolerance = 0.01;
  morph::Path path;
  path.moves.push_back(level_move({-5, 22, z0}, {18, 22, z0}, 1));
  path.moves.push_back(level_move({18, 22, z0}, {18, 10, z0}, 2));
  morph::Move arc = level_move({18, 10, z0}, {30, 10, z0}, 3);
  arc.kind = morph::MoveKind::Arc;
  arc.center = Vector3d(24, 10, z0);
  arc.axis = Vector3d::UnitZ();
  arc.sweep = M_PI;  // counter-clockwise about +z from (18, 10): through (24, 4)
  path.moves.push_back(arc);
  path.moves.push_back(level_move({30, 10, z0}, {30, 26, z0}, 4));
  if (retrace) path.moves.push_back(level_move({30, 26, z0}, {30, 18, z0}, 5));
  job.paths.push_back(path);
  return job;
}

/// Cuts the generator's surface at heights above the tip hemisphere and measures each section against
/// the planar erosion by the body's radius.
void expect_sections_match(const morph::Job& job) {
  const double r = job.tools.at(1).radius, z0 = 4.0;
  const morph::ErodeResult solid = morph::erode(job);
  // The planar job: the block's outline, the moves' XY motion, the disc of the body's radius.
  const morph::planar::Region stock = morphmill_test::rectangle(0, 0, 40, 30);
  const auto moves = morph::planar::planar_trajectory(job.moves(), z0 + 1e-9);
  ASSERT_EQ(moves.size(), job.move_count());
  const auto exact = morph::planar::erode(stock, moves, r);
  EXPECT_EQ(exact.region.pieces.size(), 1u);
  for (const double z : {6.5, 8.0, 9.5}) {
    SCOPED_TRACE("section at z = " + std::to_string(z));
    const morph::planar::Region cut = section(solid.mesh, z);
    ASSERT_FALSE(cut.loops[0].curves.empty());
    const auto deviation = morph::planar::planar_deviation(exact.region, cut);
    // The generator's surface is within its tolerance of the exact one; the section's segments are
    // chords of its triangles.
    EXPECT_LE(deviation.hausdorff(), job.tolerance);
    EXPECT_NEAR(morph::planar::area(cut), morph::planar::area(exact.region),
                job.tolerance * morph::planar::perimeter(exact.region));
  }
  // Below the tip hemisphere's equator the section is narrower than the disc: the test can fail.
  const auto low = morph::planar::planar_deviation(exact.region, section(solid.mesh, z0 + 0.5));
  EXPECT_GT(low.hausdorff(), 10.0 * job.tolerance);
}

}  // namespace

TEST(PlanarSections, BallEndSectionsAboveTheTipAreThePlanarErosion) {
  expect_sections_match(sections_job(false));
}

// Found by this test, left for the generator (issue 23's closing note): with the stub retraced, every
// section has 16 units more side-sweep boundary than the exact one (the walls x = 28 and x = 32
// between y = 18 and 26 are the length of both; the retracing move's coincident side sweeps are
// the suspects), all within the tolerance of the exact boundary (the Hausdorff check passes), and
// the section's oriented area is 15.97 short of the exact 935.177. Enable when that is fixed.
TEST(PlanarSections, DISABLED_RetracedMoveSectionsAreThePlanarErosion) {
  expect_sections_match(sections_job(true));
}
