// SPDX-License-Identifier: Apache-2.0
// Face provenance of the reference against a brute-force evaluation of its rule with morph's exact
// sweep distances: every face is tagged with the move whose sweep is nearest its centroid (the
// earliest of moves tied within 1e-9) when that sweep is within the centroid's stock distance.
#include <gtest/gtest.h>
#include <morph/stock.h>
#include <morph/sweep_distance.h>
#include <vdb_ref/reference.h>

#include <cmath>

#include "vdb_ref/job_builders.h"

namespace {

using namespace vdb_ref_test;
using Eigen::Vector3d;

// A ball-end raster of consecutive moves (they tie where they meet), a plunge, a ramp that leaves
// the stock, and a quarter arc.
morph::Job raster_job() {
  morph::Job job = box_job(Vector3d(0, 0, 0), Vector3d(30, 20, 10));
  add_tool(job, 1, morph::ToolType::BallEnd, 2.0, 15.0);
  std::vector<morph::Move> moves;
  int line_number = 10;
  Vector3d at(-3, 4, 8);
  for (const Vector3d& next :
       {Vector3d(12, 4, 7), Vector3d(27, 4, 7.5), Vector3d(27, 7, 7.5), Vector3d(-3, 7, 6.5),
        Vector3d(15, 12, 6.5), Vector3d(15, 12, 3), Vector3d(25, 16, 12)}) {
    moves.push_back(line(at, next, 1, line_number));
    line_number += 10;
    at = next;
  }
  morph::Move arc;
  arc.kind = morph::MoveKind::Arc;
  arc.center = Vector3d(8, 15, 7);
  arc.start = Vector3d(13, 15, 7);
  arc.end = Vector3d(8, 20, 7);
  arc.axis = Vector3d::UnitZ();
  arc.sweep = M_PI / 2;
  arc.tool = 1;
  arc.line = line_number;
  moves.push_back(arc);
  add_path(job, moves);
  return job;
}

TEST(ReferenceFaceTags, NearestMoveWithinTheStockDistanceEarliestOfTies) {
  const morph::Job job = raster_job();
  vdb_ref::ReferenceOptions options;
  options.voxel_size = 0.5;
  const vdb_ref::ReferenceResult result = vdb_ref::compute_reference(job, options);
  const std::vector<const morph::Move*> moves = job.moves();
  ASSERT_EQ(result.mesh.tags.size(), result.mesh.triangle_count());
  std::size_t swept = 0, stock_faces = 0, ties = 0, checked = 0;
  std::vector<std::size_t> faces_per_move(moves.size(), 0);
  for (std::size_t t = 0; t < result.mesh.triangle_count(); ++t) {
    const auto& tri = result.mesh.triangles[t];
    const Vector3d c =
        (result.mesh.vertices[tri[0]] + result.mesh.vertices[tri[1]] + result.mesh.vertices[tri[2]]) / 3;
    std::vector<double> distance(moves.size());
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < moves.size(); ++i) {
      distance[i] = morph::swept_signed_distance(job.tool_of(*moves[i]), *moves[i], c);
      nearest = std::min(nearest, distance[i]);
    }
    int expected = -1;
    int within_tie = 0;
    for (std::size_t i = 0; i < moves.size(); ++i) {
      if (distance[i] <= nearest + 1e-9) {
        if (expected < 0) expected = static_cast<int>(i);
        ++within_tie;
      }
      // A move just at the edge of the tie window may fall either side by rounding: skip.
      if (std::abs(distance[i] - (nearest + 1e-9)) < 1e-11) expected = -2;
    }
    const double stock = std::abs(morph::analytic_signed_distance(job.stock, c));
    if (expected == -2 || std::abs(std::abs(nearest) - stock) < 1e-9) continue;
    ++checked;
    if (within_tie > 1) ++ties;
    const morph::FaceTag& tag = result.mesh.tags[t];
    EXPECT_EQ(tag.kind, morph::PatchKind::Reference);
    if (std::abs(nearest) <= stock) {
      ASSERT_EQ(tag.source, expected) << "face " << t << " at " << c.transpose();
      EXPECT_EQ(tag.line, moves[static_cast<std::size_t>(expected)]->line);
      ++faces_per_move[static_cast<std::size_t>(expected)];
      ++swept;
    } else {
      ASSERT_EQ(tag.source, -1) << "face " << t << " at " << c.transpose();
      EXPECT_EQ(tag.line, 0);
      ++stock_faces;
    }
  }
  EXPECT_GT(checked, result.mesh.triangle_count() * 99 / 100);
  EXPECT_GT(swept, 1000u);
  EXPECT_GT(stock_faces, 1000u);
  EXPECT_GT(ties, 10u) << "the raster's junctions were exercised";
  // Every move cuts the stock, so every move owns faces.
  for (std::size_t i = 0; i < moves.size(); ++i) EXPECT_GT(faces_per_move[i], 0u) << "move " << i;
}

TEST(ReferenceFaceTags, ManyMovesGiveTheSameResultWithAndWithoutThreads) {
  // Many sweeps per leaf node and ties between moves: the sampling order and the tie rule must not
  // depend on the threads.
  const morph::Job job = raster_job();
  vdb_ref::ReferenceOptions threaded;
  threaded.voxel_size = 0.4;
  vdb_ref::ReferenceOptions sequential = threaded;
  sequential.threaded = false;
  const vdb_ref::ReferenceResult a = vdb_ref::compute_reference(job, threaded);
  const vdb_ref::ReferenceResult b = vdb_ref::compute_reference(job, sequential);
  EXPECT_TRUE(a.mesh.vertices == b.mesh.vertices);
  EXPECT_TRUE(a.mesh.triangles == b.mesh.triangles);
  EXPECT_TRUE(a.mesh.tags == b.mesh.tags);
  EXPECT_EQ(a.volume(), b.volume());
  EXPECT_EQ(a.area(), b.area());
}

}  // namespace
