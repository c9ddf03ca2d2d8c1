// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/mesh.h>
#include <morph/mesh_distance.h>

#include <random>

using Eigen::Vector3d;

namespace {
// Unit cube [0,1]^3, 12 outward triangles.
morph::TriangleMesh cube() {
  morph::TriangleMesh m;
  for (int i = 0; i < 8; ++i) m.vertices.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}
}  // namespace

TEST(Mesh, CubeVolumeAreaAndAppend) {
  morph::TriangleMesh m = cube();
  EXPECT_NEAR(morph::enclosed_volume(m), 1.0, 1e-15);
  EXPECT_NEAR(morph::surface_area(m), 6.0, 1e-15);
  morph::TriangleMesh two = m;
  two.append(m);
  EXPECT_EQ(two.vertex_count(), 16u);
  EXPECT_EQ(two.triangles.back()[0], m.triangles.back()[0] + 8);
  EXPECT_NEAR(morph::enclosed_volume(two), 2.0, 1e-15);
}

TEST(Mesh, ValidateNamesTheProblem) {
  morph::TriangleMesh m = cube();
  m.triangles.push_back({0, 1, 99});
  try {
    m.validate("part.ply");
    FAIL() << "expected InputError";
  } catch (const morph::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("part.ply: triangle 12 refers to vertex 99"), std::string::npos)
        << e.what();
  }
}

TEST(MeshDistance, CubeSignedDistanceIsExactIncludingEdgesAndCorners) {
  const morph::MeshDistance distance(cube());
  auto exact = [](const Vector3d& p) {
    const Vector3d d = (-p).cwiseMax(p - Vector3d::Ones());
    return d.cwiseMax(0.0).norm() + std::min(d.maxCoeff(), 0.0);
  };
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 2.0);
  for (int k = 0; k < 2000; ++k) {
    const Vector3d p(u(rng), u(rng), u(rng));
    EXPECT_NEAR(distance.signed_distance(p), exact(p), 1e-12) << p.transpose();
  }
  // Exactly diagonal from an edge and a corner, where a face normal alone would give the wrong sign.
  EXPECT_NEAR(distance.signed_distance(Vector3d(1.5, 1.5, 0.5)), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(distance.signed_distance(Vector3d(-1, -1, -1)), std::sqrt(3.0), 1e-12);
}
