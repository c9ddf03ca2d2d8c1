// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <raytest/surface_query.h>

#include <cmath>
#include <random>

#include "raytest/raytest_support.h"

namespace {

using raytest_test::box_mesh;
using raytest_test::box_signed_distance;
using raytest_test::scaled;
using raytest_test::uv_sphere;

TEST(SurfaceQuery, VerticesOfScaledSphereAreExactlyOnePercentOfTheRadiusAway) {
  // Each vertex w = 1.01 v of the scaled sphere is nearest to the vertex v of the original:
  // the adjacent faces and edges of the convex original all turn away from w.
  const double r = 2.5;
  const morph::TriangleMesh a = uv_sphere(r, 60, 120);
  const morph::TriangleMesh b = scaled(a, 1.01);
  const raytest::SurfaceQuery query(a);
  for (std::size_t v = 0; v < b.vertices.size(); ++v) {
    const raytest::ClosestPoint cp = query.closest_point(b.vertices[v]);
    ASSERT_TRUE(cp.found);
    ASSERT_NEAR(cp.distance, 0.01 * r, 1e-9 * 0.01 * r) << "vertex " << v;
    ASSERT_LT((cp.point - a.vertices[v]).norm(), 1e-12);
    ASSERT_NEAR(query.signed_distance(b.vertices[v]), 0.01 * r, 1e-9 * 0.01 * r);
  }
}

TEST(SurfaceQuery, StaysExactFarFromTheOriginWhereFloatsAreCoarse) {
  // Centred at (1000, -2000, 500) the float spacing (~1e-4) exceeds the 0.01 * 0.05 gap between
  // the two spheres' facets: only the double-precision refinement with its margin finds the
  // exact nearest triangle.
  const Eigen::Vector3d centre(1000, -2000, 500);
  const double r = 0.05;
  morph::TriangleMesh a = uv_sphere(r, 30, 60);
  morph::TriangleMesh b = a;
  for (std::size_t v = 0; v < a.vertices.size(); ++v) {
    b.vertices[v] = centre + 1.01 * a.vertices[v];
    a.vertices[v] = centre + a.vertices[v];
  }
  const raytest::SurfaceQuery query(a);
  for (std::size_t v = 0; v < b.vertices.size(); ++v) {
    const raytest::ClosestPoint cp = query.closest_point(b.vertices[v]);
    ASSERT_TRUE(cp.found);
    ASSERT_NEAR(cp.distance, (b.vertices[v] - a.vertices[v]).norm(), 1e-9 * 0.01 * r) << "vertex " << v;
    ASSERT_NEAR(cp.distance, 0.01 * r, 1e-9);  // the subtraction of the centre costs ~1e-13
  }
}

TEST(SurfaceQuery, VerticesOfInnerTessellationLieOnTheFinerMesh) {
  // The 2x finer UV sphere contains every vertex of the coarse one (polar angle i*pi/n = 2i*pi/2n).
  const morph::TriangleMesh coarse = uv_sphere(1.0, 20, 40);
  const morph::TriangleMesh fine = uv_sphere(1.0, 40, 80);
  const raytest::SurfaceQuery query(fine);
  for (const Eigen::Vector3d& v : coarse.vertices) {
    const raytest::ClosestPoint cp = query.closest_point(v);
    ASSERT_TRUE(cp.found);
    ASSERT_LE(cp.distance, 1e-15);
  }
}

TEST(SurfaceQuery, OffsetCubeDistancesAndSignsMatchTheClosedForm) {
  const Eigen::Vector3d lo(0.3, -0.2, 0.1), hi(1.3, 0.8, 1.1);
  const raytest::SurfaceQuery query(box_mesh(lo, hi, 3));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coordinate(-1.0, 2.5);
  int inside = 0, outside = 0;
  for (int i = 0; i < 4000; ++i) {
    const Eigen::Vector3d p(coordinate(rng), coordinate(rng), coordinate(rng));
    const double truth = box_signed_distance(p, lo, hi);
    const double d = query.signed_distance(p);
    ASSERT_NEAR(d, truth, 1e-12 * (1 + std::abs(truth))) << p.transpose();
    (truth < 0 ? inside : outside)++;
  }
  EXPECT_GT(inside, 100);
  EXPECT_GT(outside, 100);
}

TEST(SurfaceQuery, SignIsRightInEdgeAndVertexRegionsOfACube) {
  // Points whose nearest feature is a cube edge or corner: a face normal alone gives the wrong
  // sign for some of them, the angle-weighted pseudo-normal never does.
  const Eigen::Vector3d lo(0, 0, 0), hi(1, 1, 1);
  const raytest::SurfaceQuery query(box_mesh(lo, hi, 1));
  const std::vector<Eigen::Vector3d> outside_points = {
      {1.2, 1.1, 0.5},    {1.05, 1.3, 0.5},  {-0.1, -0.3, 0.2}, {1.1, 1.1, 1.1},
      {-0.2, -0.1, -0.3}, {1.3, -0.01, 1.2}, {0.5, -0.4, 1.4},  {1.5, 1.5, -0.5}};
  for (const Eigen::Vector3d& p : outside_points) {
    const double d = query.signed_distance(p);
    EXPECT_NEAR(d, box_signed_distance(p, lo, hi), 1e-12) << p.transpose();
    EXPECT_GT(d, 0) << p.transpose();
  }
  const std::vector<Eigen::Vector3d> inside_points = {
      {0.95, 0.97, 0.5}, {0.99, 0.98, 0.97}, {0.01, 0.02, 0.03}, {0.5, 0.999, 0.999}};
  for (const Eigen::Vector3d& p : inside_points) {
    const double d = query.signed_distance(p);
    EXPECT_NEAR(d, box_signed_distance(p, lo, hi), 1e-12) << p.transpose();
    EXPECT_LT(d, 0) << p.transpose();
  }
}

TEST(SurfaceQuery, MaxDistanceLimitsTheSearch) {
  const raytest::SurfaceQuery query(box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 2));
  const Eigen::Vector3d p(0.5, 0.5, 1.5);
  EXPECT_FALSE(query.closest_point(p, 0.4).found);
  const raytest::ClosestPoint cp = query.closest_point(p, 0.6);
  ASSERT_TRUE(cp.found);
  EXPECT_NEAR(cp.distance, 0.5, 1e-15);
}

