// SPDX-License-Identifier: Apache-2.0
#include <morph/aabb_tree.h>
#include <morph/exceptions.h>
#include <morph/joint_culling.h>
#include <morph/sweep_culling.h>

#include "generator2/tool_facet_groups.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace morph {

namespace {

using Eigen::AlignedBox3d;
using Eigen::Vector3d;

bool same_plane(const SweepCulling::FacePlane& p, const SweepCulling::FacePlane& q) {
  return p.normal == q.normal && p.offset == q.offset;
}

bool outside(const AlignedBox3d& box, const AlignedBox3d& stock) {
  return (box.min().array() > stock.max().array()).any() || (box.max().array() < stock.min().array()).any();
}

// A cluster of facets about one grid cell of the tool, at one placement.
struct ClusterKey {
  std::int64_t cell;
  int placement;
  bool operator<(const ClusterKey& o) const {
    return cell < o.cell || (cell == o.cell && placement < o.placement);
  }
  bool operator==(const ClusterKey& o) const { return cell == o.cell && placement == o.placement; }
};

// The facet's corners in loop order, from the points the plane tests use (a tool facet's loop
// at one end; a silhouette edge u, w at the ordered start and end: u+a, u+b, w+a, w+b; a facet
// clipped to the stock: its polygon), without the centroid appended last.
std::vector<Vector3d> ordered_polygon(bool silhouette, const std::vector<Vector3d>& points) {
  if (silhouette) return {points[0], points[2], points[3], points[1]};
  return std::vector<Vector3d>(points.begin(), points.end() - 1);
}

// The part of the convex polygon inside the box (Sutherland-Hodgman, one face at a time).
void clip_to_box(std::vector<Vector3d>& polygon, const AlignedBox3d& box) {
  std::vector<Vector3d> kept;
  for (int axis = 0; axis < 3 && polygon.size() >= 3; ++axis)
    for (const bool upper : {false, true}) {
      const double bound = upper ? box.max()[axis] : box.min()[axis];
      const auto value = [&](const Vector3d& x) { return upper ? x[axis] - bound : bound - x[axis]; };
      kept.clear();
      for (std::size_t k = 0; k < polygon.size(); ++k) {
        const Vector3d &x = polygon[k], &y = polygon[(k + 1) % polygon.size()];
        const double vx = value(x), vy = value(y);
        if (vx <= 0.0) kept.push_back(x);
        if ((vx < 0.0 && vy > 0.0) || (vx > 0.0 && vy < 0.0)) {
          Vector3d crossing = x + (y - x) * (vx / (vx - vy));
          crossing[axis] = bound;  // on the face, whatever the rounding of the rest
          kept.push_back(crossing);
        }
      }
      polygon.swap(kept);
      if (polygon.size() < 3) return;
    }
}

// The centroid of the facet's part below the candidate's planes `meeting` (the convex polygon is
// ordered from the facet's points), a point to prove inside the candidate; none when that part
// vanishes.
template <class PlaneOf>
std::optional<Vector3d> clipped_centroid(std::vector<Vector3d> polygon, const PlaneOf& plane_of,
                                         const std::vector<int>& meeting) {
  std::vector<Vector3d> below;
  for (int h : meeting) {
    const SweepCulling::FacePlane plane = plane_of(h);
    below.clear();
    for (std::size_t k = 0; k < polygon.size(); ++k) {
      const Vector3d &x = polygon[k], &y = polygon[(k + 1) % polygon.size()];
      const double vx = plane.normal.dot(x) - plane.offset, vy = plane.normal.dot(y) - plane.offset;
      if (vx <= 0.0) below.push_back(x);
      if ((vx < 0.0 && vy > 0.0) || (vx > 0.0 && vy < 0.0)) below.push_back(x + (y - x) * (vx / (vx - vy)));
    }
    polygon.swap(below);
    if (polygon.size() < 3) return std::nullopt;
  }
  Vector3d centroid = Vector3d::Zero();
  for (const Vector3d& x : polygon) centroid += x;
  return centroid / static_cast<double>(polygon.size());
}

}  // namespace

