// SPDX-License-Identifier: Apache-2.0
// SurfaceQuery's pruned search (Embree traversal, per-triangle bounding planes, hints) against a
// brute force over every triangle: the same triangle (lowest index on ties) and the same distance,
// on concentric spheres (whose distance is known in closed form) and on random triangle soups
// with slivers, degenerate triangles and points near, on and far from them.
#include <gtest/gtest.h>
#include <morph/mesh_distance.h>
#include <raytest/deviation.h>
#include <raytest/surface_query.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "raytest/raytest_support.h"

namespace {

using raytest_test::uv_sphere;

struct Nearest {
  double distance = std::numeric_limits<double>::infinity();
  std::uint32_t triangle = 0;
};

// Every triangle, in index order: the least distance, the lowest index among equals.
Nearest brute_force(const morph::TriangleMesh& mesh, const Eigen::Vector3d& p) {
  Nearest best;
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    const morph::Triangle& tri = mesh.triangles[t];
    const Eigen::Vector3d q = morph::closest_point_on_triangle(p, mesh.vertices[tri[0]],
                                                               mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
    const double d = (p - q).norm();
    if (d < best.distance) best = {d, t};
  }
  return best;
}

Eigen::Vector3d random_direction(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  for (;;) {
    const Eigen::Vector3d v(normal(rng), normal(rng), normal(rng));
    if (v.norm() > 1e-3) return v.normalized();
  }
}

// Largest radius of a ball about the origin inside the (convex, origin-centred) mesh: the least
// distance from the origin to a face's plane.
double inscribed_radius(const morph::TriangleMesh& mesh) {
  double r = std::numeric_limits<double>::infinity();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Eigen::Vector3d& a = mesh.vertices[mesh.triangles[t][0]];
    r = std::min(r, std::abs(morph::face_normal(mesh, t).dot(a)));
  }
  return r;
}

TEST(SurfaceQueryExactness, PointsAboveASphereAreTheRadiusDifferenceAwayWithinTheFacetingBound) {
  // The faceted sphere lies between the balls of radius h (its inscribed radius) and r, so a point
  // at radius R > r is between R - r and R - h from it; the search must also agree with the brute
  // force exactly, with and without a hint.
  const double r = 1.0;
  const morph::TriangleMesh sphere = uv_sphere(r, 50, 100);
  const double h = inscribed_radius(sphere);
  ASSERT_GT(h, 0.999);
  const raytest::SurfaceQuery query(sphere);
  std::mt19937_64 rng(21);
  std::uint32_t hint = 0;
  for (int i = 0; i < 400; ++i) {
    const double radius = r + std::vector<double>{0.01, 1e-6, 0.3, 2.0}[i % 4];
    const Eigen::Vector3d p = radius * random_direction(rng);
    const Nearest expected = brute_force(sphere, p);
    const raytest::ClosestPoint plain = query.closest_point(p);
    const raytest::ClosestPoint hinted =
        query.closest_point(p, std::numeric_limits<double>::infinity(), hint);
    for (const raytest::ClosestPoint& cp : {plain, hinted}) {
      ASSERT_TRUE(cp.found);
      ASSERT_EQ(cp.triangle, expected.triangle) << "point " << i;
      ASSERT_EQ(cp.distance, expected.distance) << "point " << i;
      ASSERT_GE(cp.distance, radius - r - 1e-12);
      ASSERT_LE(cp.distance, radius - h + 1e-12);
    }
    hint = plain.triangle;
  }
}

TEST(SurfaceQueryExactness, SphereVertexDeviationMatchesTheBruteForceTo1e9) {
  // The deviation command's path (vertex samples in parallel, each hinting the next) on the peers'
  // pair in small: a finer sphere of radius 1.01 against a coarser one of radius 1.
  const morph::TriangleMesh outer = uv_sphere(1.01, 60, 120);
  const morph::TriangleMesh inner = uv_sphere(1.0, 25, 40);
  const raytest::SurfaceQuery query(inner);
  const std::vector<double> values = raytest::vertex_deviation(outer, query, raytest::DeviationMode::Signed);
  ASSERT_EQ(values.size(), outer.vertices.size());
  const double h = inscribed_radius(inner);
  for (std::size_t v = 0; v < outer.vertices.size(); ++v) {
    const Nearest expected = brute_force(inner, outer.vertices[v]);
    ASSERT_NEAR(values[v], expected.distance, 1e-9) << "vertex " << v;  // outside: positive
    ASSERT_GE(values[v], 0.01 - 1e-12);
    ASSERT_LE(values[v], 1.01 - h + 1e-12);
  }
}

