// SPDX-License-Identifier: Apache-2.0
// Topology report against meshes whose counts are known in closed form.
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/topology.h>

#include <cmath>
#include <numeric>

#include "common/test_meshes.h"

namespace {

using morph::Triangle;
using morph::TriangleMesh;
using morphmill_test::box;
using morphmill_test::torus;

constexpr double kPi = 3.14159265358979323846;

TriangleMesh unit_cube() {
  return box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
}

// The unit cube and the cube (1,1,1)-(2,2,2), the second's corner (1,1,1) (its vertex 0) welded
// to the first cube's vertex 7: 15 vertices, 24 triangles.
TriangleMesh cubes_welded_at_a_corner() {
  TriangleMesh mesh = unit_cube();
  const TriangleMesh other = box({1, 1, 1}, {2, 2, 2});
  for (std::size_t i = 1; i < 8; ++i) mesh.vertices.push_back(other.vertices[i]);
  for (const Triangle& t : other.triangles) {
    Triangle w;
    for (int k = 0; k < 3; ++k) w[k] = t[k] == 0 ? 7 : t[k] + 7;
    mesh.triangles.push_back(w);
  }
  return mesh;
}

// Corner tetrahedron (0,0,0), e_x, e_y, e_z wound outward: volume 1/6.
TriangleMesh tetrahedron() {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  mesh.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return mesh;
}

TEST(Topology, Tetrahedron) {
  const morph::TopologyReport r = morph::topology_report(tetrahedron());
  EXPECT_EQ(r.vertices, 4u);
  EXPECT_EQ(r.triangles, 4u);
  EXPECT_EQ(r.edges, 6u);
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_EQ(r.non_manifold_vertices, 0u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_NEAR(r.volume, 1.0 / 6.0, 1e-15);
  EXPECT_NEAR(r.area, 1.5 + std::sqrt(3.0) / 2.0, 1e-14);
  EXPECT_TRUE(r.closed_manifold());
}

TEST(Topology, Cube) {
  const morph::TopologyReport r = morph::topology_report(box({-1, 2, 3}, {1, 5, 7}));
  EXPECT_EQ(r.vertices, 8u);
  EXPECT_EQ(r.unreferenced_vertices, 0u);
  EXPECT_EQ(r.triangles, 12u);
  EXPECT_EQ(r.degenerate_triangles, 0u);
  EXPECT_EQ(r.edges, 18u);
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_NEAR(r.volume, 2.0 * 3.0 * 4.0, 1e-13);
  EXPECT_NEAR(r.area, 2 * (6.0 + 8.0 + 12.0), 1e-13);
  EXPECT_TRUE(r.closed_manifold());
}

TEST(Topology, TwoDisjointCubes) {
  TriangleMesh mesh = unit_cube();
  mesh.append(box({3, 0, 0}, {5, 2, 2}));
  const morph::TopologyReport r = morph::topology_report(mesh);
  EXPECT_EQ(r.vertices, 16u);
  EXPECT_EQ(r.edges, 36u);
  EXPECT_EQ(r.components, 2u);
  EXPECT_EQ(r.euler_characteristic, 4);
  EXPECT_NEAR(r.volume, 1.0 + 8.0, 1e-13);
  EXPECT_TRUE(r.closed_manifold());
}

TEST(Topology, ComponentsAreNumberedBySmallestTriangle) {
  // Interleave the triangles of two cubes so the second cube owns triangle 0.
  const TriangleMesh a = unit_cube();
  const TriangleMesh b = box({3, 0, 0}, {4, 1, 1});
  TriangleMesh mesh;
  mesh.vertices = a.vertices;
  mesh.vertices.insert(mesh.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (std::size_t t = 0; t < 12; ++t) {
    const Triangle& tb = b.triangles[t];
    mesh.triangles.push_back({tb[0] + 8, tb[1] + 8, tb[2] + 8});
    mesh.triangles.push_back(a.triangles[t]);
  }
  std::vector<std::uint32_t> component;
  ASSERT_EQ(morph::connected_components(mesh, component), 2u);
  ASSERT_EQ(component.size(), 24u);
  for (std::size_t t = 0; t < 24; ++t) EXPECT_EQ(component[t], t % 2 == 0 ? 0u : 1u) << "triangle " << t;
}

TEST(Topology, TorusHasEulerCharacteristicZero) {
  const double R = 3.0, r = 1.0;
  const int n = 40, m = 12;
  const TriangleMesh mesh = torus(R, r, n, m);
  const morph::TopologyReport report = morph::topology_report(mesh);
  EXPECT_EQ(report.vertices, std::size_t(n * m));
  EXPECT_EQ(report.triangles, std::size_t(2 * n * m));
  EXPECT_EQ(report.edges, std::size_t(3 * n * m));
  EXPECT_EQ(report.euler_characteristic, 0);
  EXPECT_EQ(report.components, 1u);
  EXPECT_TRUE(report.closed_manifold());
  const double exact = n * std::sin(2 * kPi / n) * R * 0.5 * m * r * r * std::sin(2 * kPi / m);
  EXPECT_NEAR(report.volume, exact, 1e-12 * exact);
}

TEST(Topology, OpenBoxHasBoundary) {
  TriangleMesh mesh = unit_cube();
  mesh.triangles.erase(mesh.triangles.begin() + 2, mesh.triangles.begin() + 4);  // the +z face
  const morph::TopologyReport r = morph::topology_report(mesh);
  EXPECT_EQ(r.triangles, 10u);
  EXPECT_EQ(r.edges, 17u);  // the removed face's diagonal is gone
  EXPECT_EQ(r.boundary_edges, 4u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.non_manifold_vertices, 0u);  // rim vertices are half-discs
  EXPECT_EQ(r.inconsistent_edges, 0u);
  EXPECT_EQ(r.euler_characteristic, 1);  // a disc
  EXPECT_FALSE(r.closed_manifold());
}

TEST(Topology, FlippedFaceIsInconsistent) {
  TriangleMesh mesh = unit_cube();
  std::swap(mesh.triangles[5][1], mesh.triangles[5][2]);
  const morph::TopologyReport r = morph::topology_report(mesh);
  EXPECT_EQ(r.inconsistent_edges, 3u);
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_FALSE(r.closed_manifold());
  // Relative to the cube's centre every triangle spans a tetrahedron of volume
  // (1/2 * 1/2) / 3 = 1/12; the flipped one counts negatively.
  EXPECT_NEAR(r.volume, 1.0 - 2.0 / 12.0, 1e-14);
}

TEST(Topology, ThreeTrianglesOnOneEdge) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  const morph::TopologyReport r = morph::topology_report(mesh);
  EXPECT_EQ(r.edges, 7u);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_EQ(r.boundary_edges, 6u);
  EXPECT_EQ(r.inconsistent_edges, 0u);     // not counted on a non-manifold edge
  EXPECT_EQ(r.non_manifold_vertices, 2u);  // both ends of the fin edge
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 5 - 7 + 3);
  EXPECT_FALSE(r.closed_manifold());
}

TEST(Topology, BowTieVertex) {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 3, 4}};
  const morph::TopologyReport r = morph::topology_report(mesh);
  EXPECT_EQ(r.non_manifold_vertices, 1u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.boundary_edges, 6u);
  EXPECT_EQ(r.components, 2u);  // edge-connected: a shared vertex does not join them
  EXPECT_EQ(r.euler_characteristic, 1);
  EXPECT_NEAR(r.area, 1.0, 1e-15);
}

