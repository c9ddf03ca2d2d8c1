// SPDX-License-Identifier: Apache-2.0
#include <morph/aabb_tree.h>
#include <morph/exceptions.h>
#include <morph/joint_culling.h>
#include <morph/sweep_culling.h>

#include "generator/sweep_culling_facets.h"
#include "generator/tool_facet_groups.h"
#include "generator/tool_facet_sectors.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace morph {

namespace {

using Eigen::AlignedBox3d;
using Eigen::Vector3d;

bool outside(const AlignedBox3d& box, const AlignedBox3d& stock) {
  return (box.min().array() > stock.max().array()).any() || (box.max().array() < stock.min().array()).any();
}

}  // namespace

CullingCounts& CullingCounts::operator+=(const CullingCounts& o) {
  facets += o.facets, by_joint += o.by_joint, outside_stock += o.outside_stock, by_retrace += o.by_retrace;
  by_cluster_bound += o.by_cluster_bound, by_facet_bound += o.by_facet_bound,
      by_shared_cap += o.by_shared_cap;
  by_planes += o.by_planes, kept += o.kept, cutters += o.cutters, cutting_planes += o.cutting_planes;
  candidates += o.candidates, bound_tests += o.bound_tests, plane_tests += o.plane_tests;
  without_witness += o.without_witness, apart_by_support += o.apart_by_support,
      apart_by_box += o.apart_by_box, candidates_placed += o.candidates_placed;
  return *this;
}

SweepCulling::SweepCulling(const SweepPolytopeBuilder& sweeps, std::vector<Move> moves,
                           std::vector<bool> joined, const AlignedBox3d& stock)
    : sweeps_(sweeps), moves_(std::move(moves)), joined_(std::move(joined)), stock_(stock) {
  if (joined_.size() != moves_.size()) throw InputError("sweep culling: one joint flag per move is needed");
  const ConvexPolytope& tool = sweeps_.tool();
  bounds_ = tool_bounds(tool);
  // Clusters: a grid of cells of half the inscribed radius (at least a fiftieth of the tool).
  const AlignedBox3d tool_box = tool.bounds();
  facets_around_ = facets_around(tool);
  const double cell = std::max(0.5 * bounds_.inner_radius, 0.02 * tool_box.diagonal().norm());
  for (const PolytopeFacet& f : tool.facets) {
    AlignedBox3d box;
    Vector3d centre = Vector3d::Zero();
    for (int v : f.loop) {
      box.extend(tool.vertices[v]);
      centre += tool.vertices[v];
    }
    centre /= static_cast<double>(f.loop.size());
    double radius = 0.0;
    for (int v : f.loop) radius = std::max(radius, (tool.vertices[v] - centre).norm());
    tool_planes_.push_back({f.normal, f.offset});
    tool_facet_boxes_.push_back(box);
    tool_facet_centres_.push_back(centre);
    tool_facet_radii_.push_back(radius);
    const Eigen::Array3d c = ((centre - tool_box.min()) / cell).array().floor();
    tool_facet_cell_.push_back((static_cast<std::int64_t>(c.z()) * 4096 + static_cast<std::int64_t>(c.y())) *
                                   4096 +
                               static_cast<std::int64_t>(c.x()));
  }
  double extent = tool_box.diagonal().norm();
  std::vector<AlignedBox3d> boxes;
  for (const Move& m : moves_) {
    if (m.is_arc()) throw InputError("sweep culling: arcs must be split into straight moves first");
    const auto [a, b] = SweepPolytopeBuilder::ordered(m.start, m.end);
    AlignedBox3d box(tool_box.min() + a, tool_box.max() + a);
    box.extend(AlignedBox3d(tool_box.min() + b, tool_box.max() + b));
    boxes.push_back(box);
    exact_.push_back(sweeps_.exact(m.start, m.end));
    extent = std::max({extent, a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()});
  }
  extent = std::max({extent, stock.min().cwiseAbs().maxCoeff(), stock.max().cwiseAbs().maxCoeff()});
  // A plane value n·x - o with |n| = 1 is evaluated to within a few ulps of |x| + |o|.
  rounding_ = 1e-13 * (1.0 + 3.0 * extent);
  for (AlignedBox3d& box : boxes) {
    box.min().array() -= rounding_;
    box.max().array() += rounding_;
  }
  tree_ = std::make_unique<AabbTree>(std::move(boxes));
  std::vector<AlignedBox3d> facet_boxes;
  for (const AlignedBox3d& box : tool_facet_boxes_)
    facet_boxes.emplace_back(box.min().array() - rounding_, box.max().array() + rounding_);
  tool_facet_sectors_ = std::make_unique<ToolFacetSectors>(facet_boxes);
  tool_facet_tree_ = std::make_unique<AabbTree>(std::move(facet_boxes));
  facet_groups_ = std::make_unique<ToolFacetGroups>(tool);
  std::vector<std::vector<int>> neighbours(tool.facets.size());
  for (const SweepPolytopeBuilder::Edge& e : sweeps_.edges()) {
    neighbours[static_cast<std::size_t>(e.left)].push_back(e.right);
    neighbours[static_cast<std::size_t>(e.right)].push_back(e.left);
  }
  neighbour_start_.push_back(0);
  for (const std::vector<int>& around : neighbours) {
    for (int g : around) {
      neighbour_facet_.push_back(g);
      neighbour_normal_.push_back(tool.facets[static_cast<std::size_t>(g)].normal);
    }
    neighbour_start_.push_back(static_cast<std::uint32_t>(neighbour_facet_.size()));
  }
}

