#pragma once
/// \file sweep_polytope.h
/// The volume a convex tool polytope sweeps along a straight move: the convex polytope
/// tool ⊕ segment, given by its facets (and so its halfspaces). With v the motion, its facets are
/// - the tool's facets facing back (n·v < 0) at the start, and facing forward (n·v > 0) at the end;
/// - a parallelogram e × v on every silhouette edge e (between a back and a forward facet);
/// - every facet parallel to the motion (n·v = 0) swept whole into one planar face, the hull of
///   it at the start and at the end: a level move's flat bottom, a plunging cylinder's sides.
/// The segment is taken unordered (its ends sorted), so a move and its retrace give the same
/// polytope, bit for bit.
#include <morph/convex_polytope.h>

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace morph {

/// Builds sweeps of one tool polytope; the tool's edge adjacency is found once.
class SweepPolytopeBuilder {
 public:
  /// `tool`: a closed convex polytope about the tool point (tool_polytope.h).
  explicit SweepPolytopeBuilder(ConvexPolytope tool);

  /// The polytope swept as the tool point moves from `start` to `end` (job units). A move
  /// shorter than 1e-12 of the tool's size gives the tool itself at `start`.
  ConvexPolytope operator()(const Eigen::Vector3d& start, const Eigen::Vector3d& end) const;

  const ConvexPolytope& tool() const { return tool_; }

 private:
  struct Edge {
    int from, to;     ///< vertices, as they run in facet `left`
    int left, right;  ///< the facet holding from->to, and the one holding to->from
  };
  ConvexPolytope tool_;
  std::vector<Edge> edges_;
  double size_ = 0.0;
};

/// One-off form of SweepPolytopeBuilder.
ConvexPolytope sweep_polytope(const ConvexPolytope& tool, const Eigen::Vector3d& start,
                              const Eigen::Vector3d& end);

}  // namespace morph
