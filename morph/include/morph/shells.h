// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file shells.h
/// Shells of a closed stock mesh that lie inside or across one another. Each shell of a stock
/// bounds its own solid; a shell inside another (a void wound outward) or two shells that
/// overlap would have their common volume counted twice and the erosion's surface cross itself.
#include <morph/mesh.h>

#include <cstdint>
#include <optional>

namespace morph {

struct EnclosedShell {
  std::uint32_t inner_triangle = 0;  ///< first triangle of the shell with a vertex inside the other
  std::uint32_t outer_triangle = 0;  ///< first triangle of the shell that encloses that vertex
  std::uint32_t vertex = 0;          ///< the enclosed vertex
  double winding_number = 0.0;       ///< of the outer shell at that vertex (1 inside, 0 outside)
};

/// For a closed, consistently oriented mesh: the first vertex of one edge-connected shell that
/// another shell encloses (generalized winding number above 1/2), or nothing when every shell
/// lies outside every other (vertices on another shell's surface count as outside). One shell
/// never conflicts with itself.
std::optional<EnclosedShell> find_enclosed_shell(const TriangleMesh& mesh);

}  // namespace morph
