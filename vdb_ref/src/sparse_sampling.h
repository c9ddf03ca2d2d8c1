// SPDX-License-Identifier: Apache-2.0
#pragma once
// Sparse narrow-band sampling of signed distance functions on the voxel grid, culled per block so
// that only leaf nodes near the zero set are ever sampled (work ~ surface area / voxel^2).
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "level_set.h"
#include "straight_sweep.h"

namespace vdb_ref::detail {

/// A signed distance (job units, negative inside) that is 1-Lipschitz and exact outside and near
/// its zero set; inside it may be a bound closer to zero than the truth (a union's minimum).
using DistanceFunction = std::function<double(const Eigen::Vector3d&)>;

/// Leaf nodes that may hold voxels within the band of f's zero set, and blocks wholly inside f
/// deeper than the band, over the voxels [lo, hi] (inclusive).
struct BlockLists {
  std::vector<VoxelCoord> leaves;
  std::vector<VoxelCoord> interior_origins;
  std::vector<int> interior_sizes;
};

/// Voxel box [lo, hi] covering the world box grown by `margin` (job units).
std::pair<VoxelCoord, VoxelCoord> voxel_range(const Eigen::AlignedBox3d& box, double voxel_size,
                                              double margin);

/// Culls blocks (the coarsest as large as the range) down to leaf nodes by the distance at each block's
/// centre against its half diagonal plus the band, appending to `out`.
void enumerate_blocks(const DistanceFunction& f, const VoxelCoord& lo, const VoxelCoord& hi,
                      double voxel_size, double band, BlockLists& out);

/// World position of a voxel centre.
inline Eigen::Vector3d voxel_centre(const VoxelCoord& c, double voxel_size) {
  return Eigen::Vector3d(c[0], c[1], c[2]) * voxel_size;
}

/// Samples every voxel of one leaf node: the minimum over `functions`, clamped to +-background.
void sample_leaf(const VoxelCoord& origin, const std::vector<const DistanceFunction*>& functions,
                 double voxel_size, float background, std::array<float, kLeafVoxels>& values);

/// Samples every voxel of one leaf node of the union of `sweeps`: the same values as sample_leaf
/// with their distance functions, but a sweep is evaluated at a voxel only while its distance at
/// the centre of the voxel's 4^3 sub-block, less the voxel's offset from that centre (the distance
/// is 1-Lipschitz), could still lower the voxel's value below the band's clamp or the minimum so
/// far. Visiting the sweeps nearest first makes most voxels cost one or two evaluations.
void sample_sweep_leaf(const VoxelCoord& origin, const std::vector<const StraightSweep*>& sweeps,
                       double voxel_size, float background, std::array<float, kLeafVoxels>& values);

}  // namespace vdb_ref::detail
