// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>
#include <morph/mesh_distance.h>
#include <raytest/sampling.h>

#include <cmath>

#include "raytest/raytest_support.h"

namespace {

TEST(Sampling, CountsKindsAndPositionsOnTheSourceTriangle) {
  const morph::TriangleMesh mesh = raytest_test::uv_sphere(1.0, 10, 20);
  raytest::SamplingOptions options;
  options.edge_samples = 500;
  options.face_samples = 2000;
  const std::vector<raytest::SurfaceSample> samples = raytest::sample_surface(mesh, options);
  ASSERT_EQ(samples.size(), mesh.vertices.size() + 500 + 2000);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const raytest::SurfaceSample& s = samples[i];
    const raytest::SampleKind expected = i < mesh.vertices.size()         ? raytest::SampleKind::Vertex
                                         : i < mesh.vertices.size() + 500 ? raytest::SampleKind::Edge
                                                                          : raytest::SampleKind::Face;
    ASSERT_EQ(s.kind, expected);
    const morph::Triangle& tri = mesh.triangles[s.triangle];
    const Eigen::Vector3d q = morph::closest_point_on_triangle(s.position, mesh.vertices[tri[0]],
                                                               mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
    ASSERT_LT((q - s.position).norm(), 1e-14) << "sample " << i;
    ASSERT_NEAR(s.normal.norm(), 1.0, 1e-12);
    // On a sphere centred at the origin every pseudo-normal points outward.
    ASSERT_GT(s.normal.dot(s.position), 0.0);
  }
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) EXPECT_EQ(samples[v].position, mesh.vertices[v]);
}

TEST(Sampling, FaceSamplesAreAreaUniform) {
  // Two triangles of areas 1 and 3: a quarter of the samples land on the first.
  morph::TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {10, 0, 0}, {16, 0, 0}, {10, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
  raytest::SamplingOptions options;
  options.vertices = false;
  options.face_samples = 40000;
  const auto samples = raytest::sample_surface(mesh, options);
  std::size_t first = 0;
  double mean_x = 0;
  for (const auto& s : samples) {
    if (s.triangle == 0) {
      ++first;
      mean_x += s.position.x();
    }
  }
  mean_x /= static_cast<double>(first);
  // Binomial: sd = sqrt(n p (1-p)) ~ 87; 5 sd.
  EXPECT_NEAR(static_cast<double>(first), 10000.0, 440.0);
  // Uniform over the triangle: the mean is the centroid (2/3); its sd ~ 0.0047 here.
  EXPECT_NEAR(mean_x, 2.0 / 3.0, 0.025);
}

TEST(Sampling, CentroidsComeLastOnePerTriangle) {
  morph::TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {3, 0, 0}, {0, 3, 0}, {3, 3, 3}};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
  raytest::SamplingOptions options;
  options.face_samples = 7;
  options.centroids = true;
  const auto samples = raytest::sample_surface(mesh, options);
  ASSERT_EQ(samples.size(), 4u + 7u + 2u);
  const raytest::SurfaceSample& first = samples[11];
  const raytest::SurfaceSample& second = samples[12];
  EXPECT_EQ(first.triangle, 0u);
  EXPECT_EQ(second.triangle, 1u);
  EXPECT_LT((first.position - Eigen::Vector3d(1, 1, 0)).norm(), 1e-15);
  EXPECT_LT((second.position - Eigen::Vector3d(2, 2, 1)).norm(), 1e-15);
  EXPECT_NEAR(first.normal.z(), 1.0, 1e-15);
}

TEST(Sampling, SameSeedSameSamplesOtherSeedOtherSamples) {
  const morph::TriangleMesh mesh = raytest_test::uv_sphere(1.0, 8, 16);
  raytest::SamplingOptions options;
  options.edge_samples = 100;
  options.face_samples = 300;
  options.seed = 42;
  const auto first = raytest::sample_surface(mesh, options);
  const auto second = raytest::sample_surface(mesh, options);
  ASSERT_EQ(first.size(), second.size());
  for (std::size_t i = 0; i < first.size(); ++i) {
    ASSERT_EQ(first[i].position, second[i].position);
    ASSERT_EQ(first[i].triangle, second[i].triangle);
  }
  options.seed = 43;
  const auto third = raytest::sample_surface(mesh, options);
  EXPECT_NE(first.back().position, third.back().position);
}

TEST(Sampling, VertexNormalsOfACubeCornerPointAlongTheDiagonal) {
  const morph::TriangleMesh cube =
      raytest_test::box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 1);
  EXPECT_GT(morph::enclosed_volume(cube), 0.999);
  const auto normals = raytest::angle_weighted_vertex_normals(cube);
  for (std::size_t v = 0; v < cube.vertices.size(); ++v) {
    const Eigen::Vector3d expected = (cube.vertices[v] - Eigen::Vector3d::Constant(0.5)).normalized();
    EXPECT_LT((normals[v] - expected).norm(), 1e-12) << v;
  }
}

}  // namespace
