// SPDX-License-Identifier: Apache-2.0
// Disjoint sets whose representative is the smallest member, whatever the order of the unions.
#include <morph/union_find.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <utility>

namespace {

TEST(UnionFind, TheSmallestMemberStandsForItsSetWhateverTheOrder) {
  // Sets {0, 3, 7}, {1, 5}, {2}, {4, 6, 8, 9}.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs{{7, 3}, {3, 0}, {5, 1}, {9, 8},
                                                             {8, 6}, {6, 4}, {0, 7}};
  const std::vector<std::uint32_t> expected{0, 1, 2, 0, 4, 1, 4, 0, 4, 4};
  std::mt19937 random(11);
  morph::UnionFind sets;
  for (int trial = 0; trial < 20; ++trial) {
    std::shuffle(pairs.begin(), pairs.end(), random);
    sets.reset(expected.size());
    for (const auto& [a, b] : pairs) trial % 2 ? sets.unite(a, b) : sets.unite(b, a);
    for (std::uint32_t v = 0; v < expected.size(); ++v) EXPECT_EQ(sets.find(v), expected[v]) << v;
  }
}

}  // namespace
