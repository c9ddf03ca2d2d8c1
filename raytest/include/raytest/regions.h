// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file regions.h
/// Out-of-band places of a signed deviation merged into regions: one row per connected gouge or
/// excess area of a surface (not one per sample), with its area, largest depth, location and the
/// provenance (moves, G-code lines) of the faces it lies on. Works on per-vertex values of a mesh
/// refined so that no edge is longer than the feature size of interest (see refine_long_edges).
#include <morph/mesh.h>
#include <raytest/deviation.h>

#include <vector>

namespace raytest {

/// A mesh with every triangle cut into strips parallel to its longest edge, each at most max_edge
/// high, and each strip into triangles at most about max_edge long: about 2 area / max_edge^2 plus
/// perimeter / max_edge triangles per parent, so a long sliver costs its length, not its length
/// squared. Each edge's points (evenly spaced, plus the strips' ends of both its triangles) are
/// shared by both its triangles, so a closed mesh stays closed. Tags follow the parent triangle;
/// scalars and colours are dropped.
struct RefinedMesh {
  morph::TriangleMesh mesh;
  std::vector<std::uint32_t> parent;  ///< for each triangle of `mesh`, the triangle it came from
  double max_edge = 0;                ///< the edge length actually used (mesh units)
};

/// Splits long triangles so that edges are at most about `max_edge` (mesh units; the diagonals
/// across a strip up to about 1.5 times it), or the smallest length
/// that keeps the result under `max_triangles` triangles. Throws morph::InputError if max_edge <= 0.
RefinedMesh refine_long_edges(const morph::TriangleMesh& mesh, double max_edge,
                              std::size_t max_triangles = 4'000'000);

/// Provenance of part of a region: a face tag and the worst signed value found on its faces.
struct RegionSource {
  morph::FaceTag tag;
  double worst = 0;  ///< signed value of largest magnitude on faces with this tag (mesh units)
};

/// A connected gouge or excess area.
struct DeviationRegion {
  DeviationClass kind = DeviationClass::Gouge;
  double area = 0;   ///< mesh units^2: one third of every incident triangle per vertex in the region
  double worst = 0;  ///< signed value of largest magnitude (the largest depth), mesh units
  Eigen::Vector3d location = Eigen::Vector3d::Zero();  ///< vertex where `worst` was found
  Eigen::AlignedBox3d bounds;                          ///< of the region's vertices
  std::size_t vertices = 0;
  std::vector<RegionSource> sources;  ///< tags of the faces in the region, worst first
};

/// Regions of vertices outside `band`, connected along the mesh's edges, largest |worst| first
/// (ties by location, so the order is deterministic). `values` has one entry per vertex (NaN:
/// unknown, never in a region). Each region keeps at most `max_sources` sources.
std::vector<DeviationRegion> find_regions(const morph::TriangleMesh& mesh, const std::vector<double>& values,
                                          const ToleranceBand& band, std::size_t max_sources = 5);

}  // namespace raytest
