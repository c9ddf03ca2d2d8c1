// SPDX-License-Identifier: Apache-2.0
#include <morph/emit.h>
#include <morph/parallel.h>

#include "generator2/rounding.h"

#include <limits>
#include <utility>

namespace morph {

TriangleMesh emit(const LimitSurface& surface, const std::vector<std::int32_t>& move_index,
                  const std::vector<std::int32_t>& move_line, EmitCounts* counts, ExecutionPolicy policy) {
  TriangleMesh mesh;
  // Only the referenced vertices, in the order of their plane triples' indices, then a centroid
  // for each polygon that is not strictly convex, in polygon order; the points and triangles are
  // made in parallel, each in its slot.
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> index(surface.vertices.size(), kUnused);
  for (const LimitPolygon& polygon : surface.polygons)
    for (std::uint32_t v : polygon.loop) index[v] = 0;
  std::vector<std::uint32_t> used;
  for (std::uint32_t v = 0; v < surface.vertices.size(); ++v)
    if (index[v] != kUnused) {
      index[v] = static_cast<std::uint32_t>(used.size());
      used.push_back(v);
    }
  const std::size_t polygons = surface.polygons.size();
  std::vector<std::size_t> first_triangle(polygons + 1, 0), centre_of(polygons, 0);
  std::size_t vertex_count = used.size();
  for (std::size_t i = 0; i < polygons; ++i) {
    const LimitPolygon& polygon = surface.polygons[i];
    const std::size_t n = polygon.loop.size();
    std::size_t triangles = n;
    if (polygon.strictly_convex)
      triangles = n >= 2 ? n - 2 : 0;
    else
      centre_of[i] = vertex_count++;
    first_triangle[i + 1] = first_triangle[i] + triangles;
  }
  resize_faulted_in(mesh.vertices, vertex_count, policy);
  for_each_index(policy, 0, used.size(), [&](std::size_t k) {
    const auto& t = surface.vertices[used[k]];
    mesh.vertices[k] = surface.points.empty() ? vertex_point(t[0], t[1], t[2]) : surface.points[used[k]];
  });
  resize_faulted_in(mesh.triangles, first_triangle.back(), policy);
  resize_faulted_in(mesh.tags, first_triangle.back(), policy);
  std::vector<Eigen::Vector3d> facing;  // per triangle: the way its polygon faces out
  resize_faulted_in(facing, first_triangle.back(), policy);
  for_each_index(policy, 0, polygons, [&](std::size_t i) {
    const LimitPolygon& polygon = surface.polygons[i];
    const FaceTag tag = polygon.move < 0 ? FaceTag{PatchKind::StockFace, polygon.face, 0}
                                         : FaceTag{PatchKind::SideSweep, move_index.at(polygon.move),
                                                   move_line.at(polygon.move)};
    const Eigen::Vector3d out = surface.outward_normal(polygon);
    std::size_t next = first_triangle[i];
    const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      mesh.triangles[next] = {a, b, c};
      mesh.tags[next] = tag;
      facing[next++] = out;
    };
    const std::size_t n = polygon.loop.size();
    if (polygon.strictly_convex) {
      for (std::size_t k = 1; k + 1 < n; ++k)
        add(index[polygon.loop[0]], index[polygon.loop[k]], index[polygon.loop[k + 1]]);
      return;
    }
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (std::uint32_t v : polygon.loop) centroid += mesh.vertices[index[v]];
    const auto centre = static_cast<std::uint32_t>(centre_of[i]);
    mesh.vertices[centre] = centroid / static_cast<double>(n);
    for (std::size_t k = 0; k < n; ++k) add(centre, index[polygon.loop[k]], index[polygon.loop[(k + 1) % n]]);
  });
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
