// SPDX-License-Identifier: Apache-2.0
#include <morph/joint_culling.h>
#include <morph/sweep_polytope.h>

namespace morph {

bool joined_at_joint(const SweepPolytopeBuilder& sweeps, const Move& move, const Move& next) {
  return !move.is_arc() && !next.is_arc() && move.tool == next.tool && move.end == next.start &&
         !sweeps.degenerate(move.start, move.end) && !sweeps.degenerate(next.start, next.end);
}

std::vector<JointVerdict> joint_verdicts(const ConvexPolytope& tool, const Eigen::Vector3d& motion,
                                         const std::optional<Eigen::Vector3d>& previous_motion,
                                         const std::optional<Eigen::Vector3d>& next_motion) {
  std::vector<JointVerdict> verdicts(tool.facets.size(), JointVerdict::Kept);
  for (std::size_t f = 0; f < tool.facets.size(); ++f) {
    const Eigen::Vector3d& n = tool.facets[f].normal;
    const int side = motion_side(n, motion);
    if (side < 0 && previous_motion)
      verdicts[f] =
          motion_side(n, *previous_motion) < 0 ? JointVerdict::InsidePrevious : JointVerdict::OwnedByPrevious;
    else if (side > 0 && next_motion && motion_side(n, *next_motion) > 0)
      verdicts[f] = JointVerdict::InsideNext;
  }
  return verdicts;
}

}  // namespace morph
