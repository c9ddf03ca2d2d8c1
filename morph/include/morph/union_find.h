// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file union_find.h
/// Disjoint sets over the indices 0..n-1 whose representative is always the smallest member: the
/// sets, and which member stands for each, do not depend on the order of the unions, so serial and
/// parallel passes that unite the same pairs agree. Path halving; no union by rank (the smallest
/// root must win).
#include <cstddef>
#include <cstdint>
#include <numeric>
#include <vector>

namespace morph {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n = 0) { reset(n); }
  /// n singletons again, reusing the storage.
  void reset(std::size_t n) {
    parent_.resize(n);
    std::iota(parent_.begin(), parent_.end(), std::uint32_t{0});
  }
  /// The smallest member of x's set.
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a < b) parent_[b] = a;
    if (b < a) parent_[a] = b;
  }

 private:
  std::vector<std::uint32_t> parent_;
};

}  // namespace morph
