// SPDX-License-Identifier: Apache-2.0
// The exact self-intersection test against meshes whose crossings are known by construction:
// what triangles share by index is not a crossing, what they share beyond it is.
#include <gtest/gtest.h>
#include <morphmill/self_intersections.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <stdexcept>

#include "common/test_meshes.h"

namespace {

using morph::TriangleMesh;
using morphmill::find_self_intersections;
using morphmill_test::box;
using morphmill_test::torus;

TriangleMesh two_triangles(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                           const Eigen::Vector3d& d, const std::array<std::uint32_t, 3>& second) {
  TriangleMesh mesh;
  mesh.vertices = {a, b, c, d};
  mesh.triangles = {{0, 1, 2}, second};
  return mesh;
}

// Laid in the plane x + y + z = 0 by an integer map, exactly for dyadic coordinates (so that
// coplanar stays coplanar): the 3D predicates decide, not the axis-plane shortcut.
TriangleMesh tilted(TriangleMesh mesh) {
  for (Eigen::Vector3d& v : mesh.vertices)
    v = v.x() * Eigen::Vector3d(1, -1, 0) + v.y() * Eigen::Vector3d(1, 1, -2) +
        v.z() * Eigen::Vector3d(1, 1, 1);
  return mesh;
}

// Rotated off every axis; coplanar points stop being exactly coplanar, so only answers that do
// not hang on coplanarity are asked of it.
TriangleMesh rotated(TriangleMesh mesh) {
  const Eigen::Matrix3d turn =
      (Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix());
  for (Eigen::Vector3d& v : mesh.vertices) v = turn * v;
  return mesh;
}

TEST(SelfIntersections, ClosedSolidsHaveNone) {
  EXPECT_EQ(find_self_intersections(box({0, 0, 0}, {1, 2, 3})).pairs, 0u);
  EXPECT_EQ(find_self_intersections(torus(3.0, 1.0, 48, 16)).pairs, 0u);
  EXPECT_EQ(find_self_intersections(rotated(torus(3.0, 1.0, 48, 16))).pairs, 0u);
}

// Two triangles on a common edge 0-1, the second's apex at d.
TEST(SelfIntersections, ACommonEdgeCrossesOnlyWhenFoldedFlat) {
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 0), c(1, 1, 0);
  for (int view = 0; view < 3; ++view) {
    auto count = [&](const Eigen::Vector3d& d) {
      TriangleMesh mesh = two_triangles(a, b, c, d, {1, 0, 3});
      return find_self_intersections(view == 0 ? mesh : view == 1 ? tilted(mesh) : rotated(mesh)).pairs;
    };
    EXPECT_EQ(count({1, -1, 0}), 0u) << "flat, unfolded, view " << view;
    EXPECT_EQ(count({1, -1, 0.5}), 0u) << "bent, view " << view;
    EXPECT_EQ(count({1, 0.5, 0.5}), 0u) << "bent over the first, view " << view;
    if (view == 2) continue;
    EXPECT_EQ(count({1, 0.5, 0}), 1u) << "folded flat onto the first, view " << view;
    EXPECT_EQ(count({5, 3, 0}), 1u) << "folded flat, reaching past the first, view " << view;
  }
}

// Two triangles on a common vertex 0.
TEST(SelfIntersections, ACommonVertexCrossesOnlyWhenTheyOverlapBeyondIt) {
  for (int view = 0; view < 3; ++view) {
    auto count = [&](const Eigen::Vector3d& c, const Eigen::Vector3d& d, const Eigen::Vector3d& e) {
      TriangleMesh mesh;
      mesh.vertices = {{0, 0, 0}, {2, 0, 0}, c, d, e};
      mesh.triangles = {{0, 1, 2}, {0, 3, 4}};
      return find_self_intersections(view == 0 ? mesh : view == 1 ? tilted(mesh) : rotated(mesh)).pairs;
    };
    EXPECT_EQ(count({0, 2, 0}, {-2, 0, 0}, {0, -2, 0}), 0u) << "flat, opposite quadrants, view " << view;
    EXPECT_EQ(count({0, 2, 0}, {1, 1, 1}, {1, 1, -1}), 1u) << "piercing through the first, view " << view;
    EXPECT_EQ(count({0, 2, 0}, {1, 1, 1}, {2, 2, 1}), 0u) << "above the first, view " << view;
    if (view == 2) continue;
    EXPECT_EQ(count({0, 2, 0}, {1, 0.25, 0}, {0.25, 1, 0}), 1u) << "flat, inside the first, view " << view;
    EXPECT_EQ(count({0, 2, 0}, {-1, 1, 0}, {1, 1, 0}), 1u) << "flat, overlapping a wedge, view " << view;
  }
}