TEST(SurfaceQuery, RayHitsAtClosedFormDistances) {
  // A square in the plane z = 1, hit from the origin at angle theta: t = 1 / cos(theta).
  morph::TriangleMesh plane;
  plane.vertices = {{-5, -5, 1}, {5, -5, 1}, {5, 5, 1}, {-5, 5, 1}};
  plane.triangles = {{0, 1, 2}, {0, 2, 3}};
  const raytest::SurfaceQuery query(plane);
  for (double theta : {0.0, 0.3, 0.7, 1.1}) {
    const Eigen::Vector3d origin(0.1, 0.2, 0);
    const Eigen::Vector3d direction(0, std::sin(theta), std::cos(theta));
    const raytest::RayHit hit = query.first_hit(origin, direction);
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.t, 1.0 / std::cos(theta), 1e-12);
    EXPECT_NEAR(hit.point.z(), 1.0, 1e-12);
    // Both ways from above the plane: the hit is behind, so t is negative.
    const raytest::RayHit back = query.nearest_hit_both_ways(Eigen::Vector3d(0.1, 0.2, 3), direction, 10);
    ASSERT_TRUE(back.hit);
    EXPECT_NEAR(back.t, -2.0 / std::cos(theta), 1e-12);
  }
  EXPECT_FALSE(query.first_hit(Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, 1), 0, 0.9).hit);
  EXPECT_FALSE(query.first_hit(Eigen::Vector3d::Zero(), Eigen::Vector3d(1, 0, 0)).hit);
}

TEST(SurfaceQuery, EmptyMeshFindsNothing) {
  const raytest::SurfaceQuery query(morph::TriangleMesh{});
  EXPECT_FALSE(query.closest_point(Eigen::Vector3d::Zero()).found);
  EXPECT_FALSE(query.first_hit(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()).hit);
}

TEST(SurfaceQuery, InvalidMeshIsRejected) {
  morph::TriangleMesh bad;
  bad.vertices = {{0, 0, 0}, {1, 0, 0}};
  bad.triangles = {{0, 1, 2}};
  EXPECT_THROW(raytest::SurfaceQuery{bad}, morph::InputError);
}

}  // namespace