CullingCounts& CullingCounts::operator+=(const CullingCounts& o) {
  facets += o.facets, by_joint += o.by_joint, outside_stock += o.outside_stock, by_retrace += o.by_retrace;
  by_cluster_bound += o.by_cluster_bound, by_facet_bound += o.by_facet_bound,
      by_shared_cap += o.by_shared_cap;
  by_planes += o.by_planes, kept += o.kept, cutters += o.cutters, cutting_planes += o.cutting_planes;
  candidates += o.candidates, bound_tests += o.bound_tests, plane_tests += o.plane_tests;
  without_witness += o.without_witness, apart_by_support += o.apart_by_support,
      candidates_placed += o.candidates_placed;
  return *this;
}

// A candidate sweep of a move: its ordered ends.
struct SweepCulling::Candidate {
  std::uint32_t move;
  Vector3d a, b;
  bool degenerate;
  bool exact;
};

// A facet of a sweep as placed from the tool: a tool facet at one end (placement -1 at the
// ordered start, +1 at the ordered end) or swept whole (0), or a silhouette edge (0).
struct SweepCulling::Placed {
  int facet = 0, tool_facet = -1, edge = -1, placement = 0;
  AlignedBox3d box;
  Vector3d centre;
  double radius = 0.0;
  Vector3d from, to;  // the facet lies within `thickness` of the segment [from, to]
  double thickness = 0.0;
  FacePlane plane;
  ClusterKey cluster{};
  /// Reaching out of the stock, so cut to it: the points are its polygon's, in order, and the
  /// bounds above are theirs.
  bool clipped = false;
};

SweepCulling::SweepCulling(const SweepPolytopeBuilder& sweeps, std::vector<Move> moves,
                           std::vector<bool> joined, const AlignedBox3d& stock)
    : sweeps_(sweeps), moves_(std::move(moves)), joined_(std::move(joined)), stock_(stock) {
  if (joined_.size() != moves_.size()) throw InputError("sweep culling: one joint flag per move is needed");
  const ConvexPolytope& tool = sweeps_.tool();
  bounds_ = tool_bounds(tool);
  // Clusters: a grid of cells of half the inscribed radius (at least a fiftieth of the tool).
  const AlignedBox3d tool_box = tool.bounds();
  facets_at_vertex_ = facets_at_vertices(tool);
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
  std::vector<AlignedBox3d> facet_boxes, edge_boxes;
  for (const AlignedBox3d& box : tool_facet_boxes_)
    facet_boxes.emplace_back(box.min().array() - rounding_, box.max().array() + rounding_);
  for (const SweepPolytopeBuilder::Edge& e : sweeps_.edges()) {
    AlignedBox3d box(tool.vertices[e.from]);
    box.extend(tool.vertices[e.to]);
    edge_boxes.emplace_back(box.min().array() - rounding_, box.max().array() + rounding_);
  }
  tool_facet_tree_ = std::make_unique<AabbTree>(std::move(facet_boxes));
  tool_edge_tree_ = std::make_unique<AabbTree>(std::move(edge_boxes));
  facet_groups_ = std::make_unique<ToolFacetGroups>(tool);
}

SweepCulling::~SweepCulling() = default;