// Two triangles (0, 1, 2) and (0, 3, 4) of integer points in a plane meet beyond their common
// corner 0 exactly when a corner other than 0 of one lies in the other, or an edge of each
// crosses, away from corner 0: the corners of their common part other than 0 are such points.
// Decided here in integers (exact for these small coordinates), without the test's own geometry.
bool meet_beyond_corner_0(const std::array<std::array<long, 2>, 5>& x) {
  auto orientation = [&](int a, int b, int c) {
    const long value = (x[b][0] - x[a][0]) * (x[c][1] - x[a][1]) - (x[b][1] - x[a][1]) * (x[c][0] - x[a][0]);
    return (value > 0) - (value < 0);
  };
  auto in_triangle = [&](int p, int a, int b, int c) {  // closed
    const int o = orientation(a, b, c);
    return orientation(a, b, p) * o >= 0 && orientation(b, c, p) * o >= 0 && orientation(c, a, p) * o >= 0;
  };
  auto between = [&](int p, int a, int b) {  // p on the closed segment a-b, given collinear
    return std::min(x[a][0], x[b][0]) <= x[p][0] && x[p][0] <= std::max(x[a][0], x[b][0]) &&
           std::min(x[a][1], x[b][1]) <= x[p][1] && x[p][1] <= std::max(x[a][1], x[b][1]);
  };
  auto segments_meet = [&](int a, int b, int c, int d) {  // closed segments
    const int o1 = orientation(a, b, c), o2 = orientation(a, b, d), o3 = orientation(c, d, a),
              o4 = orientation(c, d, b);
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    return (o1 == 0 && between(c, a, b)) || (o2 == 0 && between(d, a, b)) || (o3 == 0 && between(a, c, d)) ||
           (o4 == 0 && between(b, c, d));
  };
  if (in_triangle(1, 0, 3, 4) || in_triangle(2, 0, 3, 4) || in_triangle(3, 0, 1, 2) ||
      in_triangle(4, 0, 1, 2))
    return true;
  // Edges from corner 0 meet only there, unless they overlap along one ray (then the shorter's
  // far corner lies in the other triangle, found above). Every other pair of edges meets away
  // from corner 0 if at all: corner 0 lies on no edge opposite it in a proper triangle.
  const std::array<std::array<int, 2>, 3> first{{{0, 1}, {1, 2}, {2, 0}}}, second{{{0, 3}, {3, 4}, {4, 0}}};
  for (const auto& e : first)
    for (const auto& f : second) {
      if ((e[0] == 0 || e[1] == 0) && (f[0] == 0 || f[1] == 0)) continue;
      if (segments_meet(e[0], e[1], f[0], f[1])) return true;
    }
  return false;
}

// Every configuration of small integer corners (collinear rays, corners on the other's edges,
// nested and touching cones), flat in the xy-plane and tilted out of it, against that count.
TEST(SelfIntersections, ACommonVertexCrossesExactlyWhereTheirCornersAndEdgesSay) {
  std::mt19937 random(7);
  std::uniform_int_distribution<long> coordinate(-2, 2);
  int meeting = 0, apart = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    std::array<std::array<long, 2>, 5> x;
    for (auto& p : x) p = {coordinate(random), coordinate(random)};
    auto cross = [&](int a, int b, int c) {
      return (x[b][0] - x[a][0]) * (x[c][1] - x[a][1]) - (x[b][1] - x[a][1]) * (x[c][0] - x[a][0]);
    };
    if (cross(0, 1, 2) == 0 || cross(0, 3, 4) == 0) continue;  // proper triangles only
    const bool expected = meet_beyond_corner_0(x);
    (expected ? meeting : apart)++;
    TriangleMesh mesh;
    for (const auto& p : x) mesh.vertices.emplace_back(double(p[0]), double(p[1]), 0.0);
    mesh.triangles = {{0, 1, 2}, {0, 3, 4}};
    EXPECT_EQ(find_self_intersections(mesh).pairs, expected ? 1u : 0u) << "flat, trial " << trial;
    EXPECT_EQ(find_self_intersections(tilted(mesh)).pairs, expected ? 1u : 0u) << "tilted, trial " << trial;
  }
  EXPECT_GT(meeting, 500);
  EXPECT_GT(apart, 500);
}

