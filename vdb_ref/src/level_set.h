// SPDX-License-Identifier: Apache-2.0
#pragma once
// Internal interface between the geometry code of vdb_ref and its single OpenVDB translation unit
// (level_set_openvdb.cpp). No OpenVDB type appears here, so only that one file pays for OpenVDB's
// headers.
#include <morph/mesh.h>
#include <morph/progress.h>
#include <vdb_ref/reference.h>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace vdb_ref::detail {

/// Integer voxel coordinates; voxel (i, j, k) is centred at world (i, j, k) * voxel_size.
using VoxelCoord = std::array<std::int32_t, 3>;

/// Voxels per edge of an OpenVDB leaf node (FloatTree's leaf is 8^3).
constexpr int kLeafDim = 8;
constexpr int kLeafVoxels = kLeafDim * kLeafDim * kLeafDim;

/// Offset of local voxel (x, y, z) in a leaf's value array, OpenVDB's layout.
inline int leaf_offset(int x, int y, int z) {
  return (x << 6) | (y << 3) | z;
}

/// A narrow-band level set before it becomes an OpenVDB grid: sampled leaf nodes (values clamped
/// to +-background; |value| < background marks an active voxel) and cubic blocks that lie wholly
/// inside deeper than the band. Everything else is outside.
struct SparseLevelSet {
  std::vector<VoxelCoord> leaf_origins;  ///< multiples of kLeafDim
  std::vector<std::array<float, kLeafVoxels>> leaf_values;
  std::vector<VoxelCoord> interior_origins;  ///< block origins, multiples of their size
  std::vector<int> interior_sizes;           ///< block edge in voxels (a multiple of kLeafDim)

  std::size_t bytes() const {
    return leaf_origins.capacity() * sizeof(VoxelCoord) + leaf_values.capacity() * sizeof(leaf_values[0]) +
           interior_origins.capacity() * sizeof(VoxelCoord) + interior_sizes.capacity() * sizeof(int);
  }
  void release() { *this = SparseLevelSet{}; }
};

/// Measures of one segment of the erosion level set, before cavities are merged into pieces.
struct Segment {
  double volume = 0.0;  ///< negative for the wall of an internal void
  double area = 0.0;
  Eigen::AlignedBox3d bounds;
  int enclosing = -1;  ///< for a void: index of the solid segment around it
};

/// The OpenVDB side of the reference: grids, CSG, rebuild, meshing, segmentation and measures.
/// Every call polls `progress` through an OpenVDB interrupter and throws morph::Interrupted.
class LevelSetPipeline {
 public:
  LevelSetPipeline(double voxel_size, double half_width_voxels, morph::Progress* progress);
  ~LevelSetPipeline();
  LevelSetPipeline(const LevelSetPipeline&) = delete;
  LevelSetPipeline& operator=(const LevelSetPipeline&) = delete;

  /// Background (outside) value of the level sets, job units: half width * voxel size.
  float background() const;

  /// The stock from sampled leaves (box, cylinder).
  void set_stock(const SparseLevelSet& stock);
  /// The stock from a closed, outward triangle mesh (OpenVDB mesh-to-volume).
  void set_stock_mesh(const morph::TriangleMesh& mesh);
  /// The union of the sweeps.
  void set_sweep(const SparseLevelSet& sweep);
  /// erosion = stock \ sweep (level-set CSG difference), rebuilt to a clean signed distance.
  void difference();
  /// The erosion's zero iso-surface: outward triangles, untagged.
  morph::TriangleMesh mesh() const;
  /// Disjoint surfaces of the erosion with their measures.
  std::vector<Segment> segments() const;
  /// Writes the erosion grid; throws morph::IoError.
  /// `metadata` (name, value) is stored on the grid as string metadata.
  void write(const std::string& path,
             const std::vector<std::pair<std::string, std::string>>& metadata = {}) const;

  std::size_t active_voxels() const;
  /// Bytes held by the grids alive now, or the largest transient use inside one call if larger.
  std::size_t memory_bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vdb_ref::detail
