// SPDX-License-Identifier: Apache-2.0
// Step 5 of the culling (sweep_culling.h): a facet against a candidate sweep's halfspaces, after
// the facet is cut to the stock.
#include <morph/aabb_tree.h>
#include <morph/sweep_culling.h>

#include "generator/sweep_culling_facets.h"
#include "generator/tool_facet_groups.h"
#include "generator/tool_facet_sectors.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

namespace morph {
namespace {

using Eigen::AlignedBox3d;
using Eigen::Vector3d;

// A tool of this many facets or fewer has their boxes scanned, not walked as a tree.
constexpr std::size_t kScannedToolFacets = 128;

bool same_plane(const SweepCulling::FacePlane& p, const SweepCulling::FacePlane& q) {
  return p.normal == q.normal && p.offset == q.offset;
}

// The facet's corners in loop order, from the points the plane tests use (a tool facet's loop
// at one end; a silhouette edge u, w at the ordered start and end: u+a, u+b, w+a, w+b; a facet
// clipped to the stock: its polygon), without the centroid appended last.
std::vector<Vector3d> ordered_polygon(bool silhouette, const std::vector<Vector3d>& points) {
  if (silhouette) return {points[0], points[2], points[3], points[1]};
  return std::vector<Vector3d>(points.begin(), points.end() - 1);
}

// The part of the convex polygon inside the box (Sutherland-Hodgman, one face at a time).
void clip_to_box(std::vector<Vector3d>& polygon, const AlignedBox3d& box) {
  thread_local std::vector<Vector3d> kept;  // storage, swapped with the polygon's
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

// One facet of move i against one candidate j's halfspaces (against()): the candidate's faces as
// the tests read them, and the steps of the test, cheapest first.
class SweepCulling::HalfspaceTest {
 public:
  HalfspaceTest(const SweepCulling& culling, const Placed& p, std::size_t i, const Ends& own, std::uint32_t j,
                const std::vector<Vector3d>& points, const Faces& candidate, std::vector<int>& near_faces,
                std::vector<int>& planes, std::vector<char>& marks, int& points_below, CullingCounts& counts)
      : c_(culling),
        p_(p),
        i_(i),
        own_(own),
        j_(j),
        points_(points),
        candidate_(candidate),
        near_faces_(near_faces),
        planes_(planes),
        marks_(marks),
        points_below_(points_below),
        counts_(counts),
        first_silhouette_(static_cast<int>(culling.sweeps_.tool().facets.size())),
        face_count_(first_silhouette_ + static_cast<int>(candidate.silhouette.size())) {
    // A face in the facet's own plane is the tie: below an earlier polytope's plane, above a
    // later one's. Only the same tool facet, or a silhouette face, can have the facet's plane bit
    // for bit.
    if (p.tool_facet >= 0) {
      if (same_plane(face_plane(p.tool_facet), p.plane)) tie_face_ = p.tool_facet;
    } else {
      for (int h = first_silhouette_; h < face_count_ && tie_face_ < 0; ++h)
        if (same_plane(face_plane(h), p.plane)) tie_face_ = h;
    }
  }

  Against run() {
    if (apart_by_a_likely_face()) return Against::Apart;
    find_near_faces();
    if (const std::optional<Against> verdict = judge_near_faces()) return *verdict;
    if (const std::optional<Against> verdict = witnessed()) return *verdict;
    return every_crossing_plane();
  }

 private:
  // Face h's plane and box: a tool facet's placed at the candidate's end by place()'s arithmetic
  // (the same numbers, bit for bit), a silhouette face's as faces() keeps it. Made here rather
  // than kept for each of a thread's recent candidates: reading ~700 kept faces of each was
  // memory-bound (the first touch of a candidate's faces alone was a tenth of against()).
  FacePlane face_plane(int h) const {
    if (h >= first_silhouette_)
      return candidate_.silhouette[static_cast<std::size_t>(h - first_silhouette_)].plane;
    const FacePlane& t = c_.tool_planes_[static_cast<std::size_t>(h)];
    const Vector3d& at = candidate_.side[static_cast<std::size_t>(h)] > 0 ? candidate_.b : candidate_.a;
    return {t.normal, t.offset + t.normal.dot(at)};
  }
  AlignedBox3d face_box(int h) const {
    if (h >= first_silhouette_)
      return candidate_.silhouette[static_cast<std::size_t>(h - first_silhouette_)].box;
    const AlignedBox3d& t = c_.tool_facet_boxes_[static_cast<std::size_t>(h)];
    const int side = candidate_.side[static_cast<std::size_t>(h)];
    AlignedBox3d box;
    if (side == 0) {
      box = AlignedBox3d(t.min() + candidate_.a, t.max() + candidate_.a);
      box.extend(AlignedBox3d(t.min() + candidate_.b, t.max() + candidate_.b));
    } else {
      const Vector3d& at = side > 0 ? candidate_.b : candidate_.a;
      box = AlignedBox3d(t.min() + at, t.max() + at);
    }
    return AlignedBox3d(box.min().array() - c_.rounding_, box.max().array() + c_.rounding_);
  }
  double value(int h, const Vector3d& x) const {
    const FacePlane plane = face_plane(h);
    return plane.normal.dot(x) - plane.offset;
  }
  bool tie(int h) const { return h == tie_face_; }
  // Every point of the facet above face h's plane by the rounding.
  bool above(int h) const {
    const FacePlane plane = face_plane(h);
    return std::all_of(points_.begin(), points_.end(),
                       [&](const Vector3d& x) { return plane.normal.dot(x) - plane.offset >= c_.rounding_; });
  }
  // A face's plane against the facet's points: true when the facet lies above it (apart); a plane
  // the facet straddles goes into `planes`. Marks the points the plane has not below it by the
  // rounding (`inside` would find that face).
  bool separates_or_crosses(int h) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    const FacePlane plane = face_plane(h);
    for (std::size_t k = 0; k < points_.size(); ++k) {
      const double v = plane.normal.dot(points_[k]) - plane.offset;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
      if (v > -c_.rounding_ && k < 64) not_below_ |= std::uint64_t{1} << k;
    }
    if (lo >= c_.rounding_) return true;
    if (hi > -c_.rounding_) planes_.push_back(h);
    return false;
  }
  // A cutter, with how many points its near faces all have below them (its order, carve_culled.h).
  Against cuts() {
    points_below_ =
        static_cast<int>(std::min<std::size_t>(points_.size(), 64)) - __builtin_popcountll(not_below_);
    return Against::Cuts;
  }
  // Below every face's plane by the rounding (the tie's excepted when `but_tie`). The faces' loops
  // skip the tool facets' groups that cannot reach the threshold (tool_facet_groups.h): the
  // silhouette faces, from index first_silhouette_ on, go one by one.
  bool below_faces(const Vector3d& x, bool but_tie) const {
    if (!c_.facet_groups_->for_each_reaching(x, 0.0, candidate_.a, candidate_.b, -c_.rounding_, [&](int h) {
          return (but_tie && tie(h)) || value(h, x) <= -c_.rounding_;
        }))
      return false;
    for (int h = first_silhouette_; h < face_count_; ++h)
      if (!(but_tie && tie(h)) && value(h, x) > -c_.rounding_) return false;
    return true;
  }
  // The inner bounds first: deeper than the slack inside the tool's inscribed ball or cylinder.
  bool inside(const Vector3d& x) const {
    return ball_inside_sweep(c_.bounds_, candidate_.a, candidate_.b, x, 0.0) || below_faces(x, true);
  }

  // 1. The candidate's planes of the facet's own tool facets: where two sweeps are apart, one of
  // them usually shows it. Then the candidate's face that leans furthest from its tool's path
  // toward the facet: its plane usually shows it, and finding it costs a climb over a few tool
  // facets, where the walk below tests every face near the facet.
  bool apart_by_a_likely_face() {
    left_ = p_.edge >= 0 ? c_.sweeps_.edges()[p_.edge].left : p_.tool_facet;
    right_ = p_.edge >= 0 ? c_.sweeps_.edges()[p_.edge].right : -1;
    for (int h : {left_, right_})
      if (h >= 0 && !tie(h) && above(h)) return true;
    const Vector3d a = candidate_.a + Vector3d(0.0, 0.0, c_.bounds_.centre_height);
    const Vector3d motion = candidate_.b - candidate_.a;
    const double length2 = motion.squaredNorm();
    const double t = length2 > 0.0 ? std::clamp((p_.centre - a).dot(motion) / length2, 0.0, 1.0) : 0.0;
    Vector3d core = a + t * motion;
    core.z() += std::clamp(p_.centre.z() - core.z(), 0.0, c_.bounds_.top - c_.bounds_.centre_height);
    const Vector3d away = p_.centre - core;
    if (away.squaredNorm() > 0.0) {
      const int h = c_.support_facet(left_, away);
      if (h != left_ && h != right_ && !tie(h) && above(h)) return true;
    }
    return false;
  }

  // 2. Only the faces whose boxes meet the facet's can meet it: their planes either show it
  // apart, or leave it below (then it meets no face: wholly inside or wholly outside), or cross
  // it. Found from the tool's facets and edges: a face placed at a (or b) meets the box only if
  // its tool facet meets the box moved by -a (or -b); a face swept along [a, b] only if it meets
  // the box swept along [-b, -a].
  void find_near_faces() {
    AlignedBox3d box = p_.box;
    box.min().array() -= c_.rounding_;
    box.max().array() += c_.rounding_;
    near_faces_.clear();
    const Vector3d& a = candidate_.a;
    const Vector3d& b = candidate_.b;
    // A tool facet placed at a meets the box only if it meets the box moved by -a (at b, by -b);
    // one swept along [a, b] only if it meets the box swept along [-b, -a].
    const AlignedBox3d at_a(box.min() - a, box.max() - a), at_b(box.min() - b, box.max() - b);
    const AlignedBox3d swept(box.min() - a.cwiseMax(b), box.max() - a.cwiseMin(b));
    // Each kept only where its face, as placed, meets the facet's box.
    auto near_face = [&](std::size_t k, const AlignedBox3d& moved) {
      if (boxes_meet(c_.tool_facet_tree_->box(k), moved) && boxes_meet(face_box(static_cast<int>(k)), box))
        near_faces_.push_back(static_cast<int>(k));
    };
    if (c_.tool_facet_tree_->size() <= kScannedToolFacets) {
      for (std::size_t k = 0; k < c_.tool_facet_tree_->size(); ++k) {
        const int side = candidate_.side[k];
        near_face(k, side == 0 ? swept : side < 0 ? at_a : at_b);
      }
    } else {
      // The tool's rings and sectors list the few facets near each end's box (tool_facet_sectors.h):
      // each facet placed at a from the first list, at b from the second; the swept ones, a few,
      // from the candidate's own list.
      c_.tool_facet_sectors_->for_each_candidate(at_a, [&](std::uint32_t k) {
        if (candidate_.side[k] < 0) near_face(k, at_a);
      });
      if (a != b)
        c_.tool_facet_sectors_->for_each_candidate(at_b, [&](std::uint32_t k) {
          if (candidate_.side[k] > 0) near_face(k, at_b);
        });
      for (int k : candidate_.swept_facets) near_face(static_cast<std::size_t>(k), swept);
    }
    // The silhouette faces, a few dozen, by their boxes, a chunk of neighbours at a time: a walk of
    // the edges' tree with the swept box met most of the tool's edges when the candidate is long,
    // to find the few on its silhouette.
    const std::size_t chunk = SweepCulling::kSilhouetteChunk;
    for (std::size_t c = 0; c < candidate_.silhouette_chunks.size(); ++c) {
      if (!boxes_meet(candidate_.silhouette_chunks[c], box)) continue;
      for (std::size_t k = c * chunk; k < std::min(candidate_.silhouette.size(), (c + 1) * chunk); ++k)
        if (boxes_meet(candidate_.silhouette[k].box, box))
          near_faces_.push_back(first_silhouette_ + static_cast<int>(k));
    }
  }

  // 3. The near faces' planes: one above the facet shows it apart (so does the tie, for a later
  // candidate); the others that cross it are listed, sorted into the face order the cutter lists
  // them in. With none crossing, the facet is wholly inside the candidate or wholly outside.
  // Whether any face shows the facet apart does not depend on their order.
  std::optional<Against> judge_near_faces() {
    planes_.clear();
    for (int h : near_faces_) {
      if (tie(h)) {
        if (j_ > i_) return Against::Apart;
        continue;
      }
      if (separates_or_crosses(h)) return Against::Apart;
    }
    std::sort(planes_.begin(), planes_.end());
    if (!planes_.empty()) return std::nullopt;
    const Vector3d& centroid = points_.back();
    if (inside(centroid)) return Against::Inside;
    if (!c_.facet_groups_->for_each_reaching(centroid, 0.0, candidate_.a, candidate_.b, c_.rounding_,
                                             [&](int h) { return value(h, centroid) < c_.rounding_; }))
      return Against::Apart;
    for (int h = first_silhouette_; h < face_count_; ++h)
      if (value(h, centroid) >= c_.rounding_) return Against::Apart;
    return std::nullopt;  // undecided within the rounding
  }

  // A corner of the facet in the candidate by construction, on its boundary: a tool vertex placed
  // at an end the two moves share (mostly a joint: the rounding leaves the facet touching the
  // next sweep along a tool edge there undecided). When both sweeps' planes are exact, the
  // candidate's exact polytope holds the whole tool placed at either of its ends: a tool facet's
  // plane placed at one end holds the tool there, and at the other end by the exact sign of its
  // side; a silhouette plane holds both placements, its normal lying in its edge's normal cone
  // (the edge's facets face opposite ways along the motion). So no face need be looked at. The
  // corner is one of the facet's exact corners; in the stock's box grown by the rounding, it is
  // one of the points' polygon, cut to that box as cut_to_stock() does.
  // Any point of the facet in the closed candidate is a witness as good as one inside it: a face
  // whose plane bounds the facet's part in the candidate passes through a point of that part, so
  // meets the facet, so is among the faces whose boxes meet the facet's (and so under the
  // perturbation, whose limit lies in that part).
  bool corner_in_candidate() const {
    if (!c_.exact_[i_] || !c_.exact_[j_]) return false;
    const AlignedBox3d grown_stock(c_.stock_.min().array() - c_.rounding_,
                                   c_.stock_.max().array() + c_.rounding_);
    const ConvexPolytope& tool = c_.sweeps_.tool();
    const std::vector<SweepPolytopeBuilder::Edge>& edges = c_.sweeps_.edges();
    const std::array<int, 2> edge_ends =
        p_.edge >= 0 ? std::array<int, 2>{edges[p_.edge].from, edges[p_.edge].to} : std::array<int, 2>{};
    const int* first_corner = p_.edge >= 0 ? edge_ends.data() : tool.facets[p_.tool_facet].loop.data();
    const std::size_t corner_count = p_.edge >= 0 ? 2 : tool.facets[p_.tool_facet].loop.size();
    for (const bool at_own_end : {false, true}) {
      if (at_own_end ? p_.placement < 0 : p_.placement > 0) continue;  // no corner placed there
      const Vector3d& end = at_own_end ? own_.b : own_.a;
      if (end != candidate_.a && end != candidate_.b) continue;
      if (!p_.clipped) return true;
      for (std::size_t k = 0; k < corner_count; ++k)
        if (grown_stock.contains(Vector3d(tool.vertices[first_corner[k]] + end))) return true;
    }
    return false;
  }

  // 4. With crossing planes and a point of the facet inside the candidate, the facet's part
  // inside it is its part below the crossing planes (a segment from that point leaves the
  // candidate through a face meeting the facet). Any point proves it, so a corner at an end both
  // moves share goes first (no face looked at; the points' looks fail on most of such facets: a
  // joint's facets touch the next sweep), then the inner bound, cheap, over all points; then
  // every face for the points no crossing face has above it (one that has is inside only by the
  // bound); then the centroid of the facet's part below the crossing planes.
  std::optional<Against> witnessed() {
    if (planes_.empty()) return std::nullopt;
    if (corner_in_candidate()) return cuts();
    if (any_point_inside_sweep(c_.bounds_, candidate_.a, candidate_.b, points_)) return cuts();
    for (std::size_t k = 0; k < points_.size(); ++k) {
      const bool seen_outside = k < 64 && (not_below_ >> k & 1);
      if (!seen_outside && below_faces(points_[k], true)) return cuts();
    }
    const bool swept = p_.tool_facet >= 0 && p_.placement == 0;
    if (!swept) {
      const std::optional<Vector3d> centroid = clipped_centroid(
          ordered_polygon(p_.edge >= 0 && !p_.clipped, points_), [&](int h) { return face_plane(h); },
          planes_);
      // Proven inside by every face of the candidate, the tie's too.
      if (centroid && below_faces(*centroid, false)) return cuts();
    }
    return std::nullopt;
  }

  // 5. Undecided within the rounding: every plane that crosses the facet, in face order as the
  // cutter lists them: the tool facets' came group by group, and are put in order by flags (a
  // sort of these long lists cost a twentieth of the run); the silhouette faces' follow in order.
  Against every_crossing_plane() {
    ++counts_.without_witness;
    planes_.clear();
    const Vector3d& centroid = points_.back();
    double radius = 0.0;
    for (const Vector3d& x : points_) radius = std::max(radius, (x - centroid).norm());
    if (!c_.facet_groups_->for_each_reaching(centroid, radius, candidate_.a, candidate_.b, -c_.rounding_,
                                             [&](int h) { return tie(h) || !separates_or_crosses(h); }))
      return Against::Apart;
    marks_.resize(static_cast<std::size_t>(first_silhouette_), 0);  // all clear between calls
    int lowest = first_silhouette_, highest = -1;
    for (int h : planes_) {
      marks_[static_cast<std::size_t>(h)] = 1;
      lowest = std::min(lowest, h);
      highest = std::max(highest, h);
    }
    std::size_t next = 0;
    for (int h = lowest; h <= highest; ++h)
      if (marks_[static_cast<std::size_t>(h)]) {
        marks_[static_cast<std::size_t>(h)] = 0;
        planes_[next++] = h;
      }
    for (int h = first_silhouette_; h < face_count_; ++h) {
      if (tie(h)) continue;
      if (separates_or_crosses(h)) return Against::Apart;
    }
    return planes_.empty() ? Against::Inside : cuts();
  }

  const SweepCulling& c_;
  const Placed& p_;
  const std::size_t i_;
  const Ends& own_;
  const std::uint32_t j_;
  const std::vector<Vector3d>& points_;  ///< the facet's corners and, last, its centroid
  const Faces& candidate_;
  std::vector<int>& near_faces_;
  std::vector<int>& planes_;  ///< the crossing planes
  std::vector<char>& marks_;
  int& points_below_;
  CullingCounts& counts_;
  const int first_silhouette_, face_count_;
  int tie_face_ = -1;
  int left_ = -1, right_ = -1;   ///< the facet's own tool facets (a silhouette face's two)
  std::uint64_t not_below_ = 0;  ///< the points some face's plane has not below it by the rounding
};

// Facet p of move i against candidate j's faces, by halfspaces. `points`: the facet's corners
// and, last, its centroid. On Cuts, `planes` are the candidate's planes that cut it.
SweepCulling::Against SweepCulling::against(const Placed& p, std::size_t i, const Ends& own, std::uint32_t j,
                                            const std::vector<Vector3d>& points, const Faces& candidate,
                                            std::vector<int>& near_faces, std::vector<int>& planes,
                                            std::vector<char>& marks, int& points_below,
                                            CullingCounts& counts) const {
  return HalfspaceTest(*this, p, i, own, j, points, candidate, near_faces, planes, marks, points_below,
                       counts)
      .run();
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
    if (p.edge >= 0) std::swap(points[1], points[2]), std::swap(points[2], points[3]);  // in loop order
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

}  // namespace morph
