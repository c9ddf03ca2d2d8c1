// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file rounding.h
/// Generator 2's output rounding (design §5), after emit has rounded the exact vertices to
/// doubles. Distinct exact points closer than a double's resolution (the near-concurrent planes
/// of a tool polytope's pole, thin cells of near-reversals) can round to one double or to three
/// collinear doubles. Every decision here is on the rounded doubles taken as exact (no
/// threshold), and none changes the surface's geometry:
/// 1. an edge whose two ends rounded to the same double is collapsed when the link condition
///    holds (the two ends' common neighbours are the edge's two opposite corners), dropping its
///    two triangles: the other triangles keep their corners' coordinates;
/// 2. a triangle whose three corners rounded onto one line, the middle one strictly between the
///    others, has its longest edge flipped with the neighbour across it: the neighbour splits at
///    the middle corner into two triangles covering it exactly;
/// 3. a triangle left flat or turned against its polygon's facing has a corner moved to a
///    neighbouring double that keeps every incident triangle's orientation (re-rounding).
/// Each is counted; what none of them can settle is counted too (target 0).
#include <morph/mesh.h>

#include <vector>

namespace morph {

struct RoundingCounts {
  std::size_t collapsed_edges = 0;     ///< step 1
  std::size_t flipped_edges = 0;       ///< step 2
  std::size_t rerounded_vertices = 0;  ///< step 3
  std::size_t misoriented_left = 0;    ///< triangles still flat or turned the wrong way
};

/// Sign of normal · ((b - a) × (c - a)), the doubles taken as exact (filter, then integers).
int oriented_area_sign(const Eigen::Vector3d& normal, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       const Eigen::Vector3d& c);

/// Steps 1-3 on `mesh` (a closed, oriented 2-manifold), where `facing[t]` is the direction
/// triangle t must turn to (its polygon's outward normal). Removes the dropped triangles (and
/// their tags) and the vertices no triangle uses any more.
RoundingCounts settle_rounding(TriangleMesh& mesh, std::vector<Eigen::Vector3d> facing);

}  // namespace morph
