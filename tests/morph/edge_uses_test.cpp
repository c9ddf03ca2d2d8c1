// SPDX-License-Identifier: Apache-2.0
// The generator's private edge bookkeeping (morph/src/mesh/edge_uses.h) and its large arrays
// (morph/src/mesh/huge_pages.h), against meshes whose edges and components are known.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "common/test_meshes.h"
#include "mesh/edge_uses.h"
#include "mesh/huge_pages.h"

namespace {

using morph::Triangle;
using morph::TriangleMesh;
using morph::detail::EdgeUse;

bool same_uses(const std::vector<EdgeUse>& a, const std::vector<EdgeUse>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].key != b[i].key || a[i].triangle != b[i].triangle || a[i].corner != b[i].corner ||
        a[i].forward != b[i].forward)
      return false;
  return true;
}

TEST(EdgeUses, CubeHasTwelveTrianglesAndEighteenEdgesEachUsedOnceEachWay) {
  const TriangleMesh cube = morphmill_test::box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  const std::vector<EdgeUse> uses = morph::detail::sorted_edge_uses(cube);
  ASSERT_EQ(uses.size(), 3 * cube.triangles.size());
  std::size_t edges = 0;
  for (std::size_t i = 0; i < uses.size(); i += 2) {
    ASSERT_EQ(uses[i].key, uses[i + 1].key);
    EXPECT_NE(uses[i].forward, uses[i + 1].forward);
    if (i + 2 < uses.size()) {
      EXPECT_LT(uses[i].key, uses[i + 2].key);
    }
    ++edges;
  }
  EXPECT_EQ(edges, 18u);  // 12 cube edges and 6 face diagonals
}

TEST(EdgeUses, ReusedStorageGivesTheSameUsesAsAFreshVector) {
  const TriangleMesh small = morphmill_test::box(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones());
  const TriangleMesh torus = morphmill_test::torus(3.0, 1.0, 40, 20);
  std::vector<EdgeUse> reused;
  morph::detail::sorted_edge_uses(torus, reused);  // larger first: the storage shrinks in use
  EXPECT_TRUE(same_uses(reused, morph::detail::sorted_edge_uses(torus)));
  morph::detail::sorted_edge_uses(small, reused);
  EXPECT_TRUE(same_uses(reused, morph::detail::sorted_edge_uses(small)));
  EXPECT_EQ(reused.size(), 3 * small.triangles.size());
}

TEST(EdgeUses, ComponentsJoinAtSharedEdgesOnlyAndAreNumberedBySmallestTriangle) {
  TriangleMesh mesh;
  mesh.vertices.assign(9, Eigen::Vector3d::Zero());
  mesh.triangles = {
      {4, 5, 6},  // 0: alone but for the vertex it shares with 3
      {0, 1, 2},  // 1
      {2, 1, 3},  // 2: shares edge 1-2 with 1
      {6, 7, 8},  // 3: shares only vertex 6 with 0
      {3, 3, 1},  // 4: collapsed, still has the edge 1-3 it shares with 2
      {7, 7, 7},  // 5: collapsed to a point: no edge with two ends
  };
  std::vector<std::uint32_t> component;
  const std::size_t count = morph::detail::components_of_uses(
      mesh.triangles.size(), morph::detail::sorted_edge_uses(mesh), component);
  EXPECT_EQ(count, 4u);
  EXPECT_EQ(component, (std::vector<std::uint32_t>{0, 1, 1, 2, 1, 3}));
}

TEST(HugePages, LargeVectorHoldsItsValuesAndReserveKeepsTheElements) {
  constexpr std::size_t kCount = 3u << 20;  // 12 MiB of uint32: several huge pages
  std::vector<std::uint32_t> v = morph::detail::large_vector<std::uint32_t>(kCount, 7u);
  ASSERT_EQ(v.size(), kCount);
  EXPECT_EQ(v.front(), 7u);
  EXPECT_EQ(v.back(), 7u);
  for (std::size_t i = 0; i < kCount; ++i) v[i] = static_cast<std::uint32_t>(i);
  morph::detail::reserve_large(v, 2 * kCount);
  EXPECT_GE(v.capacity(), 2 * kCount);
  ASSERT_EQ(v.size(), kCount);
  bool kept = true;
  for (std::size_t i = 0; i < kCount; ++i) kept = kept && v[i] == i;
  EXPECT_TRUE(kept);
  // A smaller reservation changes nothing.
  const std::uint32_t* data = v.data();
  morph::detail::reserve_large(v, 10);
  EXPECT_EQ(v.data(), data);
}

}  // namespace
