// SPDX-License-Identifier: Apache-2.0
#include <morph/shells.h>
#include <morph/topology.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <vector>

namespace morph {

namespace {

/// Solid angle of triangle (a, b, c) seen from p, over 4 pi (Van Oosterom and Strackee).
double winding_share(const Eigen::Vector3d& p, const Eigen::Vector3d& a0, const Eigen::Vector3d& b0,
                     const Eigen::Vector3d& c0) {
  const Eigen::Vector3d a = a0 - p, b = b0 - p, c = c0 - p;
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double numerator = a.dot(b.cross(c));
  const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return std::atan2(numerator, denominator) / (2.0 * M_PI);
}

}  // namespace

std::optional<EnclosedShell> find_enclosed_shell(const TriangleMesh& mesh) {
  std::vector<std::uint32_t> shell_of;
  const std::size_t shells = connected_components(mesh, shell_of);
  if (shells < 2) return std::nullopt;
  std::vector<Eigen::AlignedBox3d> box(shells);
  std::vector<std::uint32_t> first_triangle(shells, 0);
  std::vector<std::vector<std::uint32_t>> triangles(shells);
  std::vector<std::uint32_t> vertex_shell(mesh.vertices.size(), std::uint32_t(-1));
  for (std::size_t t = mesh.triangles.size(); t-- > 0;) {
    const std::uint32_t s = shell_of[t];
    first_triangle[s] = std::uint32_t(t);
    triangles[s].push_back(std::uint32_t(t));
    for (std::uint32_t v : mesh.triangles[t]) {
      box[s].extend(mesh.vertices[v]);
      vertex_shell[v] = s;
    }
  }
  std::vector<std::vector<std::uint32_t>> vertices(shells);
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v)
    if (vertex_shell[v] != std::uint32_t(-1)) vertices[vertex_shell[v]].push_back(v);
  // Every vertex of a nested shell is enclosed, and an overlap encloses a region of vertices, so
  // a spread sample finds them; the sample keeps each pair's work near kWorkPerPair terms.
  constexpr double kWorkPerPair = 2e7;
  for (std::uint32_t inner = 0; inner < shells; ++inner)
    for (std::uint32_t outer = 0; outer < shells; ++outer) {
      if (outer == inner || !box[outer].intersects(box[inner])) continue;
      const std::size_t n = vertices[inner].size();
      const std::size_t stride = std::max<std::size_t>(
          1, std::size_t(std::ceil(double(n) * double(triangles[outer].size()) / kWorkPerPair)));
      for (std::size_t k = 0; k < n; k += stride) {
        const std::uint32_t v = vertices[inner][k];
        const Eigen::Vector3d& p = mesh.vertices[v];
        if (!box[outer].contains(p)) continue;
        double winding = 0.0;
        for (std::uint32_t t : triangles[outer]) {
          const Triangle& tri = mesh.triangles[t];
          winding += winding_share(p, mesh.vertices[tri[0]], mesh.vertices[tri[1]], mesh.vertices[tri[2]]);
        }
        if (winding > 0.5) return EnclosedShell{first_triangle[inner], first_triangle[outer], v, winding};
      }
    }
  return std::nullopt;
}

}  // namespace morph
