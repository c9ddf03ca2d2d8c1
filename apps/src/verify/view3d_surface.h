// SPDX-License-Identifier: Apache-2.0
#pragma once
// The surface that the report's 3D view embeds. A browser draws a few hundred thousand triangles
// well, and every embedded triangle costs about 40 bytes of report; a generator mesh of a large
// part can have millions. So the view gets the part refined to a fixed fraction of its size when
// it is small, and decimated (OpenMesh's quadric decimater) to a cap when it is large.
#include <morph/mesh.h>

#include <cstddef>

namespace morphmill {

/// The triangles the 3D view embeds at most by default (about 6 MB of report).
inline constexpr std::size_t kView3dMaxTriangles = 150'000;

struct ViewSurface {
  morph::TriangleMesh mesh;          ///< with a face tag per triangle when the source had tags
  std::size_t source_triangles = 0;  ///< triangles of the mesh it was made from
  bool decimated = false;            ///< true when it has fewer triangles than the source
};

/// `mesh` itself when it has at most `max_triangles` triangles, else `mesh` decimated to at most
/// `max_triangles`. A decimated face keeps the tag (move, G-code line) of the source face nearest
/// its centroid. Throws std::invalid_argument when max_triangles is 0.
ViewSurface decimated_for_view(const morph::TriangleMesh& mesh,
                               std::size_t max_triangles = kView3dMaxTriangles);

/// `mesh` refined so that no edge is longer than 1/150 of its diagonal (as far as `max_triangles`
/// allows), or decimated to `max_triangles` when it already has more.
ViewSurface view_surface(const morph::TriangleMesh& mesh, std::size_t max_triangles = kView3dMaxTriangles);

}  // namespace morphmill
