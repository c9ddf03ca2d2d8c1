// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file sweep_culling_facets.h
/// What SweepCulling's stages share (sweep_culling.cpp places and sorts the facets,
/// sweep_culling_halfspaces.cpp judges them against a candidate's halfspaces): a candidate sweep
/// and a facet as placed from the tool.
#include <morph/sweep_culling.h>

#include <Eigen/Geometry>
#include <cstdint>

namespace morph {

// A cluster of facets about one grid cell of the tool, at one placement.
struct ClusterKey {
  std::int64_t cell;
  int placement;
  bool operator<(const ClusterKey& o) const {
    return cell < o.cell || (cell == o.cell && placement < o.placement);
  }
  bool operator==(const ClusterKey& o) const { return cell == o.cell && placement == o.placement; }
};

// A candidate sweep of a move: its ordered ends.
struct SweepCulling::Candidate {
  std::uint32_t move;
  Eigen::Vector3d a, b;
  bool degenerate;
  bool exact;
};

// A facet of a sweep as placed from the tool: a tool facet at one end (placement -1 at the
// ordered start, +1 at the ordered end) or swept whole (0), or a silhouette edge (0).
struct SweepCulling::Placed {
  int facet = 0, tool_facet = -1, edge = -1, placement = 0;
  Eigen::AlignedBox3d box;
  Eigen::Vector3d centre;
  double radius = 0.0;
  Eigen::Vector3d from, to;  // the facet lies within `thickness` of the segment [from, to]
  double thickness = 0.0;
  FacePlane plane;
  ClusterKey cluster{};
  /// Reaching out of the stock, so cut to it: the points are its polygon's, in order, and the
  /// bounds above are theirs.
  bool clipped = false;
};

}  // namespace morph
