// SPDX-License-Identifier: Apache-2.0
#include "sparse_sampling.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vdb_ref::detail {

namespace {

constexpr int kSmallestTopBlock = 64;  // voxels per edge of the coarsest culling block, at least

std::int64_t floor_to_multiple(std::int64_t v, std::int64_t m) {
  const std::int64_t q = v >= 0 ? v / m : -((-v + m - 1) / m);
  return q * m;
}

void visit(const DistanceFunction& f, const VoxelCoord& origin, int size, const VoxelCoord& lo,
           const VoxelCoord& hi, double voxel_size, double band, BlockLists& out) {
  for (int a = 0; a < 3; ++a)
    if (origin[a] > hi[a] || origin[a] + size - 1 < lo[a]) return;
  const double half = 0.5 * (size - 1);
  const Eigen::Vector3d centre =
      (Eigen::Vector3d(origin[0], origin[1], origin[2]) + Eigen::Vector3d::Constant(half)) * voxel_size;
  // Every voxel centre of the block is within half_diagonal of the block centre, and f is
  // 1-Lipschitz; the small slack absorbs the rounding of the distance functions.
  const double reach = std::sqrt(3.0) * half * voxel_size + band + 1e-6 * voxel_size;
  const double d = f(centre);
  if (d > reach) return;
  if (d < -reach) {
    out.interior_origins.push_back(origin);
    out.interior_sizes.push_back(size);
    return;
  }
  if (size == kLeafDim) {
    out.leaves.push_back(origin);
    return;
  }
  const int h = size / 2;
  for (int dx = 0; dx < 2; ++dx)
    for (int dy = 0; dy < 2; ++dy)
      for (int dz = 0; dz < 2; ++dz)
        visit(f, {origin[0] + dx * h, origin[1] + dy * h, origin[2] + dz * h}, h, lo, hi, voxel_size, band,
              out);
}

}  // namespace

std::pair<VoxelCoord, VoxelCoord> voxel_range(const Eigen::AlignedBox3d& box, double voxel_size,
                                              double margin) {
  VoxelCoord lo, hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = static_cast<std::int32_t>(std::floor((box.min()[a] - margin) / voxel_size)) - 1;
    hi[a] = static_cast<std::int32_t>(std::ceil((box.max()[a] + margin) / voxel_size)) + 1;
  }
  return {lo, hi};
}

void enumerate_blocks(const DistanceFunction& f, const VoxelCoord& lo, const VoxelCoord& hi,
                      double voxel_size, double band, BlockLists& out) {
  for (int a = 0; a < 3; ++a)
    if (lo[a] > hi[a]) return;
  // The coarsest blocks are as large as the whole range (at most 2 per axis cover it), so even a
  // long diagonal move's box is culled hierarchically, never scanned block by block.
  std::int32_t extent = 0;
  for (int a = 0; a < 3; ++a) extent = std::max(extent, hi[a] - lo[a] + 1);
  int top = kSmallestTopBlock;
  while (top < extent && top < (1 << 29)) top *= 2;
  std::array<std::int64_t, 3> start;
  for (int a = 0; a < 3; ++a) start[a] = floor_to_multiple(lo[a], top);
  for (std::int64_t x = start[0]; x <= hi[0]; x += top)
    for (std::int64_t y = start[1]; y <= hi[1]; y += top)
      for (std::int64_t z = start[2]; z <= hi[2]; z += top)
        visit(f, {static_cast<std::int32_t>(x), static_cast<std::int32_t>(y), static_cast<std::int32_t>(z)},
              top, lo, hi, voxel_size, band, out);
}

void sample_leaf(const VoxelCoord& origin, const std::vector<const DistanceFunction*>& functions,
                 double voxel_size, float background, std::array<float, kLeafVoxels>& values) {
  for (int x = 0; x < kLeafDim; ++x)
    for (int y = 0; y < kLeafDim; ++y)
      for (int z = 0; z < kLeafDim; ++z) {
        const Eigen::Vector3d p = voxel_centre({origin[0] + x, origin[1] + y, origin[2] + z}, voxel_size);
        double d = std::numeric_limits<double>::infinity();
        for (const DistanceFunction* f : functions) d = std::min(d, (*f)(p));
        values[leaf_offset(x, y, z)] = static_cast<float>(
            std::clamp(d, -static_cast<double>(background), static_cast<double>(background)));
      }
}

void sample_sweep_leaf(const VoxelCoord& origin, const std::vector<const StraightSweep*>& sweeps,
                       double voxel_size, float background, std::array<float, kLeafVoxels>& values) {
  constexpr int kSub = kLeafDim / 2;
  constexpr double kSubCentre = 0.5 * (kSub - 1);
  const double clamp = static_cast<double>(background);
  // The pruning must never skip a sweep whose computed distance could still win through
  // rounding: the same slack as the block culling.
  const double slack = 1e-6 * voxel_size;
  std::vector<std::pair<double, std::uint32_t>> nearest_first(sweeps.size());
  for (int sx = 0; sx < kLeafDim; sx += kSub)
    for (int sy = 0; sy < kLeafDim; sy += kSub)
      for (int sz = 0; sz < kLeafDim; sz += kSub) {
        const Eigen::Vector3d centre = (Eigen::Vector3d(origin[0] + sx, origin[1] + sy, origin[2] + sz) +
                                        Eigen::Vector3d::Constant(kSubCentre)) *
                                       voxel_size;
        for (std::size_t k = 0; k < sweeps.size(); ++k)
          nearest_first[k] = {sweeps[k]->distance(centre), static_cast<std::uint32_t>(k)};
        std::sort(nearest_first.begin(), nearest_first.end());
        for (int x = 0; x < kSub; ++x)
          for (int y = 0; y < kSub; ++y)
            for (int z = 0; z < kSub; ++z) {
              const Eigen::Vector3d p =
                  voxel_centre({origin[0] + sx + x, origin[1] + sy + y, origin[2] + sz + z}, voxel_size);
              const double reach =
                  Eigen::Vector3d(x - kSubCentre, y - kSubCentre, z - kSubCentre).norm() * voxel_size + slack;
              // value = min(clamp, min over sweeps), then clamped below: as sample_leaf.
              double value = clamp;
              for (const auto& [centre_distance, k] : nearest_first) {
                if (centre_distance - reach >= value) break;  // this and every later sweep
                const double d = sweeps[k]->distance_within(p, -clamp, value);
                if (d < value) {
                  value = d;
                  if (value <= -clamp) break;
                }
              }
              values[leaf_offset(sx + x, sy + y, sz + z)] = static_cast<float>(std::max(value, -clamp));
            }
      }
}

}  // namespace vdb_ref::detail
