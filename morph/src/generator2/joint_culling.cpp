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

std::vector<std::vector<int>> facets_at_vertices(const ConvexPolytope& tool) {
  std::vector<std::vector<int>> out(tool.vertices.size());
  for (std::size_t f = 0; f < tool.facets.size(); ++f)
    for (int v : tool.facets[f].loop) out[v].push_back(static_cast<int>(f));
  return out;
}

std::vector<JointVerdict> joint_verdicts_off_rim(const ConvexPolytope& tool,
                                                 const std::vector<std::vector<int>>& facets_at_vertex,
                                                 const Eigen::Vector3d& motion,
                                                 const std::optional<Eigen::Vector3d>& previous_motion,
                                                 const std::optional<Eigen::Vector3d>& next_motion) {
  std::vector<JointVerdict> joint = joint_verdicts(tool, motion, previous_motion, next_motion);
  for (std::size_t f = 0; f < tool.facets.size(); ++f) {
    if (!culled(joint[f])) continue;
    const bool owned = joint[f] == JointVerdict::OwnedByPrevious;
    const Eigen::Vector3d& neighbour = joint[f] == JointVerdict::InsideNext ? *next_motion : *previous_motion;
    const int side = joint[f] == JointVerdict::InsidePrevious ? -1 : 1;
    for (int v : tool.facets[f].loop)
      for (int g : facets_at_vertex[v])
        if (motion_side(tool.facets[g].normal, neighbour) != side ||
            (owned && motion_side(tool.facets[g].normal, motion) >= 0))
          joint[f] = JointVerdict::Kept;
  }
  return joint;
}

std::vector<JointVerdict> joint_verdicts_exact(const ConvexPolytope& tool,
                                               const std::vector<std::vector<int>>& facets_at_vertex,
                                               const Eigen::Vector3d& motion,
                                               const std::optional<Eigen::Vector3d>& previous_motion,
                                               const std::optional<Eigen::Vector3d>& next_motion) {
  std::vector<JointVerdict> joint = joint_verdicts(tool, motion, previous_motion, next_motion);
  const std::vector<JointVerdict> off_rim =
      joint_verdicts_off_rim(tool, facets_at_vertex, motion, previous_motion, next_motion);
  for (std::size_t f = 0; f < tool.facets.size(); ++f) {
    if (joint[f] == JointVerdict::InsideNext) {
      joint[f] = off_rim[f];  // the tie order leaves the later polytope's rim a sliver
      continue;
    }
    if (!culled(joint[f])) continue;
    for (int v : tool.facets[f].loop)
      for (int g : facets_at_vertex[v])
        if (motion_side(tool.facets[g].normal, *previous_motion) == 0) joint[f] = JointVerdict::Kept;
  }
  return joint;
}

bool cap_placed_alike(const ConvexPolytope& tool, const std::vector<std::vector<int>>& facets_at_vertex,
                      int facet, const Placement& own, int own_side, const Placement& other, int other_side) {
  for (int v : tool.facets[facet].loop)
    for (int g : facets_at_vertex[v]) {
      const Eigen::Vector3d& n = tool.facets[g].normal;
      if (own.side(n) != own_side || other.side(n) != other_side) return false;
    }
  return true;
}

}  // namespace morph
