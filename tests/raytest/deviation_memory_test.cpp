// SPDX-License-Identifier: Apache-2.0
// The deviation memory estimate's bookkeeping: what it counts for each option. (Its agreement with
// measured peaks is tested on the binary, tests/apps/deviation_estimate_test.cpp.)
#include <gtest/gtest.h>
#include <raytest/deviation_memory.h>

#include <stdexcept>

#include "common/test_meshes.h"

namespace {

TEST(DeviationMemory, CountsEverySampleKind) {
  const morph::TriangleMesh torus = morphmill_test::torus(10.0, 2.0, 40, 10);  // 400 vertices, 800 triangles
  raytest::SamplingOptions sampling;
  sampling.vertices = true;
  sampling.edge_samples = 7;
  sampling.face_samples = 11;
  EXPECT_EQ(raytest::sample_count(torus, sampling), 400u + 7u + 11u);
  sampling.centroids = true;
  EXPECT_EQ(raytest::sample_count(torus, sampling), 400u + 800u + 7u + 11u);
  sampling.vertices = false;
  sampling.centroids = false;
  EXPECT_EQ(raytest::sample_count(torus, sampling), 18u);
}

TEST(DeviationMemory, TwoSidesIndexAndSampleBothMeshes) {
  const morph::TriangleMesh a = morphmill_test::torus(10.0, 2.0, 40, 10);
  const morph::TriangleMesh b = morphmill_test::torus(10.0, 2.1, 80, 10);
  raytest::DeviationWork work;
  work.a = &a;
  work.b = &b;
  work.sampling.face_samples = 1000;
  work.two_sided = false;
  const raytest::DeviationMemory one = raytest::estimate_deviation_memory(work);
  work.two_sided = true;
  const raytest::DeviationMemory two = raytest::estimate_deviation_memory(work);
  EXPECT_EQ(one.meshes, two.meshes);  // both meshes are read either way
  // Index: B alone (1600 triangles) against A and B (2400); samples: A's against A's and B's.
  EXPECT_DOUBLE_EQ(two.indexes / one.indexes, 2400.0 / 1600.0);
  EXPECT_DOUBLE_EQ(two.samples / one.samples, (1400.0 + 1800.0) / 1400.0);
  EXPECT_EQ(one.pictures, 0.0);
  EXPECT_DOUBLE_EQ(two.total(), two.meshes + two.indexes + two.samples);
}

TEST(DeviationMemory, PicturesCostPerTriangleOfAAndPerPixel) {
  const morph::TriangleMesh a = morphmill_test::torus(10.0, 2.0, 40, 10);
  raytest::DeviationWork work;
  work.a = &a;
  work.b = &a;
  work.vertex_values = true;
  const double values = raytest::estimate_deviation_memory(work).pictures;
  EXPECT_GT(values, 0.0);
  work.picture_pixels = 1000;
  const double small = raytest::estimate_deviation_memory(work).pictures;
  work.picture_pixels = 2000;
  const double large = raytest::estimate_deviation_memory(work).pictures;
  work.picture_pixels = 3000;
  const double larger = raytest::estimate_deviation_memory(work).pictures;
  EXPECT_GT(small, values);  // a picture adds its render scene and pixels to the per-vertex values
  EXPECT_GT(large, small);
  EXPECT_DOUBLE_EQ(larger - large, large - small);  // linear in the pixels
  work.b = nullptr;
  EXPECT_THROW(raytest::estimate_deviation_memory(work), std::invalid_argument);
}

}  // namespace
