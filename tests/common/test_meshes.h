// SPDX-License-Identifier: Apache-2.0
#pragma once
// Meshes with known topology and geometry, shared by the morph and apps tests.
#include <morph/mesh.h>

#include <cmath>
#include <cstdint>

namespace morphmill_test {

/// Axis-aligned box: 8 vertices (index = x + 2y + 4z bits), 12 triangles wound outward.
inline morph::TriangleMesh box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  morph::TriangleMesh mesh;
  for (int i = 0; i < 8; ++i)
    mesh.vertices.emplace_back(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[1]), std::uint32_t(q[2])});
    mesh.triangles.push_back({std::uint32_t(q[0]), std::uint32_t(q[2]), std::uint32_t(q[3])});
  }
  return mesh;
}

/// Torus of revolution with a regular m-gon cross-section of circumradius r around
/// the circle of radius R, revolved in n steps. Every quad is a planar isosceles
/// trapezoid, so the polyhedron's volume is exactly
///   n sin(2 pi / n) * R * (m / 2) r^2 sin(2 pi / m)
/// (each horizontal slice of a sector is the region between two chords of the wedge).
inline morph::TriangleMesh torus(double R, double r, int n, int m) {
  const double pi = 3.14159265358979323846;
  morph::TriangleMesh mesh;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double theta = 2 * pi * i / n, phi = 2 * pi * j / m;
      const double rho = R + r * std::cos(phi);
      mesh.vertices.emplace_back(rho * std::cos(theta), rho * std::sin(theta), r * std::sin(phi));
    }
  auto id = [&](int i, int j) { return std::uint32_t((i % n) * m + (j % m)); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return mesh;
}

/// Three triangles sharing the edge 0-1: one non-manifold edge.
inline morph::TriangleMesh fin() {
  morph::TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
  return mesh;
}

/// Two triangles meeting only at vertex 0: one non-manifold vertex.
inline morph::TriangleMesh bow_tie() {
  morph::TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 3, 4}};
  return mesh;
}

}  // namespace morphmill_test
