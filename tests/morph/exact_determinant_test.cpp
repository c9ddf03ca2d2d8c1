// SPDX-License-Identifier: Apache-2.0
#include "generator/exact_determinant.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <random>
#include <stdexcept>

namespace {

using morph::exact::ExactRows;
using morph::exact::Row;
using morph::exact::Width;

Row row(const Eigen::Vector3d& n, double offset) {
  return {n.x(), n.y(), n.z(), offset};
}

// Every type the bound allows gives the unbounded (cpp_int) sign, for the 4×4 determinant and
// all four 3×3 minors of the normals; returns how many fixed types took part.
int expect_tiers_agree(const std::array<Row, 4>& rows) {
  const ExactRows exact(rows);
  const int det = exact.det4_sign(Width::Unbounded);
  const int needed4 = exact.width(0) + exact.width(1) + exact.width(2) + exact.width(3) + 5;
  int compared = 0;
  const std::array<std::pair<Width, int>, 3> tiers{
      {{Width::Bits128, 127}, {Width::Bits256, 256}, {Width::Bits512, 512}}};
  for (const auto& [width, bits] : tiers) {
    if (needed4 > bits) {
      EXPECT_THROW(exact.det4_sign(width), std::logic_error);
      continue;
    }
    EXPECT_EQ(exact.det4_sign(width), det);
    ++compared;
  }
  EXPECT_EQ(exact.det4_sign(), det);
  const std::array<std::array<int, 3>, 4> minors{{{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}}};
  for (const auto& m : minors) {
    const int expected = exact.minor_sign(m[0], m[1], m[2], Width::Unbounded);
    EXPECT_EQ(exact.minor_sign(m[0], m[1], m[2]), expected);
    EXPECT_EQ(exact.minor_sign(m[2], m[1], m[0]), -expected);
  }
  return compared;
}

TEST(ExactDeterminant, RandomUnitPlanesAgreeAcrossTiers) {
  std::mt19937_64 rng(4);
  std::normal_distribution<double> g;
  std::uniform_real_distribution<double> offset(-100, 100);
  int fixed = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    std::array<Row, 4> rows;
    for (Row& r : rows) r = row(Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized(), offset(rng));
    fixed += expect_tiers_agree(rows);
  }
  EXPECT_GT(fixed, 2000) << "unit normals should fit int512 (and often int256)";
}

// Forced degeneracies: planes through one point (det 0 when the offsets are exact), parallel
// and coincident rows, dependent normals (minor 0), tiny entries next to large ones.
TEST(ExactDeterminant, DegenerateSetsAgreeAcrossTiers) {
  std::mt19937_64 rng(9);
  std::uniform_int_distribution<int> small(-40, 40), coord(-4096, 4096);
  int zeros = 0, fixed128 = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // Integer normals and a dyadic point: exact offsets, so four planes through it give det 0.
    const Eigen::Vector3d point(coord(rng) / 64.0, coord(rng) / 64.0, coord(rng) / 64.0);
    std::array<Row, 4> rows;
    for (Row& r : rows) {
      const Eigen::Vector3d n(small(rng), small(rng), small(rng));
      r = row(n, n.dot(point));
    }
    switch (trial % 4) {
      case 1:
        rows[3] = rows[1];
        break;  // coincident
      case 2:
        rows[2] = {2 * rows[0][0], 2 * rows[0][1], 2 * rows[0][2], rows[0][3] + 1};
        break;  // parallel: minors 0
      case 3:
        rows[3][3] += std::ldexp(1.0, -40);
        break;  // off by a tiny amount: det ≠ 0
      default:
        break;
    }
    const ExactRows exact(rows);
    zeros += exact.det4_sign(Width::Unbounded) == 0;
    fixed128 += exact.width(0) + exact.width(1) + exact.width(2) + exact.width(3) + 5 <= 127;
    expect_tiers_agree(rows);
  }
  EXPECT_GE(zeros, 1500);  // the concurrent and coincident cases (a quarter each and more)
  EXPECT_GT(fixed128, 1500) << "small integer planes should fit __int128";
}

TEST(ExactDeterminant, WideRowsGoUnbounded) {
  // A row with entries 2^600 apart is wider than 512 bits: only cpp_int evaluates it.
  const std::array<Row, 4> rows{Row{1, std::ldexp(1.0, -300), 0, std::ldexp(1.0, 300)}, Row{0, 1, 0, 2},
                                Row{0, 0, 1, 3}, Row{1, 1, 1, 7}};
  const ExactRows exact(rows);
  EXPECT_GT(exact.width(0), 512);
  EXPECT_THROW(exact.det4_sign(Width::Bits512), std::logic_error);
  // det = 2^300·(-1)·det[[0,1,0],[0,0,1],[1,1,1]] + (terms far smaller): its sign is -1·1 = -1.
  EXPECT_EQ(exact.det4_sign(), exact.det4_sign(Width::Unbounded));
  EXPECT_NE(exact.det4_sign(), 0);
}

}  // namespace
