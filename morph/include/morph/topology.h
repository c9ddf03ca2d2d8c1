// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file topology.h
/// Topology report of an indexed triangle mesh: what `morphmill mesh-info` prints and what the
/// generator's tests require of a closed manifold.
#include <morph/mesh.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace morph {

/// One edge-connected piece of a mesh.
struct PieceTopology {
  std::size_t triangles = 0;      ///< proper triangles (three distinct vertex indices)
  long euler_characteristic = 0;  ///< V - E + F of the piece alone
  bool closed_manifold = false;   ///< no boundary, non-manifold or inconsistent edge, no
                                  ///< non-manifold vertex in the piece
  /// Genus (handles) of a closed oriented piece, (2 - V + E - F) / 2; -1 where that is not one.
  long genus = -1;
};

struct TopologyReport {
  std::size_t vertices = 0;  ///< vertices referenced by at least one triangle
  std::size_t unreferenced_vertices = 0;
  std::size_t triangles = 0;
  std::size_t degenerate_triangles = 0;   ///< repeated vertex index or zero area
  std::size_t edges = 0;                  ///< undirected edges
  std::size_t boundary_edges = 0;         ///< used by exactly one triangle
  std::size_t non_manifold_edges = 0;     ///< used by three or more triangles
  std::size_t inconsistent_edges = 0;     ///< two triangles traversing the edge the same way
  std::size_t non_manifold_vertices = 0;  ///< whose triangle fan is not a single disc or half-disc
  std::size_t components = 0;             ///< edge-connected components of triangles
  long euler_characteristic = 0;          ///< V - E + F
  double volume = 0.0;                    ///< enclosed volume (divergence theorem)
  double area = 0.0;
  /// Per piece, in the order of their smallest triangle index (see connected_components).
  std::vector<PieceTopology> pieces;

  /// Closed, oriented 2-manifold: no boundary, no non-manifold edges or vertices, consistent.
  bool closed_manifold() const {
    return boundary_edges == 0 && non_manifold_edges == 0 && inconsistent_edges == 0 &&
           non_manifold_vertices == 0 && triangles > 0;
  }
};

TopologyReport topology_report(const TriangleMesh& mesh);

/// The vertices whose triangles (collapsed ones left out) do not form a single disc or
/// half-disc, in increasing order: where two sheets of the surface meet at one point.
std::vector<std::uint32_t> non_manifold_vertices(const TriangleMesh& mesh);

/// The same among the vertices `among` only (sorted, unique; each must index a vertex): one
/// pass over the triangles, fans of those vertices alone.
std::vector<std::uint32_t> non_manifold_vertices(const TriangleMesh& mesh,
                                                 const std::vector<std::uint32_t>& among);

/// Triangle -> component index (edge-connected), components numbered by their smallest
/// triangle index so the numbering is deterministic. Returns the number of components.
std::size_t connected_components(const TriangleMesh& mesh, std::vector<std::uint32_t>& component_of_triangle);

}  // namespace morph
