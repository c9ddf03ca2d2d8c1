// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file deviation_memory.h
/// What a deviation measurement will hold in memory at its peak, estimated from the two meshes'
/// sizes and the options before anything is indexed or sampled, so that a command can refuse work
/// that would not fit (`--memory-cap`) instead of being killed half way.
#include <morph/mesh.h>
#include <raytest/sampling.h>

#include <cstddef>

namespace raytest {

/// The work of one `deviation` run, as far as memory is concerned.
struct DeviationWork {
  const morph::TriangleMesh* a = nullptr;  ///< sampled (A -> B)
  const morph::TriangleMesh* b = nullptr;  ///< indexed (and sampled when two-sided)
  SamplingOptions sampling;
  bool two_sided = true;
  bool vertex_values = false;      ///< a deviation value and a colour per vertex of A (heatmap/VTP/PNG)
  std::size_t picture_pixels = 0;  ///< width x height of a rendered picture of A, 0 for none
};

/// Bytes, by what holds them. Coefficients measured on meshes of 50k to 1M triangles (peak
/// resident memory of `morphmill deviation` by /usr/bin/time, see docs/design/reliability.md).
struct DeviationMemory {
  double meshes = 0;    ///< both meshes as read: indexed triangles, vertices, tags
  double indexes = 0;   ///< Embree scenes and closest-point data of each queried mesh
  double samples = 0;   ///< sample points and their results, on each sampled side
  double pictures = 0;  ///< per-vertex values and colours, the render scene and its pixels
  double total() const { return meshes + indexes + samples + pictures; }
};

/// Number of samples `sampling` takes on `mesh` (vertices used by a triangle, edge, face and
/// centroid samples).
std::size_t sample_count(const morph::TriangleMesh& mesh, const SamplingOptions& sampling);

/// The estimate for `work` (both meshes given). Excludes the process itself (code, libraries).
DeviationMemory estimate_deviation_memory(const DeviationWork& work);

}  // namespace raytest