TEST(SelfIntersections, DisjointIndicesCrossWhereverTheyMeet) {
  for (int view = 0; view < 2; ++view) {
    auto count = [&](double lift) {
      TriangleMesh mesh;
      mesh.vertices = {{0, 0, 0},   {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, -1 + lift}, {0.5, 0.5, 1 + lift},
                       {3, 3, lift}};
      mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
      return find_self_intersections(view == 0 ? mesh : tilted(mesh)).pairs;
    };
    EXPECT_EQ(count(0.0), 1u) << "crossing, view " << view;
    EXPECT_EQ(count(1.0), 1u) << "touching at a vertex, view " << view;
    EXPECT_EQ(count(1.5), 0u) << "above, view " << view;
  }
  // A duplicated vertex is not a shared one: coincident points of different indices touch.
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {-1, 0, 0}, {0, -1, 0}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  EXPECT_EQ(find_self_intersections(mesh).pairs, 1u);
}

// Two unit cubes, the second moved by (0.5, 0.5, 0.5): a closed manifold made of two closed
// manifolds, whose crossings are pairs of one face of each, where the faces cross.
TEST(SelfIntersections, OverlappingShellsAreFoundPairByPair) {
  TriangleMesh mesh = box({0, 0, 0}, {1, 1, 1});
  mesh.append(box({0.5, 0.5, 0.5}, {1.5, 1.5, 1.5}));
  const morphmill::SelfIntersections found = find_self_intersections(mesh, 1000);
  EXPECT_GT(found.pairs, 0u);
  ASSERT_EQ(found.first_pairs.size(), found.pairs);
  for (const auto& [i, j] : found.first_pairs) {
    EXPECT_LT(i, 12u);
    EXPECT_GE(j, 12u);
  }
  // The same pairs on one thread.
  EXPECT_EQ(find_self_intersections(mesh, 1000, false).first_pairs, found.first_pairs);
  // Apart, nothing.
  for (std::size_t v = 8; v < mesh.vertices.size(); ++v) mesh.vertices[v] += Eigen::Vector3d(3, 0, 0);
  EXPECT_EQ(find_self_intersections(mesh).pairs, 0u);
}

TEST(SelfIntersections, FirstPairsAreTheSmallestAndCountsAgreeAcrossThreads) {
  TriangleMesh mesh = torus(3.0, 1.0, 64, 24);
  // The same torus stood up in the xz-plane: its core circle passes through the first's core
  // circle at (+-3, 0, 0), so the two tubes cross there.
  TriangleMesh ring = torus(3.0, 1.0, 64, 24);
  for (Eigen::Vector3d& v : ring.vertices) v = Eigen::Vector3d(v.x(), v.z(), v.y());
  mesh.append(ring);
  const morphmill::SelfIntersections threaded = find_self_intersections(mesh, 5, true);
  const morphmill::SelfIntersections single = find_self_intersections(mesh, 5, false);
  EXPECT_GT(threaded.pairs, 0u);
  EXPECT_EQ(threaded.pairs, single.pairs);
  EXPECT_EQ(threaded.first_pairs, single.first_pairs);
  ASSERT_EQ(threaded.first_pairs.size(), 5u);
  EXPECT_TRUE(std::is_sorted(threaded.first_pairs.begin(), threaded.first_pairs.end()));
}

TEST(SelfIntersections, CollapsedTrianglesAreLeftOutAndBadIndicesRefused) {
  TriangleMesh mesh = box({0, 0, 0}, {1, 1, 1});
  mesh.triangles.push_back({0, 0, 1});
  mesh.vertices.push_back({0.5, 0.5, 0.5});
  mesh.vertices.push_back({0.6, 0.6, 0.6});
  mesh.vertices.push_back({0.7, 0.7, 0.7});
  mesh.triangles.push_back({8, 9, 10});  // collinear: no area, no crossing
  EXPECT_EQ(find_self_intersections(mesh).pairs, 0u);
  mesh.triangles.push_back({0, 1, 99});
  EXPECT_THROW(find_self_intersections(mesh), std::invalid_argument);
}

}  // namespace
