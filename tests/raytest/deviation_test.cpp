// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <raytest/deviation.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numeric>

#include "raytest/raytest_support.h"

namespace {

using raytest_test::box_mesh;
using raytest_test::scaled;
using raytest_test::uv_sphere;

TEST(DeviationStats, KnownDataGiveClosedFormStatistics) {
  std::vector<double> values(100);
  std::iota(values.begin(), values.end(), 1.0);  // 1..100
  values.push_back(std::numeric_limits<double>::quiet_NaN());
  raytest::StatsOptions options;
  options.histogram_bins = 10;
  options.tolerance = 10.0;
  const raytest::DeviationStats s = raytest::compute_stats(values, options);
  EXPECT_EQ(s.count, 100u);
  EXPECT_EQ(s.misses, 1u);
  EXPECT_EQ(s.min, 1.0);
  EXPECT_EQ(s.max, 100.0);
  EXPECT_DOUBLE_EQ(s.mean, 50.5);
  EXPECT_DOUBLE_EQ(s.rms, std::sqrt(338350.0 / 100.0));  // sum of k^2 = n(n+1)(2n+1)/6
  EXPECT_DOUBLE_EQ(s.p50, 50.5);
  EXPECT_DOUBLE_EQ(s.p90, 1 + 0.9 * 99);
  EXPECT_DOUBLE_EQ(s.p99, 1 + 0.99 * 99);
  EXPECT_DOUBLE_EQ(s.p999, 1 + 0.999 * 99);
  EXPECT_DOUBLE_EQ(s.share_within_tolerance, 0.1);
  ASSERT_EQ(s.histogram.edges.size(), 11u);
  ASSERT_EQ(s.histogram.counts.size(), 10u);
  EXPECT_DOUBLE_EQ(s.histogram.edges[1], 1 + 9.9);
  // Bins of width 9.9 from 1: [1, 10.9) holds 1..10, ..., the last (closed) bin [90.1, 100] 91..100.
  for (std::size_t count : s.histogram.counts) EXPECT_EQ(count, 10u);
  EXPECT_EQ(std::accumulate(s.histogram.counts.begin(), s.histogram.counts.end(), std::size_t{0}), 100u);
}

TEST(DeviationStats, SignedValuesUseMagnitudesForPercentiles) {
  const raytest::DeviationStats s = raytest::compute_stats({-4.0, 1.0, 2.0, -3.0});
  EXPECT_EQ(s.min, -4.0);
  EXPECT_EQ(s.max, 2.0);
  EXPECT_DOUBLE_EQ(s.mean, -1.0);
  EXPECT_DOUBLE_EQ(s.mean_abs, 2.5);
  EXPECT_EQ(s.max_abs, 4.0);
  EXPECT_DOUBLE_EQ(s.p50, 2.5);
  EXPECT_EQ(raytest::compute_stats({}).count, 0u);
}

TEST(Deviation, ScaledSphereTwoSided) {
  const double r = 1.0;
  const morph::TriangleMesh a = uv_sphere(r, 40, 80);
  const morph::TriangleMesh b = scaled(a, 1.01);
  raytest::DeviationOptions options;
  options.sampling.face_samples = 5000;
  options.mode = raytest::DeviationMode::Signed;
  const raytest::TwoSidedDeviation d = raytest::measure_two_sided(a, b, options);
  // B -> A: vertices exactly 0.01 r outside A; face samples of B are nearer (chords bend in).
  const std::size_t nv = b.vertices.size();
  for (std::size_t i = 0; i < nv; ++i) ASSERT_NEAR(d.b_to_a.values[i], 0.01 * r, 1e-9 * 0.01 * r);
  for (std::size_t i = nv; i < d.b_to_a.values.size(); ++i) {
    ASSERT_GT(d.b_to_a.values[i], 0.0);
    ASSERT_LE(d.b_to_a.values[i], 0.01 * r * (1 + 1e-9));
  }
  // A lies inside B everywhere.
  EXPECT_LT(d.a_to_b.stats.max, 0.0);
  EXPECT_NEAR(d.b_to_a.stats.max, 0.01 * r, 1e-9 * 0.01 * r);
  EXPECT_NEAR(d.hausdorff, std::max(d.a_to_b.stats.max_abs, d.b_to_a.stats.max_abs), 0.0);
  EXPECT_GE(d.hausdorff, 0.01 * r * (1 - 1e-9));
  EXPECT_EQ(d.a_to_b.stats.count, a.vertices.size() + 5000);
  EXPECT_TRUE(d.a_to_b.groups.empty());  // untagged meshes
}

TEST(Deviation, RayModeBetweenNestedCubesHasClosedFormHits) {
  // Face samples of the inner cube [-0.5, 0.5]^3 hit the outer cube [-1, 1]^3 at 0.5 along their
  // normals, inside it (negative); corners hit the outer corners at 0.5 sqrt(3).
  const morph::TriangleMesh inner =
      box_mesh(Eigen::Vector3d::Constant(-0.5), Eigen::Vector3d::Constant(0.5), 2);
  const raytest::SurfaceQuery outer(box_mesh(Eigen::Vector3d::Constant(-1), Eigen::Vector3d::Constant(1), 2));
  raytest::DeviationOptions options;
  options.mode = raytest::DeviationMode::Ray;
  options.sampling.vertices = false;
  options.sampling.face_samples = 3000;
  const raytest::OneSidedDeviation faces = raytest::measure_one_sided(inner, outer, options);
  EXPECT_EQ(faces.stats.count, 3000u);
  EXPECT_EQ(faces.stats.misses, 0u);
  EXPECT_NEAR(faces.stats.min, -0.5, 1e-12);
  EXPECT_NEAR(faces.stats.max, -0.5, 1e-12);

  std::vector<raytest::SurfaceSample> corners;
  for (int c = 0; c < 8; ++c) {
    raytest::SurfaceSample s;
    s.position = Eigen::Vector3d(c & 1 ? 0.5 : -0.5, c & 2 ? 0.5 : -0.5, c & 4 ? 0.5 : -0.5);
    s.normal = s.position.normalized();
    corners.push_back(s);
  }
  const raytest::OneSidedDeviation corner_hits = raytest::measure_samples(inner, corners, outer, options);
  EXPECT_EQ(corner_hits.stats.misses, 0u);
  for (double v : corner_hits.values) EXPECT_NEAR(v, -0.5 * std::sqrt(3.0), 1e-9);

  options.max_distance = 0.4;  // nothing within reach: every sample misses
  const raytest::OneSidedDeviation none = raytest::measure_one_sided(inner, outer, options);
  EXPECT_EQ(none.stats.count, 0u);
  EXPECT_EQ(none.stats.misses, 3000u);
}

TEST(Deviation, AgainstAnExactFieldOfASphere) {
  const morph::TriangleMesh a = uv_sphere(1.0, 30, 60);
  raytest::DeviationOptions options;
  options.mode = raytest::DeviationMode::Signed;
  options.sampling.face_samples = 2000;
  const raytest::DistanceField sphere = [](const Eigen::Vector3d& p) { return p.norm() - 1.01; };
  const raytest::OneSidedDeviation d = raytest::measure_against_field(a, sphere, options);
  for (std::size_t v = 0; v < a.vertices.size(); ++v) ASSERT_NEAR(d.values[v], -0.01, 1e-12);
  EXPECT_NEAR(d.stats.max, -0.01, 1e-12);
  EXPECT_LT(d.stats.min, -0.01);  // face samples lie on chords, deeper inside
  options.mode = raytest::DeviationMode::Ray;
  EXPECT_THROW(raytest::measure_against_field(a, sphere, options), morph::InputError);
}

TEST(Deviation, ProvenanceGroupsNameTheWrongMoveFirst) {
  // Two unit squares tagged as two moves; the second is 0.2 off in the target.
  morph::TriangleMesh a;
  a.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {3, 0, 0}, {3, 1, 0}, {2, 1, 0}};
  a.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  const morph::FaceTag good{morph::PatchKind::SideSweep, 0, 10}, bad{morph::PatchKind::SideSweep, 1, 20};
  a.tags = {good, good, bad, bad};
  morph::TriangleMesh b = a;
  b.tags.clear();
  for (std::size_t v = 4; v < 8; ++v) b.vertices[v].z() = 0.2;
  raytest::DeviationOptions options;
  options.sampling.face_samples = 1000;
  const raytest::TwoSidedDeviation d = raytest::measure_two_sided(a, b, options);
  ASSERT_EQ(d.a_to_b.groups.size(), 2u);
  EXPECT_EQ(d.a_to_b.groups[0].tag, bad);
  EXPECT_NEAR(d.a_to_b.groups[0].stats.max, 0.2, 1e-12);
  EXPECT_EQ(d.a_to_b.groups[1].tag, good);
  EXPECT_LT(d.a_to_b.groups[1].stats.max_abs, 1e-15);
  // B -> A is grouped by A's tags through the closest triangle.
  ASSERT_EQ(d.b_to_a.groups.size(), 2u);
  EXPECT_EQ(d.b_to_a.groups[0].tag, bad);
  EXPECT_NEAR(d.b_to_a.groups[0].stats.min, 0.2, 1e-12);
  options.worst_groups = 1;
  EXPECT_EQ(raytest::measure_two_sided(a, b, options).a_to_b.groups.size(), 1u);
}

