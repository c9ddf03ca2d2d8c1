// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/topology.h>
#include <raytest/regions.h>

#include <cmath>
#include <map>
#include <utility>

#include "raytest/raytest_support.h"

namespace {

// A 10 x 10 square in z = 0 as two triangles.
morph::TriangleMesh square() {
  morph::TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.tags = {{morph::PatchKind::SideSweep, 4, 17}, {morph::PatchKind::FrontSweep, 5, 18}};
  return mesh;
}

TEST(RefineLongEdges, EdgesShortAreaKeptAndClosedMeshesStayClosed) {
  // A box whose faces are 1, 4 and 10 long: parents get different n and must still share points.
  const morph::TriangleMesh box = raytest_test::box_mesh({0, 0, 0}, {10, 4, 1}, 1);
  const raytest::RefinedMesh refined = raytest::refine_long_edges(box, 0.5);
  EXPECT_EQ(refined.max_edge, 0.5);
  EXPECT_EQ(refined.parent.size(), refined.mesh.triangle_count());
  double area = 0, longest = 0;
  for (const auto& tri : refined.mesh.triangles) {
    for (int e = 0; e < 3; ++e)
      longest =
          std::max(longest, (refined.mesh.vertices[tri[e]] - refined.mesh.vertices[tri[(e + 1) % 3]]).norm());
    area += 0.5 * (refined.mesh.vertices[tri[1]] - refined.mesh.vertices[tri[0]])
                      .cross(refined.mesh.vertices[tri[2]] - refined.mesh.vertices[tri[0]])
                      .norm();
  }
  // Lattice edges are at most 0.5; the strips that zip a lattice to a coarser neighbour's edge points
  // stretch some by up to half a coarse step each way.
  EXPECT_LE(longest, 1.5 * 0.5);
  EXPECT_NEAR(area, 2 * (10 * 4 + 10 * 1 + 4 * 1), 1e-9);
  const morph::TopologyReport topology = morph::topology_report(refined.mesh);
  EXPECT_EQ(topology.boundary_edges, 0u);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_NEAR(topology.volume, 40.0, 1e-9);
  EXPECT_THROW(raytest::refine_long_edges(box, 0.0), morph::InputError);
}

// Long slivers (a 40 x 0.3 x 0.3 bar; a square fanned from one corner, as a generator triangulates a
// face) cost their length, not its square, and stay conforming.
TEST(RefineLongEdges, SliversBecomeStripsAndStayConforming) {
  const morph::TriangleMesh bar = raytest_test::box_mesh({0, 0, 0}, {40, 0.3, 0.3}, 1);
  const raytest::RefinedMesh strips = raytest::refine_long_edges(bar, 0.5);
  // Each long face is 80 pieces long and one strip high: about 2 x 80 triangles, not 80^2 / 2.
  EXPECT_LT(strips.mesh.triangle_count(), 4u * 2u * 200u);
  const morph::TopologyReport topology = morph::topology_report(strips.mesh);
  EXPECT_TRUE(topology.closed_manifold());
  EXPECT_NEAR(topology.volume, 40 * 0.3 * 0.3, 1e-9);

  morph::TriangleMesh fan;
  fan.vertices = {{0, 0, 0}};
  for (int i = 0; i <= 25; ++i) fan.vertices.push_back({10, 0.4 * i, 0});
  for (int i = 24; i >= 0; --i) fan.vertices.push_back({0.4 * i, 10, 0});
  for (std::uint32_t v = 1; v + 1 < fan.vertices.size(); ++v) fan.triangles.push_back({0, v, v + 1});
  const raytest::RefinedMesh refined = raytest::refine_long_edges(fan, 0.25);
  // 100 square units: about 2 x 100 / 0.25^2 = 3,200 triangles (the lattice of the longest edges
  // would have been ~50 x (14.1 / 0.25)^2 = 160,000).
  EXPECT_LT(refined.mesh.triangle_count(), 8000u);
  double area = 0, longest = 0;
  for (const auto& tri : refined.mesh.triangles) {
    for (int e = 0; e < 3; ++e)
      longest =
          std::max(longest, (refined.mesh.vertices[tri[e]] - refined.mesh.vertices[tri[(e + 1) % 3]]).norm());
    const Eigen::Vector3d n = (refined.mesh.vertices[tri[1]] - refined.mesh.vertices[tri[0]])
                                  .cross(refined.mesh.vertices[tri[2]] - refined.mesh.vertices[tri[0]]);
    EXPECT_GE(n.z(), 0.0);  // the parents' winding kept
    area += 0.5 * n.norm();
  }
  EXPECT_NEAR(area, 100.0, 1e-9);
  EXPECT_LE(longest, 1.5 * 0.25);
  // Conforming: the only edges with one triangle lie on the square's outline, and they add up to it.
  const morph::TopologyReport open = morph::topology_report(refined.mesh);
  EXPECT_EQ(open.non_manifold_edges, 0u);
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> uses;
  for (const auto& tri : refined.mesh.triangles)
    for (int e = 0; e < 3; ++e)
      ++uses[{std::min(tri[e], tri[(e + 1) % 3]), std::max(tri[e], tri[(e + 1) % 3])}];
  double outline = 0;
  for (const auto& [edge, count] : uses)
    if (count == 1) {
      const Eigen::Vector3d p = refined.mesh.vertices[edge.first], q = refined.mesh.vertices[edge.second];
      const bool on_outline = (std::abs(p.x() - 10) < 1e-12 && std::abs(q.x() - 10) < 1e-12) ||
                              (std::abs(p.y() - 10) < 1e-12 && std::abs(q.y() - 10) < 1e-12) ||
                              (p.x() == 0 && q.x() == 0) || (p.y() == 0 && q.y() == 0);
      EXPECT_TRUE(on_outline) << p.transpose() << " - " << q.transpose();
      outline += (p - q).norm();
    }
  EXPECT_NEAR(outline, 40.0, 1e-9);
}

TEST(RefineLongEdges, TriangleBudgetWidensTheEdge) {
  const raytest::RefinedMesh refined = raytest::refine_long_edges(square(), 0.01, 20000);
  EXPECT_LE(refined.mesh.triangle_count(), 20000u);
  EXPECT_GT(refined.mesh.triangle_count(), 5000u);
  EXPECT_GT(refined.max_edge, 0.01);
}

TEST(FindRegions, AGougeDiscAndAnExcessStripAreOneRegionEach) {
  const raytest::RefinedMesh refined = raytest::refine_long_edges(square(), 0.05);
  const morph::TriangleMesh& mesh = refined.mesh;
  // A cone-shaped dent 1 deep of radius 1 at (3, 3); a strip x > 8 left 0.5 thick.
  std::vector<double> values(mesh.vertex_count());
  for (std::size_t v = 0; v < values.size(); ++v) {
    const Eigen::Vector3d& p = mesh.vertices[v];
    const double r = std::hypot(p.x() - 3, p.y() - 3);
    values[v] = r < 1 ? -(1 - r) : p.x() > 8 ? 0.5 : 0.0;
  }
  const raytest::ToleranceBand band{-0.1, 0.2};
  const std::vector<raytest::DeviationRegion> regions = raytest::find_regions(mesh, values, band);
  ASSERT_EQ(regions.size(), 2u);
  const raytest::DeviationRegion& gouge = regions[0];
  EXPECT_EQ(gouge.kind, raytest::DeviationClass::Gouge);
  EXPECT_NEAR(gouge.worst, -1.0, 0.05);
  EXPECT_NEAR((gouge.location - Eigen::Vector3d(3, 3, 0)).norm(), 0.0, 0.05);
  // Out of band where 1 - r > 0.1: a disc of radius 0.9.
  EXPECT_NEAR(gouge.area, M_PI * 0.81, 0.2);
  EXPECT_NEAR(gouge.bounds.min().x(), 2.1, 0.06);
  const raytest::DeviationRegion& excess = regions[1];
  EXPECT_EQ(excess.kind, raytest::DeviationClass::Excess);
  EXPECT_DOUBLE_EQ(excess.worst, 0.5);
  EXPECT_NEAR(excess.area, 2 * 10, 0.6);
  EXPECT_GT(excess.location.x(), 8.0);
  // The strip crosses both parent faces; the dent lies in the second one (below the diagonal y = x?
  // (3, 3) is on it, so both tags may appear); every source names a real tag.
  ASSERT_FALSE(excess.sources.empty());
  for (const auto& s : excess.sources) EXPECT_TRUE(s.tag.line == 17 || s.tag.line == 18);
  EXPECT_EQ(excess.sources.size(), 2u);
  EXPECT_DOUBLE_EQ(excess.sources[0].worst, 0.5);
}

TEST(FindRegions, SeparateSpotsStaySeparateAndWithinGivesNone) {
  const raytest::RefinedMesh refined = raytest::refine_long_edges(square(), 0.1);
  const morph::TriangleMesh& mesh = refined.mesh;
  std::vector<double> values(mesh.vertex_count(), 0.0);
  for (std::size_t v = 0; v < values.size(); ++v) {
    const Eigen::Vector3d& p = mesh.vertices[v];
    if ((p - Eigen::Vector3d(2, 2, 0)).norm() < 0.5) values[v] = -0.3;
    if ((p - Eigen::Vector3d(7, 7, 0)).norm() < 0.5) values[v] = -0.4;
  }
  const auto regions = raytest::find_regions(mesh, values, {-0.1, 0.1});
  ASSERT_EQ(regions.size(), 2u);
  EXPECT_EQ(regions[0].worst, -0.4);
  EXPECT_NEAR(regions[0].location.x(), 7, 0.5);
  EXPECT_EQ(regions[1].worst, -0.3);
  EXPECT_TRUE(raytest::find_regions(mesh, values, {-1, 1}).empty());
  EXPECT_THROW(raytest::find_regions(mesh, {0.0}, {-1, 1}), morph::InputError);
}

}  // namespace
