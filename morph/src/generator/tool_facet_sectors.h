// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file tool_facet_sectors.h
/// The tool's facets by ring and sector, for "which facets' boxes may meet this box". A tool of
/// revolution (tool_polytope.h) has its side facets between two rings and two of the rings' common
/// directions, so a small box near the tool meets the facets of a few rings (its z range) and a few
/// sectors (its range of angles about the axis): both found by arithmetic, where a walk of a tree
/// of the ~700 facet boxes visits some sixty nodes to find six facets.
///
/// Nothing here assumes that structure for correctness; it only makes the filter tight:
/// - a ring is the facets of one box z range (exactly equal doubles), found by binary search;
/// - the angle is the diamond angle (monotone in atan2, no trigonometry), cut into M equal cells; a
///   facet is listed in the first cell its box's angles reach; with K the most cells a facet box of
///   its ring reaches (its angles widened by a margin far above their rounding), a query lists
///   the ring's cells from K - 1 before its own first one to its last one;
/// - a facet box about the axis (the flat ends, a pole's first ring), or one spanning a quarter of
///   the turn or more, is listed for every query.
/// So every facet whose box meets the query box is listed (tool_facet_sectors_test checks it
/// against every box), each once, with a few more whose boxes do not: the caller tests the boxes.
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

namespace morph {

class ToolFacetSectors {
 public:
  /// Over the facets' boxes (tool frame, axis +z through the origin), item k is boxes[k].
  explicit ToolFacetSectors(const std::vector<Eigen::AlignedBox3d>& boxes);

  /// Calls visit(k) for every facet k whose box may meet `query` (tool frame): a superset of those
  /// that do, each once, in no promised order.
  template <class Visit>
  void for_each_candidate(const Eigen::AlignedBox3d& query, Visit&& visit) const {
    for (std::uint32_t k : everywhere_) visit(k);
    const QueryCells cells = cells_of(query);
    for (std::size_t r = first_ring_reaching(query.min().z());
         r < rings_.size() && rings_[r].z_min <= query.max().z(); ++r) {
      if (rings_[r].z_max < query.min().z()) continue;  // only where the rings overlap in z
      const std::uint32_t* start = cell_start_.data() + r * static_cast<std::size_t>(cells_);
      const int count = cells.count + rings_[r].span - 1;
      if (cells.all || count >= cells_) {
        for (std::uint32_t i = start[0]; i < start[cells_]; ++i) visit(facets_[i]);
        continue;
      }
      int cell = cells.first - (rings_[r].span - 1);
      if (cell < 0) cell += cells_;
      for (int c = 0; c < count; ++c, cell = cell + 1 == cells_ ? 0 : cell + 1)
        for (std::uint32_t i = start[cell]; i < start[cell + 1]; ++i) visit(facets_[i]);
    }
  }

  int cells() const { return cells_; }  ///< M
  int span() const;                     ///< K: the largest of the rings' spans
  int ring_span(std::size_t ring) const { return rings_[ring].span; }
  std::size_t everywhere() const { return everywhere_.size(); }
  std::size_t rings() const { return rings_.size(); }

 private:
  struct Ring {
    double z_min = 0, z_max = 0;
    int span = 1;  ///< the most cells one of its facets' boxes reaches
  };
  struct QueryCells {
    bool all = false;
    int first = 0, count = 0;  ///< the cells the query's angles reach: first, first + 1, … (mod M)
  };
  QueryCells cells_of(const Eigen::AlignedBox3d& query) const;
  std::size_t first_ring_reaching(double z) const;

  int cells_ = 1;
  bool z_max_sorted_ = true;  ///< rings' z_max non-decreasing: the first ring by binary search
  std::vector<Ring> rings_;   ///< by z_min
  /// Ring r's cell c holds facets_[cell_start_[r·M + c] … cell_start_[r·M + c + 1]).
  std::vector<std::uint32_t> cell_start_, facets_, everywhere_;
};

}  // namespace morph