// A tool facet whose normal leans furthest toward `direction`, climbing from facet `from` to the
// neighbour that leans further while there is one (on a convex polytope the climb ends at the
// facet holding the direction in its normal cone, or next to it).
int SweepCulling::support_facet(int from, const Vector3d& direction) const {
  int at = from;
  double best = tool_planes_[static_cast<std::size_t>(at)].normal.dot(direction);
  for (bool climbed = true; climbed;) {
    climbed = false;
    const std::size_t end = neighbour_start_[static_cast<std::size_t>(at) + 1];
    for (std::size_t k = neighbour_start_[static_cast<std::size_t>(at)]; k < end; ++k) {
      const double value = neighbour_normal_[k].dot(direction);
      if (value > best) {
        best = value;
        at = neighbour_facet_[k];
        climbed = true;
      }
    }
  }
  return at;
}

SweepCulling::~SweepCulling() = default;

// Every facet of move i's sweep, placed as the builder places it (the same arithmetic).
std::size_t SweepCulling::place(std::size_t i, const std::vector<JointVerdict>& joint,
                                std::vector<Placed>& facets) const {
  const ConvexPolytope& tool = sweeps_.tool();
  const Move& m = moves_[i];
  const bool degenerate = sweeps_.degenerate(m.start, m.end);
  const auto [a, b] =
      degenerate ? std::pair{m.start, m.start} : SweepPolytopeBuilder::ordered(m.start, m.end);
  const Vector3d motion = b - a, middle = 0.5 * (a + b);
  const double half = 0.5 * motion.norm();
  std::vector<signed char> side(tool.facets.size(), -1);
  if (!degenerate) motion_sides(tool, motion, side);
  facets.reserve(facets.size() + tool.facets.size() +
                 2 * static_cast<std::size_t>(std::sqrt(tool.facets.size())) + 64);
  std::size_t skipped = 0;
  for (std::size_t f = 0; f < tool.facets.size(); ++f) {
    if (culled(joint[f])) {
      ++skipped;
      continue;
    }
    const PolytopeFacet& facet = tool.facets[f];
    Placed p;
    p.facet = p.tool_facet = static_cast<int>(f);
    p.thickness = tool_facet_radii_[f];
    p.placement = side[f];
    const AlignedBox3d& box = tool_facet_boxes_[f];
    const Vector3d& at = side[f] > 0 ? b : a;
    p.plane = {facet.normal, facet.offset + facet.normal.dot(at)};
    if (side[f] == 0) {
      p.box = AlignedBox3d(box.min() + a, box.max() + a);
      p.box.extend(AlignedBox3d(box.min() + b, box.max() + b));
      p.centre = tool_facet_centres_[f] + middle;
      p.radius = tool_facet_radii_[f] + half;
      p.from = tool_facet_centres_[f] + a;
      p.to = tool_facet_centres_[f] + b;
    } else {
      p.box = AlignedBox3d(box.min() + at, box.max() + at);
      p.centre = p.from = p.to = tool_facet_centres_[f] + at;
      p.radius = tool_facet_radii_[f];
    }
    p.cluster = {tool_facet_cell_[f], p.placement};
    facets.push_back(p);
  }
  if (degenerate) return skipped;
  int index = static_cast<int>(tool.facets.size());
  const std::vector<SweepPolytopeBuilder::Edge>& edges = sweeps_.edges();
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (side[edges[e].left] * side[edges[e].right] < 0) facets.push_back(silhouette_face(e, index++, a, b));
  return skipped;
}

