// SPDX-License-Identifier: Apache-2.0
// The level-set reference against closed-form truth: removed volumes and areas of straight
// sphere and ball-end passes, smooth internal voids (a diagonal capsule and a torus from an arc),
// surface distance to the exact erosion field, and piece counts of jobs that split.
#include <gtest/gtest.h>
#include <morph/sweep_distance.h>
#include <vdb_ref/reference.h>

#include <algorithm>
#include <cmath>
#include <iostream>

#include "vdb_ref/job_builders.h"

namespace {

using namespace vdb_ref_test;
using Eigen::Vector3d;

constexpr double kRelativeTolerance = 0.005;  // the acceptance: 0.5 %

vdb_ref::ReferenceResult run(const morph::Job& job, double voxel) {
  vdb_ref::ReferenceOptions options;
  options.voxel_size = voxel;
  return vdb_ref::compute_reference(job, options);
}

// The stock alone at the same voxel: subtracting it isolates what the tool removed, so the
// stock's own sharp box edges (rounded by any level set) do not hide the removal's error.
morph::Job stock_only(const morph::Job& job) {
  morph::Job copy = job;
  copy.paths.clear();
  return copy;
}

void expect_relative(double measured, double exact, double tolerance, const std::string& what) {
  std::cout << "  " << what << ": measured " << measured << ", exact " << exact << ", relative error "
            << (measured - exact) / exact << '\n';
  EXPECT_LE(std::abs(measured - exact), tolerance * std::abs(exact)) << what;
}

// Distance of mesh vertices to the exact erosion boundary, skipping vertices within `margin` of a
// crease: a crease is where two of {box faces, sweep surface} meet, so a vertex is skipped when
// the second nearest of those surfaces is within `margin`.
struct SurfaceError {
  double max = 0.0, rms = 0.0;
  std::size_t measured = 0, skipped = 0;
};

SurfaceError surface_error(const morph::Job& job, const morph::TriangleMesh& mesh, double margin) {
  const morph::ErosionField field(job);
  const Eigen::AlignedBox3d box = job.stock.box;
  SurfaceError e;
  double sum = 0.0;
  for (const Vector3d& v : mesh.vertices) {
    std::vector<double> near;
    for (int a = 0; a < 3; ++a) {
      near.push_back(std::abs(v[a] - box.min()[a]));
      near.push_back(std::abs(box.max()[a] - v[a]));
    }
    near.push_back(std::abs(field.sweep_distance(v)));
    std::sort(near.begin(), near.end());
    if (near[1] < margin) {
      ++e.skipped;
      continue;
    }
    const double d = std::abs(field.value(v));
    e.max = std::max(e.max, d);
    sum += d * d;
    ++e.measured;
  }
  e.rms = e.measured ? std::sqrt(sum / e.measured) : 0.0;
  return e;
}

void expect_surface_within_half_voxel(const morph::Job& job, const vdb_ref::ReferenceResult& result,
                                      double voxel) {
  const SurfaceError e = surface_error(job, result.mesh, 2.0 * voxel);
  std::cout << "  surface error away from creases: max " << e.max << " (" << e.max / voxel << " voxel), rms "
            << e.rms << " (" << e.rms / voxel << " voxel) over " << e.measured << " vertices, " << e.skipped
            << " skipped near creases\n";
  EXPECT_GT(e.measured, result.mesh.vertex_count() / 2);
  EXPECT_LE(e.max, 0.5 * voxel);
}

// A box in general position with respect to the voxel grid (no face on a voxel centre).
const Vector3d kCorner(0.13, 0.21, 0.07);
constexpr double kLength = 60.0, kWidth = 40.0, kHeight = 20.0;

morph::Job general_box_job() {
  return box_job(kCorner, kCorner + Vector3d(kLength, kWidth, kHeight));
}

// Checks a pass that cuts a groove of constant cross-section `section` (area) along the whole box
// (x), changing the box's area by `added_area`:
// - volume at voxel r/10, and the removed volume (stock alone minus result, at the same voxel, so
//   that the box's own edges cancel), within 0.5 %;
// - area: OpenVDB's volume-to-mesh (a dual method) and the level-set measure cut every sharp edge
//   by about a voxel, an error linear in the voxel size. The test checks that linear convergence
//   (the error at r/20 is about half that at r/10) and that the Richardson extrapolation
//   2 A(r/20) - A(r/10), which cancels the linear term, is within 0.5 %;
// - the surface within half a voxel of the exact one away from creases.
void check_groove(const morph::Job& job, double r, double section, double added_area) {
  const double voxel = r / 10.0;
  const vdb_ref::ReferenceResult result = run(job, voxel);
  const vdb_ref::ReferenceResult fine = run(job, voxel / 2.0);
  const vdb_ref::ReferenceResult stock = run(stock_only(job), voxel);
  const double removed_volume = section * kLength;
  const double volume = kLength * kWidth * kHeight - removed_volume;
  const double area = 2.0 * (kLength * kWidth + kWidth * kHeight + kHeight * kLength) + added_area;
  ASSERT_EQ(result.pieces.size(), 1u);
  ASSERT_EQ(fine.pieces.size(), 1u);
  expect_relative(result.volume(), volume, kRelativeTolerance, "volume at r/10");
  expect_relative(stock.volume() - result.volume(), removed_volume, kRelativeTolerance,
                  "removed volume at r/10");
  expect_relative(fine.volume(), volume, kRelativeTolerance, "volume at r/20");
  const double error = result.area() - area, fine_error = fine.area() - area;
  std::cout << "  area: r/10 " << result.area() << " (" << error / area << "), r/20 " << fine.area() << " ("
            << fine_error / area << "), exact " << area << '\n';
  EXPECT_LT(error, 0.0);
  EXPECT_NEAR(error / fine_error, 2.0, 0.5) << "linear convergence of the edge error";
  expect_relative(2.0 * fine.area() - result.area(), area, kRelativeTolerance,
                  "area extrapolated from r/10, r/20");
  expect_surface_within_half_voxel(job, result, voxel);
  expect_relative(morph::enclosed_volume(result.mesh), volume, 0.01, "volume enclosed by the output mesh");
}

TEST(ReferenceClosedForm, SpherePassAcrossBoxTopFace) {
  // A sphere of radius r whose lowest point is d below the top face cuts a groove whose section
  // is a circular segment of height d, along the whole box and beyond its ends (no end caps).
  const double r = 5.0, d = 3.0;
  morph::Job job = general_box_job();
  add_tool(job, 1, morph::ToolType::Sphere, r);
  const double z = kCorner.z() + kHeight + r - d, y = kCorner.y() + kWidth / 2;
  add_path(job, {line(Vector3d(kCorner.x() - 10, y, z), Vector3d(kCorner.x() + kLength + 10, y, z), 1, 7)});
  const double section = circular_segment_area(r, d);
  const double chord = 2.0 * std::sqrt(2.0 * r * d - d * d);
  // The top face loses the chord-wide strip, the groove adds its arc, the two end faces lose the
  // section.
  check_groove(job, r, section, (circular_segment_arc(r, d) - chord) * kLength - 2.0 * section);
}

TEST(ReferenceClosedForm, BallEndSlotDeeperThanItsRadius) {
  // Tip 1.5 r below the top face: the groove is a half disc below the hemisphere's centre plus a
  // rectangle 2r wide up to the top face; the body above leaves the box.
  const double r = 5.0, depth = 7.5;
  morph::Job job = general_box_job();
  add_tool(job, 3, morph::ToolType::BallEnd, r, 20.0);
  const double z = kCorner.z() + kHeight - depth, y = kCorner.y() + kWidth / 2;
  add_path(job, {line(Vector3d(kCorner.x() - 10, y, z), Vector3d(kCorner.x() + kLength + 10, y, z), 3, 12)});
  const double wall = depth - r;
  const double section = 0.5 * M_PI * r * r + 2.0 * r * wall;
  check_groove(job, r, section, (M_PI * r + 2.0 * wall - 2.0 * r) * kLength - 2.0 * section);
}

TEST(ReferenceClosedForm, DiagonalCapsuleVoidInsideTheBox) {
  // A sphere moving diagonally inside the box removes a capsule-shaped void: a smooth surface
  // with closed-form volume and area, and a long diagonal move exercises the sparse culling.
  const double r = 3.0;
  morph::Job job = box_job(Vector3d(0, 0, 0), Vector3d(40, 30, 20));
  add_tool(job, 1, morph::ToolType::Sphere, r);
  const Vector3d a(8, 7, 6), b(32, 23, 14);
  add_path(job, {line(a, b, 1, 1)});
  const double voxel = r / 10.0;
  const vdb_ref::ReferenceResult result = run(job, voxel);
  const vdb_ref::ReferenceResult stock = run(stock_only(job), voxel);

  const double L = (b - a).norm();
  const double void_volume = M_PI * r * r * L + 4.0 / 3.0 * M_PI * r * r * r;
  const double void_area = 2.0 * M_PI * r * L + 4.0 * M_PI * r * r;
  ASSERT_EQ(result.pieces.size(), 1u);
  EXPECT_EQ(result.pieces[0].cavities, 1);
  expect_relative(stock.volume() - result.volume(), void_volume, kRelativeTolerance, "void volume");
  expect_relative(result.area() - stock.area(), void_area, kRelativeTolerance, "void area");
  expect_relative(result.volume(), 40.0 * 30 * 20 - void_volume, kRelativeTolerance, "volume");
  expect_surface_within_half_voxel(job, result, voxel);
}

TEST(ReferenceClosedForm, FullCircleArcCarvesATorus) {
  // A sphere of radius r along a full circle of radius R inside the box: a torus-shaped void of
  // volume 2 pi^2 R r^2 and area 4 pi^2 R r.
  const double r = 3.0, R = 10.0;
  morph::Job job = box_job(Vector3d(0, 0, 0), Vector3d(40, 40, 20));
  add_tool(job, 1, morph::ToolType::Sphere, r);
  morph::Move arc;
  arc.kind = morph::MoveKind::Arc;
  arc.center = Vector3d(20, 20, 10);
  arc.start = arc.end = Vector3d(20 + R, 20, 10);
  arc.axis = Vector3d::UnitZ();
  arc.sweep = 2.0 * M_PI;
  arc.tool = 1;
  arc.line = 4;
  add_path(job, {arc});
  const double voxel = r / 10.0;
  const vdb_ref::ReferenceResult result = run(job, voxel);
  const vdb_ref::ReferenceResult stock = run(stock_only(job), voxel);
  ASSERT_EQ(result.pieces.size(), 1u);
  EXPECT_EQ(result.pieces[0].cavities, 1);
  expect_relative(stock.volume() - result.volume(), 2.0 * M_PI * M_PI * R * r * r, kRelativeTolerance,
                  "torus volume");
  expect_relative(result.area() - stock.area(), 4.0 * M_PI * M_PI * R * r, kRelativeTolerance, "torus area");
  expect_surface_within_half_voxel(job, result, voxel);
}

TEST(ReferencePieces, TwoThroughSlotsWithASphereLeaveThreePieces) {
  // Box 100 x 60 x 20; a sphere of radius 12 centred at mid-height runs across the whole width at
  // x = 100/3 and 200/3. Each slot removes, per unit of width, the disc slice |u| <= 10.
  const double r = 12.0, height = 20.0, width = 60.0;
  morph::Job job = box_job(Vector3d(0, 0, 0), Vector3d(100, width, height));
  add_tool(job, 1, morph::ToolType::Sphere, r);
  for (double x : {100.0 / 3.0, 200.0 / 3.0})
    add_path(job, {line(Vector3d(x, -20, 10), Vector3d(x, 80, 10), 1, 1)});
  const vdb_ref::ReferenceResult result = run(job, 0.5);
  ASSERT_EQ(result.pieces.size(), 3u);
  const double half_slot = 0.5 * disc_slice_area(r, -10.0, 10.0);
  const double end_piece = (100.0 / 3.0 * height - half_slot) * width;
  const double middle_piece = (100.0 / 3.0 * height - 2.0 * half_slot) * width;
  expect_relative(result.pieces[0].volume, end_piece, kRelativeTolerance, "end piece");
  expect_relative(result.pieces[1].volume, end_piece, kRelativeTolerance, "end piece");
  expect_relative(result.pieces[2].volume, middle_piece, kRelativeTolerance, "middle piece");
  // The middle piece lies between the slots.
  EXPECT_GT(result.pieces[2].bounds.min().x(), 100.0 / 3.0);
  EXPECT_LT(result.pieces[2].bounds.max().x(), 200.0 / 3.0);
}

TEST(ReferencePieces, ThreeBallEndThroughSlotsLeaveFourPieces) {
  // Ball end of radius 5 with its tip 2 below the bottom: the slot's section inside the box is
  // the disc slice below the hemisphere's centre (u in [-3, 0]) plus a 10 x 17 rectangle.
  const double r = 5.0, height = 20.0, width = 60.0;
  morph::Job job = box_job(Vector3d(0, 0, 0), Vector3d(100, width, height));
  add_tool(job, 2, morph::ToolType::BallEnd, r, 30.0);
  add_path(job, {line(Vector3d(25, -20, -2), Vector3d(25, 80, -2), 2, 1),
                 line(Vector3d(25, 80, -2), Vector3d(50, 80, 30), 2, 2),  // leaves the box above
                 line(Vector3d(50, 80, -2), Vector3d(50, -20, -2), 2, 3)});
  add_path(job, {line(Vector3d(75, -20, -2), Vector3d(75, 80, -2), 2, 1)});
  const vdb_ref::ReferenceResult result = run(job, 0.5);
  ASSERT_EQ(result.pieces.size(), 4u);
  const double half_slot = 0.5 * (disc_slice_area(r, -3.0, 0.0) + 2.0 * r * (height - 3.0));
  const double end_piece = (25.0 * height - half_slot) * width;
  const double middle_piece = (25.0 * height - 2.0 * half_slot) * width;
  for (int i = 0; i < 2; ++i)
    expect_relative(result.pieces[i].volume, end_piece, kRelativeTolerance, "end piece");
  for (int i = 2; i < 4; ++i)
    expect_relative(result.pieces[i].volume, middle_piece, kRelativeTolerance, "middle piece");
}

}  // namespace
