// SPDX-License-Identifier: Apache-2.0
#include <raytest/deviation_memory.h>

#include <stdexcept>

namespace raytest {

namespace {

// Bytes per unit, from a linear fit of measured peaks (1M/200k/50k-triangle spheres, 10 to 2M
// samples, with and without pictures); each within 5% of the measurement it came from.
constexpr double kMeshBytesPerTriangle = 30;
// Index: Embree's scene plus SurfaceQuery's 136-byte record per triangle (corners and bounding
// planes, surface_query.cpp); refitted when the record replaced 48-byte boxes (+88 B measured).
constexpr double kIndexBytesPerTriangle = 230;
constexpr double kBytesPerSample = 80;
constexpr double kVertexValueBytesPerTriangle = 80;
constexpr double kRenderBytesPerTriangle = 120;
constexpr double kBytesPerPixel = 8;

}  // namespace

std::size_t sample_count(const morph::TriangleMesh& mesh, const SamplingOptions& sampling) {
  std::size_t n = sampling.edge_samples + sampling.face_samples;
  if (sampling.vertices) n += mesh.vertex_count();
  if (sampling.centroids) n += mesh.triangle_count();
  return n;
}

DeviationMemory estimate_deviation_memory(const DeviationWork& work) {
  if (!work.a || !work.b) throw std::invalid_argument("estimate_deviation_memory: both meshes are needed");
  const double a_triangles = double(work.a->triangle_count());
  const double b_triangles = double(work.b->triangle_count());
  DeviationMemory m;
  m.meshes = kMeshBytesPerTriangle * (a_triangles + b_triangles);
  m.indexes = kIndexBytesPerTriangle * (b_triangles + (work.two_sided ? a_triangles : 0.0));
  m.samples = kBytesPerSample * double(sample_count(*work.a, work.sampling) +
                                       (work.two_sided ? sample_count(*work.b, work.sampling) : 0));
  if (work.vertex_values || work.picture_pixels > 0) m.pictures += kVertexValueBytesPerTriangle * a_triangles;
  if (work.picture_pixels > 0)
    m.pictures += kRenderBytesPerTriangle * a_triangles + kBytesPerPixel * double(work.picture_pixels);
  return m;
}

}  // namespace raytest