// The face of silhouette edge e of the sweep along [a, b] (ordered ends of a move that is not
// degenerate), facet `index` of the sweep.
SweepCulling::Placed SweepCulling::silhouette_face(std::size_t e, int index, const Vector3d& a,
                                                   const Vector3d& b) const {
  const ConvexPolytope& tool = sweeps_.tool();
  const SweepPolytopeBuilder::Edge& edge = sweeps_.edges()[e];
  const Vector3d motion = b - a, middle = 0.5 * (a + b);
  const double half = 0.5 * motion.norm();
  const Vector3d &u = tool.vertices[edge.from], &w = tool.vertices[edge.to];
  Placed p;
  p.facet = index;
  p.edge = static_cast<int>(e);
  const Halfspace look = sweeps_.silhouette_look(edge, a, motion);  // the culling reads the look alone
  p.plane = {look.normal, look.offset};
  p.box = AlignedBox3d(u + a);
  p.box.extend(w + a).extend(u + b).extend(w + b);
  p.centre = 0.5 * (u + w) + middle;
  p.radius = 0.5 * (u - w).norm() + half;
  p.from = 0.5 * (u + w) + a;
  p.to = 0.5 * (u + w) + b;
  p.thickness = 0.5 * (u - w).norm();
  p.cluster = {tool_facet_cell_[edge.left], 2};
  return p;
}

const SweepCulling::Faces& SweepCulling::faces(std::uint32_t j, Scratch& scratch,
                                               CullingCounts& counts) const {
  const auto found = scratch.slot_of_.find(j);
  if (found != scratch.slot_of_.end()) return scratch.recent_[found->second].second;
  ++counts.candidates_placed;
  // As place() places them, but only the sides of the tool facets (against() makes their faces)
  // and the silhouette faces.
  const ConvexPolytope& tool = sweeps_.tool();
  const Move& m = moves_[j];
  const bool degenerate = sweeps_.degenerate(m.start, m.end);
  const std::pair<Vector3d, Vector3d> ends =
      degenerate ? std::pair{m.start, m.start} : SweepPolytopeBuilder::ordered(m.start, m.end);
  Faces faces;
  faces.a = ends.first;
  faces.b = ends.second;
  faces.side.assign(tool.facets.size(), -1);
  if (!degenerate) {
    motion_sides(tool, faces.b - faces.a, faces.side);
    for (std::size_t k = 0; k < faces.side.size(); ++k)
      if (faces.side[k] == 0) faces.swept_facets.push_back(static_cast<int>(k));
    int index = static_cast<int>(tool.facets.size());
    const std::vector<SweepPolytopeBuilder::Edge>& edges = sweeps_.edges();
    for (std::size_t e = 0; e < edges.size(); ++e) {
      if (faces.side[static_cast<std::size_t>(edges[e].left)] *
              faces.side[static_cast<std::size_t>(edges[e].right)] >=
          0)
        continue;
      const Placed p = silhouette_face(e, index, faces.a, faces.b);
      faces.silhouette.push_back(
          {p.plane, AlignedBox3d(p.box.min().array() - rounding_, p.box.max().array() + rounding_)});
      faces.silhouette_edges.push_back(static_cast<int>(e));
      ++index;
    }
    for (std::size_t k = 0; k < faces.silhouette.size(); ++k) {
      if (k % kSilhouetteChunk == 0) faces.silhouette_chunks.emplace_back();
      faces.silhouette_chunks.back().extend(faces.silhouette[k].box);
    }
  }
  // The candidates of the last few hundred moves: a raster's neighbouring rows (about 60 kB each).
  constexpr std::size_t kRecent = 1024;
  std::size_t slot = scratch.recent_.size();
  if (slot < kRecent) {
    scratch.recent_.emplace_back(j, std::move(faces));
  } else {
    slot = scratch.next_;
    scratch.next_ = (scratch.next_ + 1) % kRecent;
    scratch.slot_of_.erase(scratch.recent_[slot].first);
    scratch.recent_[slot] = {j, std::move(faces)};
  }
  scratch.slot_of_[j] = slot;
  return scratch.recent_[slot].second;
}

