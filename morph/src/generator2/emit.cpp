// SPDX-License-Identifier: Apache-2.0
#include <morph/emit.h>

#include "generator2/rounding.h"

#include <limits>
#include <utility>

namespace morph {

TriangleMesh emit(const LimitSurface& surface, const std::vector<std::int32_t>& move_index,
                  const std::vector<std::int32_t>& move_line, EmitCounts* counts) {
  TriangleMesh mesh;
  std::vector<Eigen::Vector3d> facing;  // per triangle: the way its polygon faces out
  // Only the referenced vertices, in the order of their plane triples' indices.
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> index(surface.vertices.size(), kUnused);
  for (const LimitPolygon& polygon : surface.polygons)
    for (std::uint32_t v : polygon.loop) index[v] = 0;
  for (std::uint32_t v = 0; v < surface.vertices.size(); ++v)
    if (index[v] != kUnused) {
      index[v] = static_cast<std::uint32_t>(mesh.vertices.size());
      const auto& t = surface.vertices[v];
      mesh.vertices.push_back(vertex_point(t[0], t[1], t[2]));
    }
  for (const LimitPolygon& polygon : surface.polygons) {
    const FaceTag tag = polygon.move < 0 ? FaceTag{PatchKind::StockFace, polygon.face, 0}
                                         : FaceTag{PatchKind::SideSweep, move_index.at(polygon.move),
                                                   move_line.at(polygon.move)};
    const Eigen::Vector3d out = surface.outward_normal(polygon);
    const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      mesh.triangles.push_back({a, b, c});
      mesh.tags.push_back(tag);
      facing.push_back(out);
    };
    const std::size_t n = polygon.loop.size();
    if (polygon.strictly_convex) {
      for (std::size_t k = 1; k + 1 < n; ++k)
        add(index[polygon.loop[0]], index[polygon.loop[k]], index[polygon.loop[k + 1]]);
      continue;
    }
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (std::uint32_t v : polygon.loop) centroid += mesh.vertices[index[v]];
    const auto centre = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(centroid / static_cast<double>(n));
    for (std::size_t k = 0; k < n; ++k) add(centre, index[polygon.loop[k]], index[polygon.loop[(k + 1) % n]]);
  }
  const RoundingCounts rounding = settle_rounding(mesh, std::move(facing));
  if (counts)
    *counts = {rounding.collapsed_edges, rounding.flipped_edges, rounding.rerounded_vertices,
               rounding.misoriented_left};
  return mesh;
}

TriangleMesh emit(const ConformedSurface& surface, const std::vector<std::int32_t>& move_index,
                  const std::vector<std::int32_t>& move_line, EmitCounts* counts) {
  return emit(collapse_degenerates(surface), move_index, move_line, counts);
}

}  // namespace morph
