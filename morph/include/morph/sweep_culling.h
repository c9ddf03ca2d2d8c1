// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file sweep_culling.h
/// The generator's culling stage: of every move's sweep polytope P_i (sweep_polytope.h), the facets
/// that can bound the union of the sweeps inside the stock, and for each the moves whose
/// polytopes may cut it, with the planes of theirs that cross it. The facets' loops are never
/// built here: a facet is a tool facet or edge placed at the move's ends, so its box, ball and
/// vertices come from the tool. Cheapest proofs first:
/// 1. joints, by the facets' normals alone (joint_culling.h); where a sweep has rounded planes
///    only, for the cap facets none of whose vertices lies on the neighbour's rim (there the
///    rounded planes, not the exact tool, decide: such a facet is kept with the neighbour as a
///    cutter); between exact sweeps also at the rim (joint_verdicts_exact());
/// 2. the stock box (a facet wholly outside one of its planes);
/// 3. move against move: candidates from the sweeps' boxes (AabbTree), a retraced move (the same
///    polytope bit for bit) culled whole or dropped whole by the tie order (so is a cap both
///    place at the same point: between exact sweeps always, else when every facet around its
///    vertices is placed there by both);
/// 4. clusters of facets, then facets, against each candidate's capsules and swept cylinders
///    (tool_bounds.h): inside proves culled, missing drops the candidate; a candidate wholly
///    below the facet's plane (the sweeps' support functions differ only by their ends) drops too;
/// 5. what is left, by the candidate's halfspaces: every vertex below every plane culls the facet
///    (a convex facet in a convex polytope), every vertex above one plane drops the candidate,
///    else the candidate cuts the facet with the planes that cross it; when a point of the facet
///    is inside the candidate, only the planes of its faces whose boxes meet the facet's (so too
///    when the point is on its boundary by construction: a corner at an end both moves share).
/// Signs within a rounding bound of zero are not decided here: the candidate stays a cutter, for
/// the clipping's exact predicates. Ties are settled by the generator's one order: sweeps expand
/// by ε_0 ≫ ε_1 ≫ … in move order, so the earlier move owns a shared facet (a facet in a plane of
/// an earlier polytope, bit for bit, counts as below it; of a later one, as above it).
#include <morph/joint_culling.h>
#include <morph/path.h>
#include <morph/sweep_polytope.h>
#include <morph/tool_bounds.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

namespace morph {

class AabbTree;
class ToolFacetGroups;
class ToolFacetSectors;

/// A move whose polytope may cut a kept facet, and the indices of its halfspaces (in
/// SweepPolytopeBuilder::halfspaces() order) that cross the facet: the facet's part inside the
/// polytope is its part below all of these. The indices are KeptFacet::planes_of() it.
struct FacetCutter {
  std::uint32_t move = 0;
  std::uint32_t first = 0, count = 0;  ///< its indices in KeptFacet::planes
  /// How many of the facet's points (its corners and centroid) lie below every one of its faces
  /// near the facet, by the rounding: how much of the facet it may hold.
  int points_below = 0;
};

/// A cutter's plane indices, in a kept facet's list.
struct PlaneIndices {
  const int* first = nullptr;
  const int* last = nullptr;
  const int* begin() const { return first; }
  const int* end() const { return last; }
  std::size_t size() const { return static_cast<std::size_t>(last - first); }
};

struct KeptFacet {
  int facet = 0;  ///< index in the sweep's facet order (sweep_polytope.h)
  std::vector<FacetCutter> cutters;
  /// Every cutter's plane indices, cutter after cutter (one list per facet, not one per cutter:
  /// a kept facet of a dense raster has a dozen cutters).
  std::vector<int> planes;
  PlaneIndices planes_of(const FacetCutter& c) const {
    return {planes.data() + c.first, planes.data() + c.first + c.count};
  }
};

/// What each proof decided, summed over the moves culled.
struct CullingCounts {
  double facets = 0, by_joint = 0, outside_stock = 0, by_retrace = 0, by_cluster_bound = 0,
         by_facet_bound = 0;
  double by_shared_cap = 0, by_planes = 0, kept = 0, cutters = 0, cutting_planes = 0;
  double candidates = 0, bound_tests = 0, plane_tests = 0;
  /// Candidates dropped for a facet because they lie wholly below its plane (support functions).
  double apart_by_support = 0;
  /// Candidates dropped for a facet because their box misses its box (grown by the rounding).
  double apart_by_box = 0;
  /// Candidates' faces placed (not found in the scratch).
  double candidates_placed = 0;
  /// Cutters kept with every crossing plane: no point of the facet proven inside within rounding.
  double without_witness = 0;
  CullingCounts& operator+=(const CullingCounts& o);
};

class SweepCulling {
  struct Candidate;

