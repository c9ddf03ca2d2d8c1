// SPDX-License-Identifier: Apache-2.0
#include "generator/double_double_filter.h"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <array>
#include <cmath>
#include <random>

namespace {

using morph::exact::ExactRows;
using morph::exact::Row;
using morph::exact::Width;

Row row(const Eigen::Vector3d& n, double offset) {
  return {n.x(), n.y(), n.z(), offset};
}

Eigen::Vector3d random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Eigen::Vector3d(g(rng), g(rng), g(rng)).normalized();
}

// Four unit planes through a point, offsets n·p rounded: determinants a few ulps of their
// permanent from zero, which the double filter cannot decide. The double-word filter decides
// nearly all of them, and always as the exact integers do.
TEST(DoubleDoubleFilter, NearTiesAreDecidedAsExactly) {
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> coord(-80, 80);
  int decided = 0, nonzero = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const Eigen::Vector3d point(coord(rng), coord(rng), coord(rng));
    std::array<Row, 4> rows;
    for (Row& r : rows) {
      const Eigen::Vector3d n = random_unit(rng);
      r = row(n, n.dot(point));
    }
    const int exact = ExactRows(rows).det4_sign(Width::Unbounded);
    const int filtered = morph::exact::double_double_det4_sign(rows);
    nonzero += exact != 0;
    if (filtered != 0) {
      ++decided;
      ASSERT_EQ(filtered, exact) << "trial " << trial;
    }
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> o{};
      for (int k = 0, n = 0; k < 4; ++k)
        if (k != skip) o[n++] = k;
      const int minor = morph::exact::double_double_minor_sign(rows[o[0]], rows[o[1]], rows[o[2]]);
      ASSERT_NE(minor, 0);  // random normals: far from dependent
      ASSERT_EQ(minor, ExactRows(rows).minor_sign(o[0], o[1], o[2], Width::Unbounded));
    }
  }
  EXPECT_GT(nonzero, 3900);
  EXPECT_GT(decided, nonzero * 95 / 100) << "near-ties a few ulps off should not need integers";
}

// Exact zeros (integer normals, a dyadic point) and exactly dependent normals are never decided:
// they go on to the integers.
TEST(DoubleDoubleFilter, ExactZerosAreLeftToTheIntegers) {
  std::mt19937_64 rng(5);
  std::uniform_int_distribution<int> small(-9, 9), coord(-512, 512);
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Vector3d point(coord(rng) / 16.0, coord(rng) / 16.0, coord(rng) / 16.0);
    std::array<Row, 4> rows;
    for (Row& r : rows) {
      const Eigen::Vector3d n(small(rng), small(rng), small(rng));
      r = row(n, n.dot(point));
    }
    EXPECT_EQ(morph::exact::double_double_det4_sign(rows), 0);
    // The fourth normal a combination of two others: the minor of rows 1..3 is zero.
    const Row dependent{rows[1][0] - 2 * rows[2][0], rows[1][1] - 2 * rows[2][1], rows[1][2] - 2 * rows[2][2],
                        0};
    EXPECT_EQ(morph::exact::double_double_minor_sign(rows[1], rows[2], dependent), 0);
  }
}

// A value just above the double-word bound: 1 + 2^-80 against 1 in the offsets of otherwise
// exact rows is decided (the double filter cannot see 2^-80), and its sign is right.
TEST(DoubleDoubleFilter, SeesBelowTheDoubleFilter) {
  const std::array<Row, 4> rows{Row{1, 0, 0, 1}, Row{0, 1, 0, 1}, Row{0, 0, 1, 1},
                                Row{1, 1, 1, 3 + std::ldexp(1.0, -50)}};
  // det = offset_3·1 - (1 + 1 + 1) = 2^-50 with the expansion's signs: the exact sign decides.
  const int exact = ExactRows(rows).det4_sign(Width::Unbounded);
  ASSERT_NE(exact, 0);
  EXPECT_EQ(morph::exact::double_double_det4_sign(rows), exact);
}

}  // namespace