// Every facet of move i's sweep, placed as the builder places it (the same arithmetic).
void SweepCulling::place(std::size_t i, std::vector<Placed>& facets) const {
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
  for (std::size_t f = 0; f < tool.facets.size(); ++f) {
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
  if (degenerate) return;
  int index = static_cast<int>(tool.facets.size());
  const std::vector<SweepPolytopeBuilder::Edge>& edges = sweeps_.edges();
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (side[edges[e].left] * side[edges[e].right] < 0) facets.push_back(silhouette_face(e, index++, a, b));
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
  faces.face_of_edge.assign(sweeps_.edges().size(), -1);
  if (!degenerate) {
    motion_sides(tool, faces.b - faces.a, faces.side);
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
      faces.face_of_edge[e] = index++;
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

// Facet p of move i against candidate j's faces, by halfspaces. `points`: the facet's corners
// and, last, its centroid. On Cuts, `planes` are the candidate's planes that cut it.
SweepCulling::Against SweepCulling::against(const Placed& p, std::size_t i, std::uint32_t j,
                                            const std::vector<Vector3d>& points, const Faces& candidate,
                                            std::vector<int>& near_faces, std::vector<int>& planes,
                                            CullingCounts& counts) const {
  const auto first_silhouette = static_cast<int>(sweeps_.tool().facets.size());
  const int face_count = first_silhouette + static_cast<int>(candidate.silhouette.size());
  // Face h's plane and box: a tool facet's placed at the candidate's end by place()'s arithmetic
  // (the same numbers, bit for bit), a silhouette face's as faces() keeps it. Made here rather
  // than kept for each of a thread's recent candidates: reading ~700 kept faces of each was
  // memory-bound (the first touch of a candidate's faces alone was a tenth of against()).
  auto face_plane = [&](int h) -> FacePlane {
    if (h >= first_silhouette)
      return candidate.silhouette[static_cast<std::size_t>(h - first_silhouette)].plane;
    const FacePlane& t = tool_planes_[static_cast<std::size_t>(h)];
    const Vector3d& at = candidate.side[static_cast<std::size_t>(h)] > 0 ? candidate.b : candidate.a;
    return {t.normal, t.offset + t.normal.dot(at)};
  };
  auto face_box = [&](int h) -> AlignedBox3d {
    if (h >= first_silhouette)
      return candidate.silhouette[static_cast<std::size_t>(h - first_silhouette)].box;
    const AlignedBox3d& t = tool_facet_boxes_[static_cast<std::size_t>(h)];
    const int side = candidate.side[static_cast<std::size_t>(h)];
    AlignedBox3d box;
    if (side == 0) {
      box = AlignedBox3d(t.min() + candidate.a, t.max() + candidate.a);
      box.extend(AlignedBox3d(t.min() + candidate.b, t.max() + candidate.b));
    } else {
      const Vector3d& at = side > 0 ? candidate.b : candidate.a;
      box = AlignedBox3d(t.min() + at, t.max() + at);
    }
    return AlignedBox3d(box.min().array() - rounding_, box.max().array() + rounding_);
  };
  auto value = [&](int h, const Vector3d& x) {
    const FacePlane plane = face_plane(h);
    return plane.normal.dot(x) - plane.offset;
  };
  // A face in the facet's own plane is the tie: below an earlier polytope's plane, above a later one's.
  // Only the same tool facet, or a silhouette face, can have the facet's plane bit for bit.
  int tie_face = -1;
  if (p.tool_facet >= 0) {
    if (same_plane(face_plane(p.tool_facet), p.plane)) tie_face = p.tool_facet;
  } else {
    for (int h = first_silhouette; h < face_count && tie_face < 0; ++h)
      if (same_plane(face_plane(h), p.plane)) tie_face = h;
  }
  auto tie = [&](int h) { return h == tie_face; };
  auto above = [&](int h) {
    const FacePlane plane = face_plane(h);
    return std::all_of(points.begin(), points.end(),
                       [&](const Vector3d& x) { return plane.normal.dot(x) - plane.offset >= rounding_; });
  };
  // A face's plane against the facet's points: true when the facet lies above it (apart); a plane
  // the facet straddles goes into `planes`.
  auto separates_or_crosses = [&](int h) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    const FacePlane plane = face_plane(h);
    for (const Vector3d& x : points) {
      const double v = plane.normal.dot(x) - plane.offset;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
    if (lo >= rounding_) return true;
    if (hi > -rounding_) planes.push_back(h);
    return false;
  };
  // The faces' loops below skip the tool facets' groups that cannot reach the threshold
  // (tool_facet_groups.h): the silhouette faces, from index `first_silhouette` on, go one by one.
  auto inside = [&](const Vector3d& x) {
    // The inner bounds first: deeper than the slack inside the tool's inscribed ball or cylinder.
    if (ball_inside_sweep(bounds_, candidate.a, candidate.b, x, 0.0)) return true;
    if (!facet_groups_->for_each_reaching(x, 0.0, candidate.a, candidate.b, -rounding_,
                                          [&](int h) { return tie(h) || value(h, x) <= -rounding_; }))
      return false;
    for (int h = first_silhouette; h < face_count; ++h)
      if (!tie(h) && value(h, x) > -rounding_) return false;
    return true;
  };
  // The candidate's planes of the facet's own tool facets first: where two sweeps are apart,
  // one of them usually shows it.
  const int left = p.edge >= 0 ? sweeps_.edges()[p.edge].left : p.tool_facet;
  const int right = p.edge >= 0 ? sweeps_.edges()[p.edge].right : -1;
  for (int h : {left, right})
    if (h >= 0 && !tie(h) && above(h)) return Against::Apart;
  // Only the faces whose boxes meet the facet's can meet it: their planes either show it apart,
  // or leave it below (then it meets no face: wholly inside or wholly outside), or cross it.
  AlignedBox3d box = p.box;
  box.min().array() -= rounding_;
  box.max().array() += rounding_;
  // Found from the tool's facets and edges: a face placed at a (or b) meets the box only if its
  // tool facet meets the box moved by -a (or -b); a face swept along [a, b] only if it meets the
  // box swept along [-b, -a].
  near_faces.clear();
  const Vector3d& a = candidate.a;
  const Vector3d& b = candidate.b;
  // One walk of the tree with the swept box, which holds the box moved by -a and by -b; each
  // facet placed at an end is then tested against its own (the set of three walks).
  const AlignedBox3d at_a(box.min() - a, box.max() - a), at_b(box.min() - b, box.max() - b);
  const AlignedBox3d swept(box.min() - a.cwiseMax(b), box.max() - a.cwiseMin(b));
  tool_facet_tree_->for_each_overlapping(swept, [&](std::size_t k) {
    const int side = candidate.side[k];
    if (side == 0 || tool_facet_tree_->box(k).intersects(side < 0 ? at_a : at_b))
      near_faces.push_back(static_cast<int>(k));
  });
  tool_edge_tree_->for_each_overlapping(swept, [&](std::size_t e) {
    if (candidate.face_of_edge[e] >= 0) near_faces.push_back(candidate.face_of_edge[e]);
  });
  std::sort(near_faces.begin(), near_faces.end());
  planes.clear();
  for (int h : near_faces) {
    if (!face_box(h).intersects(box)) continue;
    if (tie(h)) {
      if (j > i) return Against::Apart;
      continue;
    }
    if (separates_or_crosses(h)) return Against::Apart;
  }
  const Vector3d& centroid = points.back();
  if (planes.empty()) {
    if (inside(centroid)) return Against::Inside;
    if (!facet_groups_->for_each_reaching(centroid, 0.0, candidate.a, candidate.b, rounding_,
                                          [&](int h) { return value(h, centroid) < rounding_; }))
      return Against::Apart;
    for (int h = first_silhouette; h < face_count; ++h)
      if (value(h, centroid) >= rounding_) return Against::Apart;
  } else {
    // With a point of the facet inside the candidate, the facet's part inside it is its part
    // below the crossing planes (a segment from that point leaves the candidate through a face
    // meeting the facet).
    const bool swept = p.tool_facet >= 0 && p.placement == 0;
    // Proven inside by every face of the candidate, the tie's too (the tool facets' groups skip
    // those certainly below, as in `inside`).
    auto below_every_face = [&](const Vector3d& x) {
      if (!facet_groups_->for_each_reaching(x, 0.0, candidate.a, candidate.b, -rounding_,
                                            [&](int h) { return value(h, x) <= -rounding_; }))
        return false;
      for (int h = first_silhouette; h < face_count; ++h)
        if (value(h, x) > -rounding_) return false;
      return true;
    };
    if (std::any_of(points.begin(), points.end(), inside)) return Against::Cuts;
    if (!swept) {
      const std::optional<Vector3d> centroid =
          clipped_centroid(ordered_polygon(p.edge >= 0 && !p.clipped, points), face_plane, planes);
      if (centroid && below_every_face(*centroid)) return Against::Cuts;
    }
  }
  // Undecided within the rounding: every plane that crosses the facet.
  ++counts.without_witness;
  planes.clear();
  double radius = 0.0;
  for (const Vector3d& x : points) radius = std::max(radius, (x - centroid).norm());
  if (!facet_groups_->for_each_reaching(centroid, radius, candidate.a, candidate.b, -rounding_,
                                        [&](int h) { return tie(h) || !separates_or_crosses(h); }))
    return Against::Apart;
  for (int h = first_silhouette; h < face_count; ++h) {
    if (tie(h)) continue;
    if (separates_or_crosses(h)) return Against::Apart;
  }
  std::sort(planes.begin(), planes.end());  // in face order, as the cutter lists them
  return planes.empty() ? Against::Inside : Against::Cuts;
}

// The points the plane tests take of facet p of the sweep along [a, b] (ordered ends): its
// corners (a tool facet's loop at its end or ends, a silhouette edge's u+a, u+b, w+a, w+b) and
// last their centroid. Only the facet's part in the stock is carved, so a facet reaching out of
// the stock (grown by the rounding) is cut to it first: a V-bit's facet runs from its tip to its
// rim, far above a shallow engraving, and its bounds met every sweep nearby while its part in
// the stock met few. Then the points are the cut polygon's, in order, and p's bounds are theirs.
// False when nothing of the facet is left (a tool facet swept along the move is not cut).
bool SweepCulling::cut_to_stock(Placed& p, const Vector3d& a, const Vector3d& b,
                                std::vector<Vector3d>& points) const {
  const ConvexPolytope& tool = sweeps_.tool();
  points.clear();
  auto add = [&](int v) {
    if (p.placement <= 0) points.push_back(tool.vertices[v] + a);
    if (p.placement >= 0) points.push_back(tool.vertices[v] + b);
  };
  if (p.tool_facet >= 0) {
    for (int v : tool.facets[p.tool_facet].loop) add(v);
  } else {
    add(sweeps_.edges()[p.edge].from);
    add(sweeps_.edges()[p.edge].to);
  }
  const AlignedBox3d stock(stock_.min().array() - rounding_, stock_.max().array() + rounding_);
  const bool swept = p.tool_facet >= 0 && p.placement == 0;
  if (!swept &&
      !std::all_of(points.begin(), points.end(), [&](const Vector3d& x) { return stock.contains(x); })) {
    if (p.edge >= 0) points = {points[0], points[2], points[3], points[1]};
    clip_to_box(points, stock);
    if (points.size() < 3) return false;
    p.clipped = true;
    p.box = AlignedBox3d();
    for (const Vector3d& x : points) p.box.extend(x);
    p.centre = Vector3d::Zero();
    for (const Vector3d& x : points) p.centre += x;
    p.centre /= static_cast<double>(points.size());
    p.radius = 0.0;
    for (const Vector3d& x : points) p.radius = std::max(p.radius, (x - p.centre).norm());
    if (p.placement == 0) {  // a silhouette edge's face: the capsule along its motion
      const Vector3d axis = p.to - p.from;
      double low = std::numeric_limits<double>::infinity(), high = -low, thickness = 0.0;
      for (const Vector3d& x : points) {
        const double t = (x - p.from).dot(axis) / axis.squaredNorm();
        low = std::min(low, t);
        high = std::max(high, t);
        thickness = std::max(thickness, (x - (p.from + t * axis)).norm());
      }
      const Vector3d from = p.from + low * axis, to = p.from + high * axis;
      p.from = from, p.to = to, p.thickness = thickness;
    } else {
      p.from = p.to = p.centre;
    }
  }
  Vector3d centroid = Vector3d::Zero();
  for (const Vector3d& x : points) centroid += x;
  points.push_back(centroid / static_cast<double>(points.size()));  // inside the facet
  return true;
}

// Facet p of move i (ordered ends `own`) against the candidates near its cluster: culled, or kept
// with its cutters in `keep`. Cheapest proofs first: the support functions, the shared cap and
// the inner bounds over every candidate (any of them culls the facet, whichever comes first),
// and only then the halfspaces, which are the cost.
SweepCulling::Culled SweepCulling::decide(const Placed& p, std::size_t i, const Ends& own,
                                          const std::vector<const Candidate*>& near,
                                          const std::vector<Vector3d>& vertices, KeptFacet& keep,
                                          CullingCounts& counts, Scratch& scratch) const {
  const ConvexPolytope& tool = sweeps_.tool();
  const Vector3d &a = own.a, &b = own.b;
  const Vector3d& n = p.plane.normal;
  // A swept face's plane holds a, and b only to within 1e-12·|b - a| (motion_side()).
  const double reach_i = p.tool_facet >= 0 && p.placement == 0 ? n.dot(a) : std::max(n.dot(a), n.dot(b));
  std::vector<const Candidate*>& open = scratch.open_;
  open.clear();
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
             cap_placed_alike(tool, facets_at_vertex_, p.tool_facet, mine, p.placement, other, side))) {
          if (c->move < i) return Culled::Shared;
          continue;
        }
      }
    }
    ++counts.bound_tests;
    if (ball_inside_sweep(bounds_, c->a, c->b, p.centre, p.radius) ||
        points_inside_sweep(bounds_, c->a, c->b, vertices))
      return Culled::Bound;
    if (ball_misses_sweep(bounds_, c->a, c->b, p.centre, p.radius) ||
        (p.placement == 0 && capsule_misses_sweep(bounds_, c->a, c->b, p.from, p.to, p.thickness)))
      continue;
    open.push_back(c);
  }
  for (const Candidate* c : open) {
    ++counts.plane_tests;
    // The planes go to the scratch first: most candidates turn out apart, and a new list for each
    // grew one allocation at a time.
    const Against verdict = against(p, i, c->move, vertices, faces(c->move, scratch, counts),
                                    scratch.near_faces_, scratch.planes_, counts);
    if (verdict == Against::Apart) continue;
    if (verdict == Against::Inside) return Culled::Planes;
    keep.cutters.push_back(FacetCutter{c->move, scratch.planes_});
  }
  return Culled::Open;
}

