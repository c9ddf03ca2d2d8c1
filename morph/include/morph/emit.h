// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file emit.h
/// Generator 2's output: the conformed polygons (conform.h) as a triangle mesh. Vertices are
/// rounded to doubles; a polygon that is only its corners is fanned from its first corner, one
/// with inserted edge vertices from its centroid (a vertex of its own), so no triangle is flat.
/// Provenance per triangle: the stock face, or the move (its global index and G-code line).
#include <morph/conform.h>
#include <morph/mesh.h>

#include <vector>

namespace morph {

/// `move_index[m]` and `move_line[m]` give the global move index and G-code line of sweep m.
TriangleMesh emit(const ConformedSurface& surface, const std::vector<std::int32_t>& move_index,
                  const std::vector<std::int32_t>& move_line);

}  // namespace morph
