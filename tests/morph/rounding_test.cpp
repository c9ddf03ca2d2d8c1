// SPDX-License-Identifier: Apache-2.0
// Generator 2's output rounding (rounding.h): a surface that needs none of its steps comes back
// as it went in, and one whose corners rounded onto a line is settled by a flip.
#include "generator/rounding.h"

#include <gtest/gtest.h>

namespace {

using Eigen::Vector3d;

// The outward normal of triangle t, as emit() gives each triangle its polygon's.
std::vector<Vector3d> outward(const morph::TriangleMesh& mesh) {
  std::vector<Vector3d> facing;
  for (const morph::Triangle& t : mesh.triangles) {
    const Vector3d &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    facing.push_back((b - a).cross(c - a).normalized());
  }
  return facing;
}

TEST(Rounding, ASoundSurfaceComesBackAsItWentIn) {
  morph::TriangleMesh tetrahedron;
  tetrahedron.vertices = {Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0), Vector3d(0, 0, 1)};
  tetrahedron.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const morph::TriangleMesh before = tetrahedron;
  const morph::RoundingCounts counts = morph::settle_rounding(tetrahedron, outward(tetrahedron));
  EXPECT_EQ(
      counts.collapsed_edges + counts.flipped_edges + counts.rerounded_vertices + counts.misoriented_left,
      0u);
  EXPECT_EQ(tetrahedron.vertices, before.vertices);
  EXPECT_EQ(tetrahedron.triangles, before.triangles);
}

TEST(Rounding, ATriangleRoundedOntoALineIsFlippedAway) {
  // p, m, q on one line: the triangle (p, q, m) has no area; its neighbour across pq, (q, p, d),
  // splits at m into two triangles that cover it exactly.
  morph::TriangleMesh mesh;
  const Vector3d p(0, 0, 0), q(2, 0, 0), m(1, 0, 0), d(1, 1, 0);
  mesh.vertices = {p, q, m, d};
  mesh.triangles = {{0, 1, 2}, {1, 0, 3}};
  const std::vector<Vector3d> facing(2, Vector3d(0, 0, -1));
  const morph::RoundingCounts counts = morph::settle_rounding(mesh, facing);
  EXPECT_EQ(counts.flipped_edges, 1u);
  EXPECT_EQ(counts.misoriented_left, 0u);
  ASSERT_EQ(mesh.triangles.size(), 2u);
  double area = 0.0;
  for (const morph::Triangle& t : mesh.triangles) {
    const Vector3d normal =
        (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    EXPECT_LT(normal.z(), 0.0);  // turning the way its polygon faces, and not flat
    area += 0.5 * normal.norm();
  }
  EXPECT_DOUBLE_EQ(area, 1.0);  // the neighbour's area: 2 × 1 / 2
}

}  // namespace
