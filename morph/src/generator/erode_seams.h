// SPDX-License-Identifier: Apache-2.0
#pragma once
// Private to the generator: joining independently trimmed patches along their shared curves.
#include <morph/mesh.h>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace morph::detail {

/// Which patch a triangle comes from and which of its edges (bit k: edge k -> k+1) lie on the
/// patch's border: only those can be open, so the seam work never touches patch interiors.
struct TriangleOrigin {
  std::uint32_t patch = 0;
  std::uint8_t border = 0;
};

/// Keeps, in order and in place, the triangles t for which keep(t, triangle) is true (`keep`
/// may first rewrite the copy of the triangle it is given), with their tags and origins.
template <class Keep>
void keep_triangles(TriangleMesh& mesh, std::vector<TriangleOrigin>& origin, Keep&& keep) {
  std::size_t kept = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    Triangle triangle = mesh.triangles[t];
    if (!keep(t, triangle)) continue;
    mesh.triangles[kept] = triangle;  // kept <= t: nothing unread is overwritten
    mesh.tags[kept] = mesh.tags[t];
    origin[kept] = origin[t];
    ++kept;
  }
  mesh.triangles.resize(kept);
  mesh.tags.resize(kept);
  origin.resize(kept);
}

struct SeamOptions {
  double weld_distance = 1e-9;    ///< points closer than this are one vertex
  double snap_distance = 0.0005;  ///< boundary vertices of different patches closer than this merge
  double match_distance = 0.005;  ///< largest distance of a vertex from the other side's chord
  double cell = 0.1;              ///< typical boundary edge length (spatial hash cell)
  double hole_diameter = 0.5;     ///< largest corner hole to fill
};

struct SeamStats {
  std::size_t welded = 0;          ///< vertices merged by the weld
  std::size_t splits = 0;          ///< boundary edges split at the other side's vertices
  std::size_t holes_filled = 0;    ///< corner holes closed
  std::size_t boundary_edges = 0;  ///< boundary edges left at the end
};

/// Exact "which surface" function of a patch (zero on it): used to place the corner point of a hole.
using SurfaceFunction = std::function<double(std::size_t patch, const Eigen::Vector3d& x)>;

/// Welds near-identical vertices, removes collapsed triangles, splits every boundary edge at the
/// boundary vertices of other patches lying on it (so that both sides of a trimming curve share
/// the same vertices) and closes the small holes left at corners where three patches meet.
/// `patch_of_triangle` is kept in step with `mesh.triangles` (and tags).
/// The exact field of the result (negative inside, zero on its boundary): a corner point off it
/// lies where the hole's surfaces meet again somewhere the result does not reach.
using FieldFunction = std::function<double(const Eigen::Vector3d& x)>;

/// Whether the triangle stays within `limit` of the exact surface (|field| <= limit) at its
/// centroid, its edge midpoints and three points between them: where a new triangle spans a
/// crease or a curved patch its error peaks inside, not at its corners.
bool triangle_near_field(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                         const FieldFunction& field, double limit);

SeamStats join_seams(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                     const SeamOptions& options, const SurfaceFunction& surface, const FieldFunction& field);

}  // namespace morph::detail