TEST(Topology, TwoCubesTouchingAtACornerMakeANonManifoldVertex) {
  const TriangleMesh mesh = cubes_welded_at_a_corner();
  const morph::TopologyReport r = morph::topology_report(mesh);
  EXPECT_EQ(r.vertices, 15u);
  EXPECT_EQ(r.non_manifold_vertices, 1u);
  EXPECT_EQ(r.boundary_edges, 0u);
  EXPECT_EQ(r.non_manifold_edges, 0u);
  EXPECT_EQ(r.components, 2u);
  EXPECT_EQ(r.euler_characteristic, 15 - 36 + 24);
  EXPECT_FALSE(r.closed_manifold());
  // The pinch itself: the shared corner, and only it.
  EXPECT_EQ(morph::non_manifold_vertices(mesh), std::vector<std::uint32_t>{7});
  EXPECT_TRUE(morph::non_manifold_vertices(unit_cube()).empty());
}

TEST(Topology, NonManifoldVerticesAmongSomeAreThoseOfAllAmongThem) {
  TriangleMesh mesh = unit_cube();
  TriangleMesh other = box({1, 1, 1}, {2, 2, 2});
  for (std::size_t i = 1; i < 8; ++i) mesh.vertices.push_back(other.vertices[i]);
  for (const Triangle& t : other.triangles) {
    Triangle w;
    for (int k = 0; k < 3; ++k) w[k] = t[k] == 0 ? 7 : t[k] + 7;
    mesh.triangles.push_back(w);
  }
  mesh.triangles.push_back({3, 3, 0});  // collapsed: left out as in the full search
  EXPECT_EQ(morph::non_manifold_vertices(mesh, {0, 3, 7, 14}), std::vector<std::uint32_t>{7});
  EXPECT_TRUE(morph::non_manifold_vertices(mesh, {0, 6, 8, 14}).empty());  // the pinch not asked about
  EXPECT_TRUE(morph::non_manifold_vertices(mesh, {}).empty());
  // Every vertex asked about: the full search's answer.
  std::vector<std::uint32_t> every(mesh.vertices.size());
  std::iota(every.begin(), every.end(), 0u);
  EXPECT_EQ(morph::non_manifold_vertices(mesh, every), morph::non_manifold_vertices(mesh));
  EXPECT_THROW(morph::non_manifold_vertices(mesh, {15}), morph::InputError);
}

