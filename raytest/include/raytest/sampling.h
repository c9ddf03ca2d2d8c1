// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file sampling.h
/// Metro-style surface samples: every vertex, points uniform along the edges, and points
/// area-uniform on the faces. Deterministic for a given seed, whatever the thread count.
#include <morph/mesh.h>

#include <cstdint>
#include <vector>

namespace raytest {

/// Where on the mesh a sample was taken.
enum class SampleKind : std::uint8_t { Vertex = 0, Edge = 1, Face = 2 };

/// One surface sample.
struct SurfaceSample {
  Eigen::Vector3d position;  ///< in mesh units
  Eigen::Vector3d normal;    ///< unit; angle-weighted pseudo-normal at vertices and edges, face normal inside
  std::uint32_t triangle = 0;  ///< a triangle the sample lies on (provenance: its FaceTag)
  SampleKind kind = SampleKind::Face;
};

struct SamplingOptions {
  bool vertices = true;          ///< one sample on every vertex used by a triangle
  std::size_t edge_samples = 0;  ///< samples spread uniformly by length over the unique edges
  std::size_t face_samples = 0;  ///< samples area-uniform over the faces
  bool centroids = false;        ///< one sample at every triangle's centroid (small triangles
                                 ///< that area-uniform samples rarely hit are still seen)
  std::uint64_t seed = 1;        ///< seed of the std::mt19937_64 streams
  /// Angle-weighted normals of the vertex samples; without them their normal is zero (only ray
  /// casting needs them, and they cost as much as a closest-point query per vertex).
  bool vertex_normals = true;
};

/// Samples `mesh` as configured. Order: vertices (by index), edge samples, face samples,
/// centroids (by triangle).
/// Throws morph::InputError if the mesh is invalid or has no area but face samples are asked for.
std::vector<SurfaceSample> sample_surface(const morph::TriangleMesh& mesh, const SamplingOptions& options);

/// Angle-weighted vertex normals (unit; zero for a vertex of no triangle).
std::vector<Eigen::Vector3d> angle_weighted_vertex_normals(const morph::TriangleMesh& mesh);

}  // namespace raytest
