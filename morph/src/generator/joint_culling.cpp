// SPDX-License-Identifier: Apache-2.0
#include <morph/joint_culling.h>
#include <morph/sweep_polytope.h>

#include <algorithm>

namespace morph {

bool joined_at_joint(const SweepPolytopeBuilder& sweeps, const Move& move, const Move& next) {
  return !move.is_arc() && !next.is_arc() && move.tool == next.tool && move.end == next.start &&
         !sweeps.degenerate(move.start, move.end) && !sweeps.degenerate(next.start, next.end);
}

namespace {

// motion_side() of every tool facet for the move and its joined neighbours, each once (the rim
// conditions read a facet's sides at each of its vertices, four facets each).
struct JointSides {
  std::vector<signed char> own, previous, next;
  JointSides(const ConvexPolytope& tool, const Eigen::Vector3d& motion,
             const std::optional<Eigen::Vector3d>& previous_motion,
             const std::optional<Eigen::Vector3d>& next_motion) {
    motion_sides(tool, motion, own);
    if (previous_motion) motion_sides(tool, *previous_motion, previous);
    if (next_motion) motion_sides(tool, *next_motion, next);
  }
};

std::vector<JointVerdict> verdicts_of(const JointSides& sides) {
  std::vector<JointVerdict> verdicts(sides.own.size(), JointVerdict::Kept);
  for (std::size_t f = 0; f < verdicts.size(); ++f) {
    const int side = sides.own[f];
    if (side < 0 && !sides.previous.empty())
      verdicts[f] = sides.previous[f] < 0 ? JointVerdict::InsidePrevious : JointVerdict::OwnedByPrevious;
    else if (side > 0 && !sides.next.empty() && sides.next[f] > 0)
      verdicts[f] = JointVerdict::InsideNext;
  }
  return verdicts;
}

// True when pred(g) holds for a tool facet g at one of facet f's vertices.
template <class Pred>
bool at_a_vertex_of(const FacetsAround& around, std::size_t f, Pred&& pred) {
  for (std::uint32_t k = around.start[f]; k < around.start[f + 1]; ++k)
    if (pred(static_cast<std::size_t>(around.facets[k]))) return true;
  return false;
}

std::vector<JointVerdict> off_rim_of(const ConvexPolytope& tool, const FacetsAround& around,
                                     const JointSides& sides) {
  std::vector<JointVerdict> joint = verdicts_of(sides);
  for (std::size_t f = 0; f < tool.facets.size(); ++f) {
    if (!culled(joint[f])) continue;
    const bool owned = joint[f] == JointVerdict::OwnedByPrevious;
    const std::vector<signed char>& neighbour =
        joint[f] == JointVerdict::InsideNext ? sides.next : sides.previous;
    const int side = joint[f] == JointVerdict::InsidePrevious ? -1 : 1;
    if (at_a_vertex_of(around, f,
                       [&](std::size_t g) { return neighbour[g] != side || (owned && sides.own[g] >= 0); }))
      joint[f] = JointVerdict::Kept;
  }
  return joint;
}

}  // namespace

std::vector<JointVerdict> joint_verdicts(const ConvexPolytope& tool, const Eigen::Vector3d& motion,
                                         const std::optional<Eigen::Vector3d>& previous_motion,
                                         const std::optional<Eigen::Vector3d>& next_motion) {
  return verdicts_of(JointSides(tool, motion, previous_motion, next_motion));
}

std::vector<std::vector<int>> facets_at_vertices(const ConvexPolytope& tool) {
  std::vector<std::vector<int>> out(tool.vertices.size());
  for (std::size_t f = 0; f < tool.facets.size(); ++f)
    for (int v : tool.facets[f].loop) out[v].push_back(static_cast<int>(f));
  return out;
}

FacetsAround facets_around(const ConvexPolytope& tool) {
  const std::vector<std::vector<int>> at_vertex = facets_at_vertices(tool);
  FacetsAround around;
  around.start.push_back(0);
  std::vector<int> list;
  for (const PolytopeFacet& facet : tool.facets) {
    list.clear();
    for (int v : facet.loop)
      list.insert(list.end(), at_vertex[static_cast<std::size_t>(v)].begin(),
                  at_vertex[static_cast<std::size_t>(v)].end());
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    around.facets.insert(around.facets.end(), list.begin(), list.end());
    around.start.push_back(static_cast<std::uint32_t>(around.facets.size()));
  }
  return around;
}

std::vector<JointVerdict> joint_verdicts_off_rim(const ConvexPolytope& tool, const FacetsAround& around,
                                                 const Eigen::Vector3d& motion,
                                                 const std::optional<Eigen::Vector3d>& previous_motion,
                                                 const std::optional<Eigen::Vector3d>& next_motion) {
  return off_rim_of(tool, around, JointSides(tool, motion, previous_motion, next_motion));
}

std::vector<JointVerdict> joint_verdicts_exact(const ConvexPolytope& tool, const FacetsAround& around,
                                               const Eigen::Vector3d& motion,
                                               const std::optional<Eigen::Vector3d>& previous_motion,
                                               const std::optional<Eigen::Vector3d>& next_motion) {
  const JointSides sides(tool, motion, previous_motion, next_motion);
  std::vector<JointVerdict> joint = verdicts_of(sides);
  const std::vector<JointVerdict> off_rim = off_rim_of(tool, around, sides);
  for (std::size_t f = 0; f < tool.facets.size(); ++f) {
    if (joint[f] == JointVerdict::InsideNext) {
      joint[f] = off_rim[f];  // the tie order leaves the later polytope's rim a sliver
      continue;
    }
    if (!culled(joint[f])) continue;
    if (at_a_vertex_of(around, f, [&](std::size_t g) { return sides.previous[g] == 0; }))
      joint[f] = JointVerdict::Kept;
  }
  return joint;
}

bool cap_placed_alike(const ConvexPolytope& tool, const FacetsAround& around, int facet, const Placement& own,
                      int own_side, const Placement& other, int other_side) {
  return !at_a_vertex_of(around, static_cast<std::size_t>(facet), [&](std::size_t g) {
    const Eigen::Vector3d& n = tool.facets[g].normal;
    return own.side(n) != own_side || other.side(n) != other_side;
  });
}

}  // namespace morph
