// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file mesh_distance.h
/// Exact signed distance to a closed triangle mesh (closest point over a bounding-volume
/// hierarchy, sign from angle-weighted pseudo-normals, which is exact at edges and vertices).
#include <morph/aabb_tree.h>
#include <morph/mesh.h>

namespace morph {

/// Closest point of triangle (a, b, c) to p, in double precision.
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                          const Eigen::Vector3d& b, const Eigen::Vector3d& c);

class MeshDistance {
 public:
  /// Keeps a copy of the mesh. Requires a closed, consistently outward-wound mesh for the sign.
  explicit MeshDistance(TriangleMesh mesh);

  /// Unsigned distance to the nearest triangle; `triangle` receives its index.
  double distance(const Eigen::Vector3d& p, std::size_t* triangle = nullptr,
                  Eigen::Vector3d* closest = nullptr) const;
  /// Signed distance, negative inside.
  double signed_distance(const Eigen::Vector3d& p) const;
  const TriangleMesh& mesh() const { return mesh_; }

 private:
  TriangleMesh mesh_;
  AabbTree tree_;
  std::vector<Eigen::Vector3d> face_normals_;
  std::vector<Eigen::Vector3d> vertex_normals_;               // angle-weighted
  std::vector<std::array<Eigen::Vector3d, 3>> edge_normals_;  // per triangle edge (i, i+1)
};

}  // namespace morph
