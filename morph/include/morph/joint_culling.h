// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file joint_culling.h
/// The generator's first culling step: at a joint between consecutive moves i, i+1 of one path
/// (the end of i is, bit for bit, the start of i+1; same tool; neither move degenerate), both
/// sweep polytopes contain the tool at the joint J, and the caps they place there are decided
/// from the facets' normals alone, with no distance and no plane test.
///
/// With v_i, v_{i+1} the motions in path order and F a tool facet of normal n:
/// - a start cap facet F + J of P_{i+1} (n·v_{i+1} < 0) lies inside P_i when n·v_i < 0 (P_i holds
///   the tool a little before J, whose interior covers F + J), lies in P_i's swept face of F when
///   n·v_i = 0, and is P_i's own end cap facet F + J when n·v_i > 0 (a tie);
/// - an end cap facet F + J of P_i (n·v_i > 0) lies inside P_{i+1} when n·v_{i+1} > 0, and is
///   shared with P_{i+1} (its start cap or its swept face) otherwise.
/// Ties follow the generator's one order (the design's symbolic perturbation: sweeps expand by
/// ε_0 ≫ ε_1 ≫ … in move order): the earlier move owns a shared facet. So every start cap facet
/// of a joined P_{i+1} is culled, and P_i keeps exactly the lune n·v_i > 0 >= n·v_{i+1} of its
/// end cap. "Side" is motion_side() (sweep_polytope.h), the one the sweep builder places facets by,
/// so both moves read the same side of every facet.
#include <morph/convex_polytope.h>
#include <morph/path.h>
#include <morph/sweep_polytope.h>

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

namespace morph {

enum class JointVerdict : std::uint8_t {
  Kept,             ///< not decided at a joint (swept faces, unjoined caps, the kept lune)
  InsidePrevious,   ///< start cap facet inside the previous move's polytope
  OwnedByPrevious,  ///< start cap facet coinciding with a facet of the previous polytope
  InsideNext,       ///< end cap facet inside the next move's polytope
};

/// The joint verdict of every tool facet of a move's sweep (sweep facets 0 … tool.facets.size()-1
/// in the builder's order; silhouette parallelograms are never decided here). `motion`,
/// `previous_motion` and `next_motion` are end minus start in path order; a neighbour is given
/// only when joined (see joined_at_joint()).
std::vector<JointVerdict> joint_verdicts(const ConvexPolytope& tool, const Eigen::Vector3d& motion,
                                         const std::optional<Eigen::Vector3d>& previous_motion,
                                         const std::optional<Eigen::Vector3d>& next_motion);

/// The tool facets around each tool vertex (indices into tool.facets).
std::vector<std::vector<int>> facets_at_vertices(const ConvexPolytope& tool);

/// The tool facets sharing a vertex with each tool facet (itself among them), each listed once:
/// what the rim conditions below read.
struct FacetsAround {
  std::vector<std::uint32_t> start;  ///< facet f's are facets[start[f] … start[f + 1])
  std::vector<int> facets;
};
FacetsAround facets_around(const ConvexPolytope& tool);

/// joint_verdicts() for the rounded planes: the verdicts hold for the exact tool, but a facet
/// with a vertex on the neighbour's boundary (the neighbour's rim there) is inside it, or shares
/// its planes, only up to the rounding of the planes and the tie order, so it may keep a sliver
/// the exact clipping finds. Such a facet is Kept (the caller lists the neighbour among its
/// cutters). A facet whose every vertex has all its facets on its own side of the motions keeps
/// its verdict: it is decided by a real margin.
std::vector<JointVerdict> joint_verdicts_off_rim(const ConvexPolytope& tool, const FacetsAround& around,
                                                 const Eigen::Vector3d& motion,
                                                 const std::optional<Eigen::Vector3d>& previous_motion,
                                                 const std::optional<Eigen::Vector3d>& next_motion);

/// joint_verdicts() for exact sweeps (sweep_polytope.h: the move and its neighbours on the grid).
/// A start cap facet at the joint is inside the previous polytope, or is its own end cap facet,
/// exactly: the previous polytope's silhouette planes pass exactly through its rim, a shared cap
/// has one exact plane in both, and the tie order (the earlier polytope expands by more) puts the
/// facet's rim strictly inside; so those verdicts stand at the rim too. Two exceptions keep the
/// facet (the previous move a cutter): a vertex where a facet is swept by the previous motion
/// (motion_side() 0 up to its 1e-12: its swept face's exact plane holds the vertex only when the
/// facet is exactly parallel to the motion); and the end caps, whose verdicts stay those of
/// joint_verdicts_off_rim(): by the tie order the later polytope expands by less, so a facet
/// touching its rim keeps a sliver outside it.
std::vector<JointVerdict> joint_verdicts_exact(const ConvexPolytope& tool, const FacetsAround& around,
                                               const Eigen::Vector3d& motion,
                                               const std::optional<Eigen::Vector3d>& previous_motion,
                                               const std::optional<Eigen::Vector3d>& next_motion);

/// How a sweep places its tool facets: `ordered_motion` is its ordered end minus its ordered
/// start (SweepPolytopeBuilder::ordered()); a degenerate sweep places every facet at its start.
struct Placement {
  Eigen::Vector3d ordered_motion;
  bool degenerate = false;
  /// -1 at the ordered start, +1 at the ordered end, 0 swept (motion_side()).
  int side(const Eigen::Vector3d& normal) const {
    return degenerate ? -1 : motion_side(normal, ordered_motion);
  }
};

/// The shared-cap rule's condition: tool facet `facet`, placed by `own` on side `own_side` and by
/// `other` on side `other_side` at one point, is one facet of both polytopes with every plane
/// near it the same bit for bit when every tool facet around its vertices is placed on those
/// same sides by both; then the tie order alone decides (the earlier move owns it). Otherwise a
/// neighbour's rim passes through a vertex and the rounding decides: the facet is kept.
bool cap_placed_alike(const ConvexPolytope& tool, const FacetsAround& around, int facet, const Placement& own,
                      int own_side, const Placement& other, int other_side);

/// True when `next` follows `move` at a joint the verdicts may use: both straight, the same
/// tool, `move`'s end is `next`'s start bit for bit, and neither is degenerate for `sweeps`.
bool joined_at_joint(const SweepPolytopeBuilder& sweeps, const Move& move, const Move& next);

/// True for a culled verdict.
inline bool culled(JointVerdict v) {
  return v != JointVerdict::Kept;
}

}  // namespace morph
