// SPDX-License-Identifier: Apache-2.0
// The reference's fast per-segment sweep distance against morph's exact one, and its pruned leaf
// sampling against plain sampling of the same functions.
#include <gtest/gtest.h>
#include <morph/sweep_distance.h>

#include <random>

#include "../../vdb_ref/src/sparse_sampling.h"
#include "../../vdb_ref/src/straight_sweep.h"

namespace {

using Eigen::Vector3d;
using vdb_ref::detail::StraightSweep;

morph::Tool make_tool(morph::ToolType type, double radius, double length) {
  morph::Tool tool;
  tool.number = 1;
  tool.type = type;
  tool.radius = radius;
  tool.length = length;
  return tool;
}

// Horizontal, plunging, rising, steep and shallow diagonals, and a zero-length move.
std::vector<std::pair<Vector3d, Vector3d>> segments() {
  return {{Vector3d(0, 0, 0), Vector3d(10, 0, 0)},     {Vector3d(0, 0, 5), Vector3d(0, 0, -5)},
          {Vector3d(1, 2, -4), Vector3d(1, 2, 6)},     {Vector3d(-3, -2, 4), Vector3d(5, 6, -3)},
          {Vector3d(-6, 1, -1), Vector3d(7, -2, 0.4)}, {Vector3d(2, 2, 2), Vector3d(2, 2, 2)},
          {Vector3d(0, 0, 0), Vector3d(0.3, 0.1, 9)}};
}

TEST(StraightSweep, MatchesMorphsExactSweptDistance) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-14.0, 14.0);
  for (const morph::Tool& tool :
       {make_tool(morph::ToolType::BallEnd, 3.0, 8.0), make_tool(morph::ToolType::BallEnd, 1.5, 20.0),
        make_tool(morph::ToolType::Sphere, 2.5, 0.0)}) {
    for (const auto& [a, b] : segments()) {
      const StraightSweep sweep(tool, a, b);
      for (int i = 0; i < 4000; ++i) {
        const Vector3d p(coordinate(random), coordinate(random), coordinate(random));
        ASSERT_NEAR(sweep.distance(p), morph::swept_signed_distance(tool, a, b, p), 1e-9)
            << "tool " << morph::to_string(tool.type) << " radius " << tool.radius << " segment "
            << a.transpose() << " -> " << b.transpose() << " at " << p.transpose();
      }
    }
  }
}

TEST(StraightSweep, PrunedLeafSamplingEqualsSamplingEverySweepEverywhere) {
  const morph::Tool tool = make_tool(morph::ToolType::BallEnd, 2.0, 10.0);
  std::vector<StraightSweep> sweeps;
  // A raster of overlapping passes and a plunge: many sweeps reach each leaf, some deep inside.
  for (int i = 0; i < 8; ++i)
    sweeps.emplace_back(tool, Vector3d(-10, 0.7 * i, -0.3 * i), Vector3d(12, 0.7 * i + 0.5, -0.2 * i));
  sweeps.emplace_back(tool, Vector3d(3, 3, 4), Vector3d(3, 3, -3));
  std::vector<const StraightSweep*> pointers;
  std::vector<vdb_ref::detail::DistanceFunction> functions;
  for (const StraightSweep& s : sweeps) {
    pointers.push_back(&s);
    functions.emplace_back([&s](const Vector3d& p) { return s.distance(p); });
  }
  std::vector<const vdb_ref::detail::DistanceFunction*> function_pointers;
  for (const auto& f : functions) function_pointers.push_back(&f);
  const double voxel = 0.4;
  const float background = 3.0f * static_cast<float>(voxel);
  std::size_t inside = 0, band = 0, outside = 0;
  for (std::int32_t x = -16; x <= 8; x += 8)
    for (std::int32_t y = -8; y <= 16; y += 8)
      for (std::int32_t z = -16; z <= 8; z += 8) {
        std::array<float, vdb_ref::detail::kLeafVoxels> pruned{}, plain{};
        vdb_ref::detail::sample_sweep_leaf({x, y, z}, pointers, voxel, background, pruned);
        vdb_ref::detail::sample_leaf({x, y, z}, function_pointers, voxel, background, plain);
        for (int n = 0; n < vdb_ref::detail::kLeafVoxels; ++n) {
          ASSERT_EQ(pruned[n], plain[n]) << "leaf " << x << "," << y << "," << z << " voxel " << n;
          if (plain[n] <= -background)
            ++inside;
          else if (plain[n] >= background)
            ++outside;
          else
            ++band;
        }
      }
  // The leaves cover all three kinds of voxels, so every branch of the pruning was compared.
  EXPECT_GT(inside, 1000u);
  EXPECT_GT(band, 1000u);
  EXPECT_GT(outside, 1000u);
}

}  // namespace