// A soup of random triangles in the unit cube: ordinary ones, slivers (one corner near the
// opposite edge), needles and degenerate ones (repeated or collinear corners), with shared corners
// and exact duplicates so that ties occur.
morph::TriangleMesh random_soup(std::mt19937_64& rng, int count) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  morph::TriangleMesh mesh;
  const auto point = [&] { return Eigen::Vector3d(unit(rng), unit(rng), unit(rng)); };
  for (int i = 0; i < count; ++i) {
    const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
    const Eigen::Vector3d a = point();
    const Eigen::Vector3d b = a + 0.1 * (point() - Eigen::Vector3d::Constant(0.5));
    Eigen::Vector3d c = a + 0.1 * (point() - Eigen::Vector3d::Constant(0.5));
    switch (i % 6) {
      case 1:  // sliver
        c = 0.5 * (a + b) + 1e-7 * (c - a);
        break;
      case 2:  // collinear
        c = a + 2.0 * (b - a);
        break;
      case 3:  // a repeated corner
        c = b;
        break;
      default:
        break;
    }
    mesh.vertices.insert(mesh.vertices.end(), {a, b, c});
    mesh.triangles.push_back({base, base + 1, base + 2});
    if (i % 7 == 0) mesh.triangles.push_back({base, base + 1, base + 2});           // duplicate: a tie
    if (i % 5 == 0 && i > 0) mesh.triangles.push_back({base, base - 1, base + 1});  // shares corners
  }
  return mesh;
}

// The soup at `origin` scaled by `size`: far from the origin the float spacing of the coordinates
// (which Embree and the stored bounding planes use) is coarse next to the soup's details.
void expect_soup_matches_brute_force(std::uint64_t seed, const Eigen::Vector3d& origin, double size) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  morph::TriangleMesh soup = random_soup(rng, 1500);
  for (Eigen::Vector3d& v : soup.vertices) v = origin + size * v;
  const raytest::SurfaceQuery query(soup);
  std::uint32_t hint = 0;
  for (int i = 0; i < 1500; ++i) {
    Eigen::Vector3d p;
    switch (i % 4) {
      case 0:  // on a triangle's corner
        p = soup.vertices[std::uniform_int_distribution<std::size_t>(0, soup.vertices.size() - 1)(rng)];
        break;
      case 1:  // far away
        p = origin + size * (Eigen::Vector3d::Constant(0.5) + 5.0 * random_direction(rng));
        break;
      default:  // among the triangles
        p = origin + size * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
    }
    const Nearest expected = brute_force(soup, p);
    const raytest::ClosestPoint plain = query.closest_point(p);
    const raytest::ClosestPoint hinted =
        query.closest_point(p, std::numeric_limits<double>::infinity(), hint);
    for (const raytest::ClosestPoint& cp : {plain, hinted}) {
      ASSERT_TRUE(cp.found);
      ASSERT_EQ(cp.triangle, expected.triangle) << "point " << i << " at " << p.transpose();
      ASSERT_EQ(cp.distance, expected.distance) << "point " << i;
    }
    hint = static_cast<std::uint32_t>((hint * 7919u + 13u) % soup.triangles.size());  // unrelated hints too
  }
}

TEST(SurfaceQueryExactness, RandomSoupsMatchTheBruteForceExactlyWithAndWithoutHints) {
  expect_soup_matches_brute_force(2111, Eigen::Vector3d::Zero(), 1.0);
  expect_soup_matches_brute_force(2112, Eigen::Vector3d::Zero(), 1.0);
}

TEST(SurfaceQueryExactness, RandomSoupFarFromTheOriginMatchesTheBruteForceExactly) {
  expect_soup_matches_brute_force(2113, Eigen::Vector3d(1000, -2000, 500), 0.05);
}

}  // namespace
