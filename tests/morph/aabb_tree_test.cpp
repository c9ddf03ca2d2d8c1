// SPDX-License-Identifier: Apache-2.0
// The bounding-volume hierarchy's queries against brute force over random boxes.
#include <morph/aabb_tree.h>

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <utility>

namespace {

std::vector<Eigen::AlignedBox3d> random_boxes(std::size_t count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> at(0.0, 10.0), size(0.0, 1.5);
  std::vector<Eigen::AlignedBox3d> boxes;
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Vector3d low(at(random), at(random), at(random));
    boxes.emplace_back(low, low + Eigen::Vector3d(size(random), size(random), size(random)));
  }
  // Touching boxes count as overlapping (closed boxes), and equal ones too.
  boxes.emplace_back(Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1));
  boxes.emplace_back(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(2, 1, 1));
  boxes.emplace_back(Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(2, 1, 1));
  return boxes;
}

TEST(AabbTree, EveryOverlappingPairOnceWhateverTheParts) {
  for (std::size_t count : {0u, 1u, 3u, 7u, 300u}) {
    const std::vector<Eigen::AlignedBox3d> boxes = random_boxes(count, 17 + static_cast<unsigned>(count));
    std::set<std::pair<std::uint32_t, std::uint32_t>> expected;
    for (std::uint32_t a = 0; a < boxes.size(); ++a)
      for (std::uint32_t b = a + 1; b < boxes.size(); ++b)
        if (boxes[a].intersects(boxes[b])) expected.insert({a, b});
    ASSERT_GT(expected.size(), 0u);
    const morph::AabbTree tree(boxes);
    for (std::size_t parts : {1u, 2u, 5u, 64u, 100000u}) {
      const std::vector<morph::AabbTree::PairWalk> walks = tree.pair_walks(parts);
      std::set<std::pair<std::uint32_t, std::uint32_t>> found;
      std::size_t visits = 0;
      for (const morph::AabbTree::PairWalk& walk : walks)
        tree.for_each_overlapping_pair(walk, [&](std::uint32_t a, std::uint32_t b) {
          EXPECT_LT(a, b);
          found.insert({a, b});
          ++visits;
        });
      EXPECT_EQ(found, expected) << count << " boxes, " << parts << " parts";
      EXPECT_EQ(visits, expected.size()) << "a pair visited twice";
      if (count == 300 && parts >= 64) {
        EXPECT_GE(walks.size(), 64u);
      }
    }
  }
}

// A tree large enough that its subtrees are built in parallel: every query finds what brute
// force finds, and every build visits the items in the same order (the layout follows from the
// item counts alone, whatever thread builds which subtree).
TEST(AabbTree, ALargeTreeBuiltInParallelAnswersAsBruteForceAndAlwaysAlike) {
  const std::vector<Eigen::AlignedBox3d> boxes = random_boxes(60000, 5);
  std::mt19937 random(9);
  std::uniform_real_distribution<double> at(0.0, 10.0);
  std::vector<Eigen::AlignedBox3d> queries;
  for (int q = 0; q < 100; ++q) {
    const Eigen::Vector3d low(at(random), at(random), at(random));
    queries.emplace_back(low, low + Eigen::Vector3d(0.5, 0.5, 0.5));
  }
  std::vector<std::size_t> first_order;
  for (int build = 0; build < 4; ++build) {
    const morph::AabbTree tree(boxes);
    std::vector<std::size_t> order;
    for (const Eigen::AlignedBox3d& query : queries) {
      std::set<std::size_t> found, expected;
      tree.for_each_overlapping(query, [&](std::size_t i) {
        found.insert(i);
        order.push_back(i);
      });
      if (build == 0) {
        for (std::size_t i = 0; i < boxes.size(); ++i)
          if (boxes[i].intersects(query)) expected.insert(i);
        EXPECT_EQ(found, expected);
      }
    }
    if (build == 0) {
      ASSERT_GT(order.size(), 1000u);
      first_order = order;
    } else {
      EXPECT_EQ(order, first_order) << "build " << build;
    }
  }
}

}  // namespace

// for_each_overlapping_while() meets the items in for_each_overlapping()'s order and stops at the
// first visit that returns false: every prefix of the full walk, and the full walk when none does.
TEST(AabbTree, AWalkThatStopsMeetsAPrefixOfTheFullWalk) {
  const std::vector<Eigen::AlignedBox3d> boxes = random_boxes(3000, 23);
  const morph::AabbTree tree(boxes);
  const Eigen::AlignedBox3d query(Eigen::Vector3d(3, 3, 3), Eigen::Vector3d(6, 6, 6));
  std::vector<std::uint32_t> full;
  tree.for_each_overlapping(query, [&](std::uint32_t i) { full.push_back(i); });
  ASSERT_GT(full.size(), 20u);
  std::vector<std::uint32_t> all;
  EXPECT_TRUE(tree.for_each_overlapping_while(query, [&](std::uint32_t i) {
    all.push_back(i);
    return true;
  }));
  EXPECT_EQ(all, full);
  for (std::size_t stop : {std::size_t{0}, std::size_t{1}, full.size() / 2, full.size() - 1}) {
    std::vector<std::uint32_t> met;
    EXPECT_FALSE(tree.for_each_overlapping_while(query, [&](std::uint32_t i) {
      met.push_back(i);
      return met.size() <= stop;
    }));
    EXPECT_EQ(met,
              std::vector<std::uint32_t>(full.begin(), full.begin() + static_cast<std::ptrdiff_t>(stop + 1)));
  }
}