 public:
  /// A facet of a candidate sweep as the plane tests need it: its halfspace and its box.
  /// A face's plane as the culling reads it: its float look alone (the exact plane is the
  /// carving's), so that a candidate's faces, read in scattered order, take half the memory.
  struct FacePlane {
    Eigen::Vector3d normal;
    double offset;
  };
  struct Face {
    FacePlane plane;
    Eigen::AlignedBox3d box;  ///< grown by the rounding bound
  };
  /// A candidate sweep's faces, in facet order: the side of each tool facet, and the silhouette
  /// faces. A tool facet's face is made from the tool and the side when read (against()): only
  /// the silhouette faces, which cost a plane each to make, are kept.
  static constexpr std::size_t kSilhouetteChunk = 8;
  struct Faces {
    std::vector<Face> silhouette;       ///< the faces from index tool().facets.size() on
    std::vector<int> silhouette_edges;  ///< each silhouette face's edge (SweepPolytopeBuilder::edges())
    /// The boxes of kSilhouetteChunk silhouette faces at a time, in their order (neighbouring
    /// edges of the tool): a query skips the chunks its box misses.
    std::vector<Eigen::AlignedBox3d> silhouette_chunks;
    std::vector<signed char> side;
    std::vector<int> swept_facets;  ///< the tool facets of side 0 (swept along the move), a few
    Eigen::Vector3d a, b;           ///< the ordered ends (both the start for a degenerate move)
  };
  /// Per-thread working memory: the faces of recent candidates, which the next moves share.
  class Scratch {
    friend class SweepCulling;
    std::unordered_map<std::uint32_t, std::size_t> slot_of_;  ///< move -> index in recent_
    std::vector<std::pair<std::uint32_t, Faces>> recent_;
    std::size_t next_ = 0;
    std::vector<int> near_faces_;
    std::vector<int> planes_;             ///< against()'s crossing planes
    std::vector<char> marks_;             ///< against()'s flags per tool facet, clear
    std::vector<const Candidate*> open_;  ///< decide()'s candidates left for the halfspaces
    std::vector<double> open_core_;       ///< their distances from the facet's centre (core_distance())
    KeptFacet keep_;                      ///< the facet cull() decides, copied out when it is kept
    std::vector<std::vector<Eigen::Vector3d>> points_of_;  ///< cull()'s facet points, by facet
    std::vector<Eigen::AlignedBox3d> candidate_boxes_;     ///< cull()'s candidates' boxes
  };

  /// `moves`: straight moves of the one tool of `sweeps`, in job order (the tie order), paths
  /// concatenated; `joined[i]` says move i follows move i-1 at a joint (joined_at_joint()).
  /// Throws InputError for an arc or mismatched sizes.
  SweepCulling(const SweepPolytopeBuilder& sweeps, std::vector<Move> moves, std::vector<bool> joined,
               const Eigen::AlignedBox3d& stock);
  ~SweepCulling();

  /// The kept facets of move i's sweep, in facet order. Thread-safe with one Scratch per thread.
  std::vector<KeptFacet> cull(std::size_t i, CullingCounts& counts, Scratch& scratch) const;
  std::vector<KeptFacet> cull(std::size_t i, CullingCounts& counts) const {
    Scratch scratch;
    return cull(i, counts, scratch);
  }

  std::size_t size() const { return moves_.size(); }

 private:
  struct Placed;
  /// Appends move i's facets but the tool facets `joint` culls; returns how many those are.
  std::size_t place(std::size_t i, const std::vector<JointVerdict>& joint, std::vector<Placed>& facets) const;
  Placed silhouette_face(std::size_t e, int index, const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;
  const Faces& faces(std::uint32_t j, Scratch& scratch, CullingCounts& counts) const;
  enum class Against { Apart, Inside, Cuts };
  class HalfspaceTest;  ///< against()'s steps (sweep_culling_halfspaces.cpp)
  enum class Culled { Open, Bound, Shared, Planes };
  struct Ends {
    Eigen::Vector3d a, b;  ///< ordered (both the start for a degenerate move)
    bool degenerate;
  };
  bool cut_to_stock(Placed& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                    std::vector<Eigen::Vector3d>& points) const;
  Culled decide(const Placed& p, std::size_t i, const Ends& own, const std::vector<const Candidate*>& near,
                const std::vector<Eigen::Vector3d>& vertices, const Candidate*& prover, KeptFacet& keep,
                CullingCounts& counts, Scratch& scratch) const;
  int support_facet(int from, const Eigen::Vector3d& direction) const;
  Against against(const Placed& p, std::size_t i, const Ends& own, std::uint32_t j,
                  const std::vector<Eigen::Vector3d>& points, const Faces& faces,
                  std::vector<int>& near_faces, std::vector<int>& planes, std::vector<char>& marks,
                  int& points_below, CullingCounts& counts) const;

  const SweepPolytopeBuilder& sweeps_;
  std::vector<Move> moves_;
  std::vector<bool> joined_;
  std::vector<bool> exact_;  ///< the move's sweep carries exact planes (SweepPolytopeBuilder::exact())
  Eigen::AlignedBox3d stock_;
  ToolBounds bounds_;
  std::vector<FacePlane> tool_planes_;  ///< the tool facets' (normal, offset), packed for against()
  std::vector<Eigen::AlignedBox3d> tool_facet_boxes_;
  std::vector<Eigen::Vector3d> tool_facet_centres_;
  std::vector<double> tool_facet_radii_;
  FacetsAround facets_around_;                 ///< the tool facets sharing a vertex with each tool facet
  std::vector<std::int64_t> tool_facet_cell_;  ///< cluster of each tool facet (a grid cell of its centre)
  /// The tool facets across each facet's edges, facet f's at [neighbour_start_[f],
  /// neighbour_start_[f + 1]), with their normals beside them (the climb reads nothing else).
  std::vector<std::uint32_t> neighbour_start_;
  std::vector<int> neighbour_facet_;
  std::vector<Eigen::Vector3d> neighbour_normal_;
  double rounding_ = 0.0;                                 ///< plane values within this of zero are undecided
  std::unique_ptr<AabbTree> tree_;                        ///< the sweeps' boxes
  std::unique_ptr<AabbTree> tool_facet_tree_;             ///< the tool facets' boxes (grown by the rounding)
  std::unique_ptr<ToolFacetSectors> tool_facet_sectors_;  ///< the same boxes by ring and sector
  std::unique_ptr<ToolFacetGroups> facet_groups_;         ///< which faces can reach a point (all-face loops)
};

}  // namespace morph
