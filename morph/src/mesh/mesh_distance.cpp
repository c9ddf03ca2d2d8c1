// SPDX-License-Identifier: Apache-2.0
#include <morph/mesh_distance.h>

#include <cmath>
#include <map>
#include <utility>

namespace morph {

Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Voronoi-region walk (Ericson, Real-Time Collision Detection, 5.1.5).
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + (d1 / (d1 - d3)) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

MeshDistance::MeshDistance(TriangleMesh mesh) : mesh_(std::move(mesh)) {
  const std::size_t nt = mesh_.triangles.size();
  std::vector<Eigen::AlignedBox3d> boxes(nt);
  face_normals_.resize(nt);
  vertex_normals_.assign(mesh_.vertices.size(), Eigen::Vector3d::Zero());
  std::map<std::pair<std::uint32_t, std::uint32_t>, Eigen::Vector3d> edge_sum;
  for (std::size_t t = 0; t < nt; ++t) {
    const Triangle& tri = mesh_.triangles[t];
    for (std::uint32_t v : tri) boxes[t].extend(mesh_.vertices[v]);
    face_normals_[t] = face_normal(mesh_, t);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& v0 = mesh_.vertices[tri[k]];
      const Eigen::Vector3d e1 = (mesh_.vertices[tri[(k + 1) % 3]] - v0).normalized();
      const Eigen::Vector3d e2 = (mesh_.vertices[tri[(k + 2) % 3]] - v0).normalized();
      const double angle = std::acos(std::clamp(e1.dot(e2), -1.0, 1.0));
      if (std::isfinite(angle)) vertex_normals_[tri[k]] += angle * face_normals_[t];
      auto key = std::minmax(tri[k], tri[(k + 1) % 3]);
      // try_emplace with an explicit zero: Eigen vectors are not zeroed by default construction.
      edge_sum.try_emplace({key.first, key.second}, Eigen::Vector3d::Zero()).first->second +=
          face_normals_[t];
    }
  }
  edge_normals_.resize(nt);
  for (std::size_t t = 0; t < nt; ++t) {
    const Triangle& tri = mesh_.triangles[t];
    for (int k = 0; k < 3; ++k) {
      auto key = std::minmax(tri[k], tri[(k + 1) % 3]);
      edge_normals_[t][k] = edge_sum.at({key.first, key.second});
    }
  }
  tree_ = AabbTree(std::move(boxes));
}

double MeshDistance::distance(const Eigen::Vector3d& p, std::size_t* triangle,
                              Eigen::Vector3d* closest) const {
  double best = 0.0;
  const std::int64_t item = tree_.nearest(
      p,
      [&](std::size_t t) {
        const Triangle& tri = mesh_.triangles[t];
        const Eigen::Vector3d q = closest_point_on_triangle(p, mesh_.vertices[tri[0]], mesh_.vertices[tri[1]],
                                                            mesh_.vertices[tri[2]]);
        return (p - q).norm();
      },
      &best);
  if (item >= 0 && closest) {
    const Triangle& tri = mesh_.triangles[static_cast<std::size_t>(item)];
    *closest =
        closest_point_on_triangle(p, mesh_.vertices[tri[0]], mesh_.vertices[tri[1]], mesh_.vertices[tri[2]]);
  }
  if (triangle) *triangle = item < 0 ? 0 : static_cast<std::size_t>(item);
  return best;
}

double MeshDistance::signed_distance(const Eigen::Vector3d& p) const {
  std::size_t t = 0;
  Eigen::Vector3d q;
  const double d = distance(p, &t, &q);
  if (mesh_.triangles.empty()) return d;
  const Triangle& tri = mesh_.triangles[t];
  // Which feature the closest point lies on decides the pseudo-normal.
  const Eigen::Vector3d& a = mesh_.vertices[tri[0]];
  const Eigen::Vector3d& b = mesh_.vertices[tri[1]];
  const Eigen::Vector3d& c = mesh_.vertices[tri[2]];
  const double area2 = (b - a).cross(c - a).norm();
  Eigen::Vector3d normal = face_normals_[t];
  if (area2 > 0) {
    const double wa = (b - q).cross(c - q).norm() / area2;
    const double wb = (c - q).cross(a - q).norm() / area2;
    const double wc = (a - q).cross(b - q).norm() / area2;
    const double eps = 1e-9;
    const double w[3] = {wa, wb, wc};
    int zeros = 0, nonzero_index = -1;
    for (int k = 0; k < 3; ++k) {
      if (w[k] < eps)
        ++zeros;
      else
        nonzero_index = k;
    }
    if (zeros == 2) {
      normal = vertex_normals_[tri[nonzero_index]];
    } else if (zeros == 1) {
      for (int k = 0; k < 3; ++k)
        if (w[k] < eps) normal = edge_normals_[t][(k + 1) % 3];  // edge opposite vertex k
    }
  }
  return (p - q).dot(normal) < 0.0 ? -d : d;
}

}  // namespace morph