// Facet p of move i (ordered ends `own`) against the candidates near its cluster: culled, or kept
// with its cutters in `keep`. Cheapest proofs first: the support functions, the shared cap and
// the inner bounds over every candidate (any of them culls the facet, whichever comes first),
// and only then the halfspaces, which are the cost.
SweepCulling::Culled SweepCulling::decide(const Placed& p, std::size_t i, const Ends& own,
                                          const std::vector<const Candidate*>& near,
                                          const std::vector<Vector3d>& vertices, const Candidate*& prover,
                                          KeptFacet& keep, CullingCounts& counts, Scratch& scratch) const {
  const ConvexPolytope& tool = sweeps_.tool();
  const Vector3d &a = own.a, &b = own.b;
  const Vector3d& n = p.plane.normal;
  // A swept face's plane holds a, and b only to within 1e-12·|b - a| (motion_side()).
  const double reach_i = p.tool_facet >= 0 && p.placement == 0 ? n.dot(a) : std::max(n.dot(a), n.dot(b));
  // The candidate that held the last facet culled by the bounds first: the next facets of the
  // cluster are often in it too. Any candidate holding the facet culls it, so the order of these
  // proofs changes nothing but their count.
  if (prover) {
    ++counts.bound_tests;
    if (ball_inside_sweep(bounds_, prover->a, prover->b, p.centre, p.radius) ||
        points_inside_sweep(bounds_, prover->a, prover->b, vertices))
      return Culled::Bound;
  }
  std::vector<const Candidate*>& open = scratch.open_;
  std::vector<double>& open_core = scratch.open_core_;  // each one's core_distance() of the centre
  open.clear();
  open_core.clear();
  AlignedBox3d box = p.box;
  box.min().array() -= rounding_;
  box.max().array() += rounding_;
  for (const Candidate* c : near) {
    // The candidate wholly below the facet's plane: both sweeps' support in the normal n is
    // the tool's plus the larger of n·a, n·b, so two dot products compare them exactly.
    if (std::max(n.dot(c->a), n.dot(c->b)) <= reach_i - rounding_) {
      ++counts.apart_by_support;
      continue;
    }
    // A cap placed at an end of the candidate, where the candidate places the same cap: one
    // facet of two polytopes, owned by the earlier move.
    if (p.tool_facet >= 0 && p.placement != 0) {
      const Vector3d& at = p.placement > 0 ? b : a;
      if (at == c->a || at == c->b) {
        const Placement mine{b - a, own.degenerate}, other{c->b - c->a, c->degenerate};
        const int side = other.side(tool.facets[p.tool_facet].normal);
        // Between exact sweeps the cap has one exact plane in both (sweep_polytope.h).
        if (side != 0 && (side > 0 ? c->b : c->a) == at &&
            ((exact_[i] && c->exact) ||
             cap_placed_alike(tool, facets_around_, p.tool_facet, mine, p.placement, other, side))) {
          if (c->move < i) return Culled::Shared;
          continue;
        }
      }
    }
    // A candidate whose box misses the facet's holds no point of it: the bounds and planes below
    // would find it apart, or a cutter that reaches nothing of the facet and leaves its pieces as
    // they are. A long silhouette face's ball reaches far beyond its box (a third of the
    // candidates the bounds left to the planes on bear.nc).
    if (!boxes_meet(tree_->box(c->move), box)) {
      ++counts.apart_by_box;
      continue;
    }
    ++counts.bound_tests;
    BallVerdict ball = BallVerdict::Unknown;
    double core = 0.0;
    if (c == prover) {  // asked above whether it holds the facet
      if (ball_misses_sweep(bounds_, c->a, c->b, p.centre, p.radius, &core)) ball = BallVerdict::Misses;
    } else {
      ball = ball_against_sweep(bounds_, c->a, c->b, p.centre, p.radius, &core);
      if (ball == BallVerdict::Inside || points_inside_sweep(bounds_, c->a, c->b, vertices)) {
        prover = c;
        return Culled::Bound;
      }
    }
    if (ball == BallVerdict::Misses ||
        (p.placement == 0 && capsule_misses_sweep(bounds_, c->a, c->b, p.from, p.to, p.thickness)))
      continue;
    open.push_back(c);
    open_core.push_back(core);
  }
  // The nearest core first: the candidate that holds the whole facet, when one does, is mostly
  // the one whose tool passes closest to it, and the cutters found before it are work thrown
  // away. The order changes nothing else: every candidate is asked when none holds the facet,
  // and the carving orders the cutters by itself.
  if (open.size() > 1) {
    std::size_t nearest = 0;
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < open.size(); ++k)
      if (open_core[k] < least) least = open_core[k], nearest = k;
    std::rotate(open.begin(), open.begin() + static_cast<std::ptrdiff_t>(nearest),
                open.begin() + static_cast<std::ptrdiff_t>(nearest) + 1);
  }
  for (const Candidate* c : open) {
    ++counts.plane_tests;
    // The planes go to the scratch first: most candidates turn out apart, and a new list for each
    // grew one allocation at a time.
    int points_below = 0;
    const Against verdict =
        against(p, i, own, c->move, vertices, faces(c->move, scratch, counts), scratch.near_faces_,
                scratch.planes_, scratch.marks_, points_below, counts);
    if (verdict == Against::Apart) continue;
    if (verdict == Against::Inside) return Culled::Planes;
    keep.cutters.push_back(FacetCutter{c->move, static_cast<std::uint32_t>(keep.planes.size()),
                                       static_cast<std::uint32_t>(scratch.planes_.size()), points_below});
    keep.planes.insert(keep.planes.end(), scratch.planes_.begin(), scratch.planes_.end());
  }
  return Culled::Open;
}

