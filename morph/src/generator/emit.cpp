// SPDX-License-Identifier: Apache-2.0
#include <morph/emit.h>
#include <morph/parallel.h>

#include "generator/rounding.h"

#include <algorithm>
#include <limits>
#include <utility>

namespace morph {
namespace {

constexpr std::uint32_t kCentroid = std::numeric_limits<std::uint32_t>::max();

// The corner to fan polygon's triangles from, or kCentroid. A fan from a corner neither of
// whose neighbours is straight has no flat triangle in exact arithmetic; of those, the first
// whose triangles are not flat once rounded to doubles either (exact corners closer than a
// double resolves, where near-parallel planes cross an edge, can round to a needle). Where no
// corner qualifies, a strictly convex polygon is fanned from its first corner and the rounding
// settles it (rounding.h); another from its centroid, a point of its own inside it.
std::uint32_t fan_apex(const LimitPolygon& polygon, const std::vector<std::uint32_t>& index,
                       const std::vector<Eigen::Vector3d>& points) {
  const std::size_t n = polygon.loop.size();
  if (n < 3) return 0;
  const auto straight = [&](std::size_t k) {
    const auto& corners = polygon.straight_corners;
    return std::binary_search(corners.begin(), corners.end(), static_cast<std::uint32_t>(k % n));
  };
  const auto at = [&](std::size_t k) -> const Eigen::Vector3d& { return points[index[polygon.loop[k % n]]]; };
  for (std::size_t apex = 0; apex < n; ++apex) {
    if (straight(apex + 1) || straight(apex + n - 1)) continue;
    bool unflat = true;
    for (std::size_t k = 1; unflat && k + 1 < n; ++k)
      unflat = !zero_area(at(apex), at(apex + k), at(apex + k + 1));
    if (unflat) return static_cast<std::uint32_t>(apex);
  }
  return polygon.strictly_convex() ? 0 : kCentroid;
}

}  // namespace

bool is_cap(const SweepPolytopeBuilder& tool, const Eigen::Vector3d& from, const Eigen::Vector3d& to,
            std::int32_t facet) {
  const std::vector<PolytopeFacet>& facets = tool.tool().facets;
  if (facet < 0 || static_cast<std::size_t>(facet) >= facets.size()) return false;
  return tool.degenerate(from, to) ||
         motion_side(facets[static_cast<std::size_t>(facet)].normal, to - from) != 0;
}

TriangleMesh emit(const LimitSurface& surface, const std::vector<std::int32_t>& move_index,
                  const std::vector<std::int32_t>& move_line, EmitCounts* counts, ExecutionPolicy policy,
                  const CapTest& caps) {
  TriangleMesh mesh;
  // Only the referenced vertices, in the order of their plane triples' indices, then a centroid
  // for each polygon fanned from one, in polygon order; the points, fans and triangles are made
  // in parallel, each in its slot.
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
  resize_faulted_in(mesh.vertices, used.size(), policy);
  for_each_index(policy, 0, used.size(), [&](std::size_t k) {
    const auto& t = surface.vertices[used[k]];
    mesh.vertices[k] = surface.points.empty() ? vertex_point(t[0], t[1], t[2]) : surface.points[used[k]];
  });
  const std::size_t polygons = surface.polygons.size();
  std::vector<std::uint32_t> apex(polygons);
  for_each_index(policy, 0, polygons,
                 [&](std::size_t i) { apex[i] = fan_apex(surface.polygons[i], index, mesh.vertices); });
  std::vector<std::size_t> first_triangle(polygons + 1, 0), centre_of(polygons, 0);
  std::size_t vertex_count = used.size();
  for (std::size_t i = 0; i < polygons; ++i) {
    const std::size_t n = surface.polygons[i].loop.size();
    std::size_t triangles = n;
    if (apex[i] != kCentroid)
      triangles = n >= 2 ? n - 2 : 0;
    else
      centre_of[i] = vertex_count++;
    first_triangle[i + 1] = first_triangle[i] + triangles;
  }
  mesh.vertices.resize(vertex_count);
  resize_faulted_in(mesh.triangles, first_triangle.back(), policy);
  resize_faulted_in(mesh.tags, first_triangle.back(), policy);
  std::vector<Eigen::Vector3d> facing;  // per triangle: the way its polygon faces out
  resize_faulted_in(facing, first_triangle.back(), policy);
  for_each_index(policy, 0, polygons, [&](std::size_t i) {
    const LimitPolygon& polygon = surface.polygons[i];
    const PatchKind sweep_kind = polygon.move >= 0 && caps && caps(polygon.move, polygon.face)
                                     ? PatchKind::FrontSweep
                                     : PatchKind::SideSweep;
    const FaceTag tag = polygon.move < 0
                            ? FaceTag{PatchKind::StockFace, polygon.face, 0}
                            : FaceTag{sweep_kind, move_index.at(polygon.move), move_line.at(polygon.move)};
    const Eigen::Vector3d out = surface.outward_normal(polygon);
    std::size_t next = first_triangle[i];
    const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      mesh.triangles[next] = {a, b, c};
      mesh.tags[next] = tag;
      facing[next++] = out;
    };
    const std::size_t n = polygon.loop.size();
    if (apex[i] != kCentroid) {
      const auto corner = [&](std::size_t k) { return index[polygon.loop[(apex[i] + k) % n]]; };
      for (std::size_t k = 1; k + 1 < n; ++k) add(corner(0), corner(k), corner(k + 1));
      return;
    }
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (std::uint32_t v : polygon.loop) centroid += mesh.vertices[index[v]];
    const auto centre = static_cast<std::uint32_t>(centre_of[i]);
    mesh.vertices[centre] = centroid / static_cast<double>(n);
    for (std::size_t k = 0; k < n; ++k) add(centre, index[polygon.loop[k]], index[polygon.loop[(k + 1) % n]]);
  });
  const RoundingCounts rounding = settle_rounding(mesh, std::move(facing));
  // One zero: a coordinate that is zero is +0 whichever way its planes face (a vertex's planes
  // are shared with other vertices, in the orientation one of them holds).
  for_each_index(policy, 0, mesh.vertices.size(),
                 [&](std::size_t v) { mesh.vertices[v] = mesh.vertices[v].array() + 0.0; });
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