TEST(Deviation, SameSeedGivesIdenticalResultsWithOneOrManyThreads) {
  const morph::TriangleMesh a = uv_sphere(1.0, 24, 48);
  const morph::TriangleMesh b = scaled(uv_sphere(1.0, 31, 57), 1.003);
  raytest::DeviationOptions options;
  options.sampling.edge_samples = 2000;
  options.sampling.face_samples = 20000;
  options.sampling.seed = 99;
  options.mode = raytest::DeviationMode::Signed;
  raytest::TwoSidedDeviation single;
  {
    tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
    single = raytest::measure_two_sided(a, b, options);
  }
  const raytest::TwoSidedDeviation parallel = raytest::measure_two_sided(a, b, options);
  options.policy = morph::ExecutionPolicy::Sequential;
  const raytest::TwoSidedDeviation sequential = raytest::measure_two_sided(a, b, options);
  for (const auto* other : {&parallel, &sequential}) {
    ASSERT_EQ(single.a_to_b.values.size(), other->a_to_b.values.size());
    for (std::size_t i = 0; i < single.a_to_b.values.size(); ++i) {
      ASSERT_EQ(single.a_to_b.samples[i].position, other->a_to_b.samples[i].position);
      ASSERT_EQ(single.a_to_b.values[i], other->a_to_b.values[i]);
    }
    EXPECT_EQ(single.b_to_a.values, other->b_to_a.values);
    EXPECT_EQ(single.a_to_b.stats.rms, other->a_to_b.stats.rms);
    EXPECT_EQ(single.b_to_a.stats.p999, other->b_to_a.stats.p999);
    EXPECT_EQ(single.hausdorff, other->hausdorff);
  }
}

