// SPDX-License-Identifier: Apache-2.0
#include "raytest/raytest_support.h"

#include <array>
#include <cmath>
#include <map>

namespace raytest_test {

morph::TriangleMesh uv_sphere(double r, int nlat, int nlon) {
  morph::TriangleMesh mesh;
  mesh.vertices.push_back(Eigen::Vector3d(0, 0, r));
  for (int i = 1; i < nlat; ++i) {
    const double theta = M_PI * i / nlat;
    for (int j = 0; j < nlon; ++j) {
      const double phi = 2 * M_PI * j / nlon;
      mesh.vertices.push_back(r * Eigen::Vector3d(std::sin(theta) * std::cos(phi),
                                                  std::sin(theta) * std::sin(phi), std::cos(theta)));
    }
  }
  mesh.vertices.push_back(Eigen::Vector3d(0, 0, -r));
  const auto ring = [&](int i, int j) { return static_cast<std::uint32_t>(1 + i * nlon + (j % nlon)); };
  const auto south = static_cast<std::uint32_t>(mesh.vertices.size() - 1);
  for (int j = 0; j < nlon; ++j) mesh.triangles.push_back({0, ring(0, j), ring(0, j + 1)});
  for (int i = 0; i + 2 < nlat; ++i)
    for (int j = 0; j < nlon; ++j) {
      const std::uint32_t a = ring(i, j), b = ring(i + 1, j), c = ring(i + 1, j + 1), d = ring(i, j + 1);
      mesh.triangles.push_back({a, b, c});
      mesh.triangles.push_back({a, c, d});
    }
  for (int j = 0; j < nlon; ++j) mesh.triangles.push_back({south, ring(nlat - 2, j + 1), ring(nlat - 2, j)});
  return mesh;
}

morph::TriangleMesh box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int n) {
  morph::TriangleMesh mesh;
  // For each axis and side, a grid over the two other axes, wound so the normal points outward.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      const auto base = static_cast<std::uint32_t>(mesh.vertices.size());
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Eigen::Vector3d p;
          p[axis] = side ? hi[axis] : lo[axis];
          p[u] = lo[u] + (hi[u] - lo[u]) * i / n;
          p[v] = lo[v] + (hi[v] - lo[v]) * j / n;
          mesh.vertices.push_back(p);
        }
      const auto at = [&](int i, int j) { return base + static_cast<std::uint32_t>(i * (n + 1) + j); };
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          // (u, v, axis) is right-handed: counter-clockwise in (u, v) faces +axis.
          if (side) {
            mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
            mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
          } else {
            mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
            mesh.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
          }
        }
    }
  // Weld the face grids: identical coordinates become one vertex, so the box is closed.
  std::map<std::array<double, 3>, std::uint32_t> index;
  std::vector<std::uint32_t> remap(mesh.vertices.size());
  morph::TriangleMesh welded;
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const std::array<double, 3> key{mesh.vertices[v].x(), mesh.vertices[v].y(), mesh.vertices[v].z()};
    const auto [it, inserted] = index.emplace(key, static_cast<std::uint32_t>(welded.vertices.size()));
    if (inserted) welded.vertices.push_back(mesh.vertices[v]);
    remap[v] = it->second;
  }
  for (const morph::Triangle& t : mesh.triangles)
    welded.triangles.push_back({remap[t[0]], remap[t[1]], remap[t[2]]});
  return welded;
}

morph::TriangleMesh scaled(morph::TriangleMesh mesh, double factor) {
  for (Eigen::Vector3d& v : mesh.vertices) v *= factor;
  return mesh;
}

double box_signed_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d center = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const Eigen::Vector3d q = (p - center).cwiseAbs() - half;
  const double outside = q.cwiseMax(0.0).norm();
  const double inside = std::min(q.maxCoeff(), 0.0);
  return outside + inside;
}

}  // namespace raytest_test
