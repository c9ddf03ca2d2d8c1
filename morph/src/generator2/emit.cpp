// SPDX-License-Identifier: Apache-2.0
#include <morph/emit.h>

namespace morph {

TriangleMesh emit(const ConformedSurface& surface, const std::vector<std::int32_t>& move_index,
                  const std::vector<std::int32_t>& move_line) {
  TriangleMesh mesh;
  mesh.vertices.reserve(surface.vertices.size());
  for (const auto& v : surface.vertices) mesh.vertices.push_back(vertex_point(v[0], v[1], v[2]));
  for (const ConformedPolygon& polygon : surface.polygons) {
    const FaceTag tag = polygon.move < 0 ? FaceTag{PatchKind::StockFace, polygon.face, 0}
                                         : FaceTag{PatchKind::SideSweep, move_index.at(polygon.move),
                                                   move_line.at(polygon.move)};
    const std::vector<std::uint32_t>& loop = polygon.loop;
    const std::size_t n = loop.size();
    if (n == polygon.corners) {
      for (std::size_t k = 1; k + 1 < n; ++k) {
        mesh.triangles.push_back({loop[0], loop[k], loop[k + 1]});
        mesh.tags.push_back(tag);
      }
      continue;
    }
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (std::uint32_t v : loop) centroid += mesh.vertices[v];
    const auto centre = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(centroid / static_cast<double>(n));
    for (std::size_t k = 0; k < n; ++k) {
      mesh.triangles.push_back({centre, loop[k], loop[(k + 1) % n]});
      mesh.tags.push_back(tag);
    }
  }
  return mesh;
}

}  // namespace morph