TEST(Deviation, VertexDeviationOfScaledSphere) {
  const morph::TriangleMesh a = uv_sphere(3.0, 20, 40);
  const raytest::SurfaceQuery target(a);
  const morph::TriangleMesh b = scaled(a, 1.01);
  const std::vector<double> values = raytest::vertex_deviation(b, target, raytest::DeviationMode::Signed);
  ASSERT_EQ(values.size(), b.vertices.size());
  for (double v : values) ASSERT_NEAR(v, 0.03, 1e-9 * 0.03);
}

}  // namespace

namespace {

TEST(DeviationStats, BandSharesAndToleranceBins) {
  // Band -0.02 / +0.1: bins of 0.02 below zero and 0.1 above, four a side.
  raytest::StatsOptions options;
  options.band = {-0.02, 0.1};
  const raytest::DeviationStats s =
      raytest::compute_stats({-0.5, -0.03, -0.01, 0.0, 0.05, 0.1, 0.15, 0.35, 1.0, -0.07}, options);
  EXPECT_EQ(s.band.low, -0.02);
  EXPECT_EQ(s.band.high, 0.1);
  EXPECT_DOUBLE_EQ(s.share_gouge, 0.3);   // -0.5, -0.07, -0.03
  EXPECT_DOUBLE_EQ(s.share_excess, 0.3);  // 0.15, 0.35, 1.0
  EXPECT_DOUBLE_EQ(s.share_within_band, 0.4);
  const raytest::Histogram& h = s.band_histogram;
  ASSERT_EQ(h.edges.size(), 9u);
  EXPECT_DOUBLE_EQ(h.edges.front(), -0.08);
  EXPECT_EQ(h.edges[4], 0.0);
  EXPECT_DOUBLE_EQ(h.edges.back(), 0.4);
  EXPECT_EQ(h.underflow, 1u);  // -0.5
  EXPECT_EQ(h.overflow, 1u);   // 1.0
  // [-0.08,-0.06) holds -0.07; [-0.04,-0.02) -0.03; [-0.02,0) -0.01; [0,0.1) 0, 0.05; [0.1,0.2) 0.1, 0.15;
  // [0.3,0.4] 0.35.
  const std::vector<std::size_t> expected{1, 0, 1, 1, 2, 2, 0, 1};
  EXPECT_EQ(h.counts, expected);
}

TEST(DeviationStats, ToleranceGivesASymmetricBandAndBadBandsThrow) {
  raytest::StatsOptions options;
  options.tolerance = 0.5;
  const raytest::DeviationStats s = raytest::compute_stats({-1.0, 0.2, 0.7}, options);
  EXPECT_EQ(s.band.low, -0.5);
  EXPECT_EQ(s.band.high, 0.5);
  EXPECT_EQ(raytest::classify(-1.0, s.band), raytest::DeviationClass::Gouge);
  EXPECT_EQ(raytest::classify(0.5, s.band), raytest::DeviationClass::Within);
  EXPECT_EQ(raytest::classify(0.7, s.band), raytest::DeviationClass::Excess);
  options.band = {0.1, 0.2};
  EXPECT_THROW(raytest::compute_stats({0.0}, options), morph::InputError);
}

}  // namespace