TEST(Topology, DegenerateTrianglesAndUnreferencedVertices) {
  TriangleMesh mesh = tetrahedron();
  mesh.vertices.push_back({5, 5, 5});      // 4: unreferenced
  mesh.vertices.push_back({0.5, 0.5, 0});  // 5: on the edge 1-2, referenced only by a sliver
  mesh.vertices.push_back({9, 9, 9});      // 6: unreferenced
  mesh.triangles.push_back({1, 2, 5});     // zero area, distinct indices
  mesh.triangles.push_back({3, 3, 0});     // repeated index
  const morph::TopologyReport r = morph::topology_report(mesh);
  EXPECT_EQ(r.triangles, 6u);
  EXPECT_EQ(r.degenerate_triangles, 2u);
  EXPECT_EQ(r.vertices, 5u);
  EXPECT_EQ(r.unreferenced_vertices, 2u);
  // The sliver adds edges 2-5 and 5-1 (boundary) and makes 1-2 non-manifold; the collapsed
  // triangle takes no part in edges.
  EXPECT_EQ(r.edges, 8u);
  EXPECT_EQ(r.boundary_edges, 2u);
  EXPECT_EQ(r.non_manifold_edges, 1u);
  EXPECT_EQ(r.non_manifold_vertices, 2u);  // 1 and 2; the sliver's apex 5 is a half-disc
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 5 - 8 + 5);
  EXPECT_NEAR(r.volume, 1.0 / 6.0, 1e-15);
}

TEST(Topology, EmptyMesh) {
  const morph::TopologyReport r = morph::topology_report(TriangleMesh{});
  EXPECT_EQ(r.triangles, 0u);
  EXPECT_EQ(r.components, 0u);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_FALSE(r.closed_manifold());
}

TEST(Topology, IndexOutOfRangeIsAnInputError) {
  TriangleMesh mesh = tetrahedron();
  mesh.triangles.push_back({0, 1, 9});
  EXPECT_THROW(morph::topology_report(mesh), morph::InputError);
}

}  // namespace

namespace {

// A torus and a cube, apart: genus 1 and 0 piece by piece, whatever the whole mesh's sum says.
TEST(TopologyPieces, GenusOfEachPiece) {
  TriangleMesh mesh = torus(3.0, 1.0, 24, 12);
  mesh.append(box({10, 10, 10}, {11, 11, 11}));
  const morph::TopologyReport r = morph::topology_report(mesh);
  ASSERT_EQ(r.pieces.size(), 2u);
  EXPECT_EQ(r.pieces[0].triangles, 24u * 12u * 2u);
  EXPECT_EQ(r.pieces[0].euler_characteristic, 0);
  EXPECT_TRUE(r.pieces[0].closed_manifold);
  EXPECT_EQ(r.pieces[0].genus, 1);
  EXPECT_EQ(r.pieces[1].triangles, 12u);
  EXPECT_EQ(r.pieces[1].euler_characteristic, 2);
  EXPECT_EQ(r.pieces[1].genus, 0);
  EXPECT_EQ(r.euler_characteristic, 2);
}

// Two cubes welded at one corner: each piece counts the shared vertex, and neither is a closed
// manifold (the pinch belongs to both).
TEST(TopologyPieces, APinchSpoilsBothPieces) {
  const morph::TopologyReport r = morph::topology_report(cubes_welded_at_a_corner());
  ASSERT_EQ(r.pieces.size(), 2u);
  for (const morph::PieceTopology& piece : r.pieces) {
    EXPECT_EQ(piece.euler_characteristic, 8 - 18 + 12);
    EXPECT_FALSE(piece.closed_manifold);
    EXPECT_EQ(piece.genus, -1);
  }
}

TEST(TopologyPieces, AnOpenPieceHasNoGenus) {
  TriangleMesh mesh = unit_cube();
  mesh.triangles.pop_back();
  mesh.append(unit_cube());
  for (std::size_t i = 8; i < mesh.vertices.size(); ++i) mesh.vertices[i].x() += 5.0;
  const morph::TopologyReport r = morph::topology_report(mesh);
  ASSERT_EQ(r.pieces.size(), 2u);
  EXPECT_FALSE(r.pieces[0].closed_manifold);
  EXPECT_EQ(r.pieces[0].genus, -1);
  EXPECT_EQ(r.pieces[0].euler_characteristic, 8 - 18 + 11);
  EXPECT_TRUE(r.pieces[1].closed_manifold);
  EXPECT_EQ(r.pieces[1].genus, 0);
}

}  // namespace
