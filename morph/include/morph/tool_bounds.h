// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file tool_bounds.h
/// Closed-form bounds of a tool polytope and of its sweeps, for the generator's culling: a ball and
/// a cylinder about the axis inside the tool, and a ball and a cylinder holding it. Swept along
/// a segment they give capsules and swept cylinders, whose tests against a query ball are a
/// point-segment distance and one linear interval: tens of flops, no search, no plane test.
/// Every test is a proof (with a 1e-9 slack): "inside" means the query ball lies inside the
/// sweep polytope, "misses" that it does not meet it. Lengths in job units.
#include <morph/convex_polytope.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace morph {

struct ToolBounds {
  double centre_height = 0.0;  ///< z of the axis point c where the inscribed ball is largest
  double inner_radius = 0.0;   ///< the ball of this radius about c lies inside the tool
  double cylinder_radius =
      0.0;  ///< the axis cylinder of this radius over [centre_height, top] lies inside (0: none)
  double outer_radius = 0.0;  ///< the ball of this radius about c holds the tool below centre_height
  double max_radius =
      0.0;  ///< largest distance of a vertex from the axis (holds the tool above centre_height)
  double bottom = 0.0, top = 0.0;  ///< z range of the tool
};

/// The bounds of a closed convex tool polytope about the z axis (tool_polytope.h).
ToolBounds tool_bounds(const ConvexPolytope& tool);

/// The distance of `x` from the swept centre c + [a, b] (c the axis point at centre_height),
/// which the capsules of the tests below are about.
double core_distance(const ToolBounds& bounds, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                     const Eigen::Vector3d& x);

/// True when the ball (centre, radius) is proven inside tool ⊕ [a, b]: inside the swept inner
/// ball (a capsule) or inside the inner cylinder at one position of the segment.
bool ball_inside_sweep(const ToolBounds& bounds, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       const Eigen::Vector3d& centre, double radius);

/// A box holding every ball that ball_inside_sweep() proves inside tool ⊕ [a, b] (the swept inner
/// ball's box and the swept inner cylinder's, grown by a rounding margin); empty when there is
/// none. A ball whose box it does not contain is not proven inside, so the test can be skipped.
Eigen::AlignedBox3d inner_box(const ToolBounds& bounds, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

/// True when every point is proven inside the swept inner ball, or every point inside the swept
/// inner cylinder: both are convex, so then the points' convex hull (a facet) is inside too.
bool points_inside_sweep(const ToolBounds& bounds, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                         const std::vector<Eigen::Vector3d>& points);

/// True when some point is proven inside tool ⊕ [a, b] by ball_inside_sweep() (radius 0).
bool any_point_inside_sweep(const ToolBounds& bounds, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                            const std::vector<Eigen::Vector3d>& points);

/// True when the ball (centre, radius) is proven apart from tool ⊕ [a, b]: outside the swept
/// outer ball (a capsule) and outside the swept outer cylinder.
/// `core`, when given, receives the centre's core_distance() (a caller may order by it).
bool ball_misses_sweep(const ToolBounds& bounds, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       const Eigen::Vector3d& centre, double radius, double* core = nullptr);

/// Both proofs above at once, sharing their distance from the swept centre: Inside when
/// ball_inside_sweep() holds, else Misses when ball_misses_sweep() does, else Unknown. `core`,
/// when given, receives the centre's core_distance().
enum class BallVerdict { Inside, Misses, Unknown };
BallVerdict ball_against_sweep(const ToolBounds& bounds, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                               const Eigen::Vector3d& centre, double radius, double* core = nullptr);

/// True when the capsule (segment [from, to] grown by `radius`) is proven apart from
/// tool ⊕ [a, b]: farther than the outer ball's radius from its swept centre (segment to
/// segment), and its bounding ball apart from the swept outer cylinder. Long thin facets (a
/// silhouette edge swept along its move) fit a capsule far better than a ball.
bool capsule_misses_sweep(const ToolBounds& bounds, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& from, const Eigen::Vector3d& to, double radius);

}  // namespace morph