std::vector<KeptFacet> SweepCulling::cull(std::size_t i, CullingCounts& counts, Scratch& scratch) const {
  const ConvexPolytope& tool = sweeps_.tool();
  const Move& move = moves_[i];
  // 1-2. Joints and the stock. The tool facets a joint culls are not placed at all (three
  // quarters of all facets on bear.nc and heart).
  std::vector<JointVerdict> joint(tool.facets.size(), JointVerdict::Kept);
  const bool after = joined_[i], before = i + 1 < moves_.size() && joined_[i + 1];
  if (after || before) {
    std::optional<Vector3d> previous, next;
    if (after) previous = moves_[i - 1].end - moves_[i - 1].start;
    if (before) next = moves_[i + 1].end - moves_[i + 1].start;
    const bool exact = exact_[i] && (!after || exact_[i - 1]) && (!before || exact_[i + 1]);
    joint = exact ? joint_verdicts_exact(tool, facets_around_, move.end - move.start, previous, next)
                  : joint_verdicts_off_rim(tool, facets_around_, move.end - move.start, previous, next);
  }
  std::vector<Placed> facets;
  const std::size_t by_joint = place(i, joint, facets);
  counts.facets += static_cast<double>(facets.size() + by_joint);
  counts.by_joint += static_cast<double>(by_joint);
  const bool degenerate = sweeps_.degenerate(move.start, move.end);
  const std::pair<Vector3d, Vector3d> ends =
      degenerate ? std::pair{move.start, move.start} : SweepPolytopeBuilder::ordered(move.start, move.end);
  const Vector3d &a = ends.first, &b = ends.second;
  // Each live facet's points, by facet index: its corners, cut to the stock where it reaches out.
  std::vector<Placed> live;
  AlignedBox3d reach;
  std::vector<std::vector<Vector3d>>& points_of = scratch.points_of_;  // kept from move to move
  // Indexed by facet index; the facets come in increasing index, the culled ones left out.
  const std::size_t facet_count = facets.empty() ? 0 : static_cast<std::size_t>(facets.back().facet) + 1;
  if (points_of.size() < facet_count) points_of.resize(facet_count);
  for (Placed& p : facets) {
    if (outside(p.box, stock_) || !cut_to_stock(p, a, b, points_of[p.facet])) {
      ++counts.outside_stock;
    } else {
      live.push_back(p);
      reach.extend(p.box);
    }
  }
  if (live.empty()) return {};
  // Cutters matter inside the stock only (the clipping keeps no facet part outside it).
  reach =
      reach.intersection(AlignedBox3d(stock_.min().array() - rounding_, stock_.max().array() + rounding_));

  // 3. Move against move.
  std::vector<Candidate> candidates;
  bool retraced = false;
  tree_->for_each_overlapping(reach, [&](std::size_t j) {
    if (j == i || retraced) return;
    const Move& m = moves_[j];
    const bool degenerate_j = sweeps_.degenerate(m.start, m.end);
    const std::pair<Vector3d, Vector3d> e =
        degenerate_j ? std::pair{m.start, m.start} : SweepPolytopeBuilder::ordered(m.start, m.end);
    const Vector3d &aj = e.first, &bj = e.second;
    if (degenerate_j == degenerate && aj == a && bj == b) {  // the same polytope
      if (j < i) retraced = true;
      return;  // an earlier one owns all of it; a later one cuts none of it
    }
    candidates.push_back({static_cast<std::uint32_t>(j), aj, bj, degenerate_j, exact_[j]});
  });
  if (retraced) {
    counts.by_retrace += static_cast<double>(live.size());
    return {};
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const Candidate& x, const Candidate& y) { return x.move < y.move; });
  counts.candidates += static_cast<double>(candidates.size());

  // 4-5. Clusters, then facets: bounds first, halfspaces last.
  std::sort(live.begin(), live.end(), [](const Placed& x, const Placed& y) {
    return x.cluster < y.cluster || (x.cluster == y.cluster && x.facet < y.facet);
  });
  // The candidates' boxes (as the sweeps' tree has them), for the clusters: a cluster's ball
  // meets a few of them, and a walk of the tree of every sweep met many others. A scan of a
  // move's hundred or so costs less than building a tree of them for each move.
  std::vector<AlignedBox3d>& candidate_boxes = scratch.candidate_boxes_;
  candidate_boxes.clear();
  for (const Candidate& c : candidates) candidate_boxes.push_back(tree_->box(c.move));
  std::vector<KeptFacet> kept;
  std::vector<const Candidate*> near, reaching;
  const Candidate* last_hider = nullptr;
  const Candidate* last_prover = nullptr;
  for (std::size_t begin = 0, end; begin < live.size(); begin = end) {
    for (end = begin + 1; end < live.size() && live[end].cluster == live[begin].cluster;) ++end;
    Vector3d centre = Vector3d::Zero();
    for (std::size_t k = begin; k < end; ++k) centre += live[k].centre;
    centre /= static_cast<double>(end - begin);
    double radius = 0.0;
    for (std::size_t k = begin; k < end; ++k)
      radius = std::max(radius, (live[k].centre - centre).norm() + live[k].radius);
    near.clear();
    // The candidate that hid the last cluster first: neighbouring clusters are often hidden by it.
    bool hidden = last_hider && ball_inside_sweep(bounds_, last_hider->a, last_hider->b, centre, radius);
    // Only the candidates whose boxes meet the cluster's ball's box can hide it or meet its
    // facets (a box misses the ball: the sweep does), in move order as the facets take them.
    reaching.clear();
    if (!hidden) {
      const AlignedBox3d ball_box(centre.array() - radius, centre.array() + radius);
      for (std::size_t k = 0; k < candidates.size(); ++k)  // in move order, as the candidates are
        if (candidate_boxes[k].intersects(ball_box)) reaching.push_back(&candidates[k]);
    }
    for (const Candidate* c : reaching) {
      if (hidden) break;
      ++counts.bound_tests;
      const BallVerdict verdict = ball_against_sweep(bounds_, c->a, c->b, centre, radius);
      if (verdict == BallVerdict::Inside) {
        hidden = true;
        last_hider = c;
        break;
      }
      if (verdict == BallVerdict::Unknown) near.push_back(c);
    }
    if (hidden) {
      counts.by_cluster_bound += static_cast<double>(end - begin);
      continue;
    }
    for (std::size_t k = begin; k < end; ++k) {
      const Placed& p = live[k];
      KeptFacet& keep = scratch.keep_;  // its lists' storage kept from facet to facet
      keep.facet = p.facet;
      keep.cutters.clear();
      keep.planes.clear();
      const Culled culled_by =
          decide(p, i, Ends{a, b, degenerate}, near, points_of[p.facet], last_prover, keep, counts, scratch);
      switch (culled_by) {
        case Culled::Bound:
          ++counts.by_facet_bound;
          break;
        case Culled::Shared:
          ++counts.by_shared_cap;
          break;
        case Culled::Planes:
          ++counts.by_planes;
          break;
        case Culled::Open:
          ++counts.kept;
          counts.cutters += static_cast<double>(keep.cutters.size());
          counts.cutting_planes += static_cast<double>(keep.planes.size());
          kept.push_back(keep);  // a copy: only kept facets allocate; the scratch's lists stay
      }
    }
  }
  std::sort(kept.begin(), kept.end(),
            [](const KeptFacet& x, const KeptFacet& y) { return x.facet < y.facet; });
  return kept;
}

}  // namespace morph