std::vector<KeptFacet> SweepCulling::cull(std::size_t i, CullingCounts& counts, Scratch& scratch) const {
  const ConvexPolytope& tool = sweeps_.tool();
  const Move& move = moves_[i];
  std::vector<Placed> facets;
  place(i, facets);
  counts.facets += static_cast<double>(facets.size());

  // 1-2. Joints and the stock.
  std::vector<JointVerdict> joint(tool.facets.size(), JointVerdict::Kept);
  const bool after = joined_[i], before = i + 1 < moves_.size() && joined_[i + 1];
  if (after || before) {
    std::optional<Vector3d> previous, next;
    if (after) previous = moves_[i - 1].end - moves_[i - 1].start;
    if (before) next = moves_[i + 1].end - moves_[i + 1].start;
    const bool exact = exact_[i] && (!after || exact_[i - 1]) && (!before || exact_[i + 1]);
    joint = exact ? joint_verdicts_exact(tool, facets_at_vertex_, move.end - move.start, previous, next)
                  : joint_verdicts_off_rim(tool, facets_at_vertex_, move.end - move.start, previous, next);
  }
  const bool degenerate = sweeps_.degenerate(move.start, move.end);
  const std::pair<Vector3d, Vector3d> ends =
      degenerate ? std::pair{move.start, move.start} : SweepPolytopeBuilder::ordered(move.start, move.end);
  const Vector3d &a = ends.first, &b = ends.second;
  // Each live facet's points, by facet index: its corners, cut to the stock where it reaches out.
  std::vector<Placed> live;
  AlignedBox3d reach;
  std::vector<std::vector<Vector3d>>& points_of = scratch.points_of_;  // kept from move to move
  if (points_of.size() < facets.size()) points_of.resize(facets.size());
  for (Placed& p : facets) {
    if (p.tool_facet >= 0 && culled(joint[p.tool_facet])) {
      ++counts.by_joint;
    } else if (outside(p.box, stock_) || !cut_to_stock(p, a, b, points_of[p.facet])) {
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
  // The candidates' own tree (their boxes as the sweeps' tree has them), for the clusters: a
  // cluster's ball meets a few of them, and a walk of the tree of every sweep met many others.
  std::vector<AlignedBox3d> candidate_boxes;
  candidate_boxes.reserve(candidates.size());
  for (const Candidate& c : candidates) candidate_boxes.push_back(tree_->box(c.move));
  const AabbTree candidate_tree(std::move(candidate_boxes));
  std::vector<KeptFacet> kept;
  std::vector<const Candidate*> near, reaching;
  const Candidate* last_hider = nullptr;
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
    if (!hidden)
      candidate_tree.for_each_overlapping(AlignedBox3d(centre.array() - radius, centre.array() + radius),
                                          [&](std::size_t k) { reaching.push_back(&candidates[k]); });
    std::sort(reaching.begin(), reaching.end());  // candidates are in move order
    for (const Candidate* c : reaching) {
      if (hidden) break;
      ++counts.bound_tests;
      if (ball_inside_sweep(bounds_, c->a, c->b, centre, radius)) {
        hidden = true;
        last_hider = c;
        break;
      }
      if (!ball_misses_sweep(bounds_, c->a, c->b, centre, radius)) near.push_back(c);
    }
    if (hidden) {
      counts.by_cluster_bound += static_cast<double>(end - begin);
      continue;
    }
    for (std::size_t k = begin; k < end; ++k) {
      const Placed& p = live[k];
      KeptFacet keep{p.facet, {}};
      const Culled culled_by =
          decide(p, i, Ends{a, b, degenerate}, near, points_of[p.facet], keep, counts, scratch);
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
          for (const FacetCutter& c : keep.cutters)
            counts.cutting_planes += static_cast<double>(c.planes.size());
          kept.push_back(std::move(keep));
      }
    }
  }
  std::sort(kept.begin(), kept.end(),
            [](const KeptFacet& x, const KeptFacet& y) { return x.facet < y.facet; });
  return kept;
}

}  // namespace morph
