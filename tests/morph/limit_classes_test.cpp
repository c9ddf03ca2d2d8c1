// SPDX-License-Identifier: Apache-2.0
// The limit step's classes of one exact point: plane triples through one point are one class,
// represented by the smallest vertex, whatever the order and the threads.
#include <gtest/gtest.h>

#include "generator/limit_classes.h"

namespace {

using Eigen::Vector3d;

morph::ExactPlane plane(const Vector3d& normal, double offset, std::uint64_t rank) {
  return morph::ExactPlane{normal, offset, rank, 1};
}

TEST(LimitClasses, TriplesThroughOnePointAreOneClass) {
  const morph::ExactPlane x0 = plane({1, 0, 0}, 0, 1), y0 = plane({0, 1, 0}, 0, 2),
                          z0 = plane({0, 0, 1}, 0, 3), diagonal = plane({1, 1, 1}, 0, 4),
                          x1 = plane({1, 0, 0}, 1, 5), near = plane({1, 1, 1}, 1e-12, 6);
  // The origin three times; (1, 0, 0), (1, 0, -1) and a point 1e-12 above the origin each alone.
  // The table of planes and each vertex's triple in it.
  morph::VertexPlanes vertices;
  vertices.planes = {x0, y0, z0, diagonal, x1, near};
  vertices.triples = {{1, 2, 4}, {0, 1, 2}, {0, 1, 3}, {1, 3, 4}, {1, 2, 3}, {0, 1, 5}};
  for (morph::ExecutionPolicy policy :
       {morph::ExecutionPolicy::Sequential, morph::ExecutionPolicy::Parallel}) {
    const std::vector<std::uint32_t> root = morph::limit_classes(vertices, policy);
    ASSERT_EQ(root.size(), vertices.size());
    EXPECT_EQ(root, (std::vector<std::uint32_t>{0, 1, 1, 3, 1, 5}));
  }
}

}  // namespace
