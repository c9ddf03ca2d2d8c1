// SPDX-License-Identifier: Apache-2.0
#include "generator/own_facet.h"

#include <morph/joint_culling.h>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace morph {
namespace {

using Eigen::Vector3d;

// Calls f(k), in increasing k, for every own plane that may have a value of at least
// `threshold` somewhere in one of the balls: the others certainly do not. `marks`: one flag per
// tool facet, all clear before and after (sorting the reached ones would cost more).
template <class F>
void for_each_plane_reaching(const OwnPlanes& own, const std::vector<Ball>& balls, double threshold,
                             std::vector<char>& marks, F&& f) {
  marks.resize(own.tool_facets, 0);
  int lowest = static_cast<int>(own.tool_facets), highest = -1;
  // Each end by itself: a group's bound taken at both ends holds for its members placed at
  // either, and a front facet's plane placed at a would reach far beyond the tool at b.
  for (const bool at_b : {false, true}) {
    if (at_b && own.a == own.b) break;
    const Vector3d& at = at_b ? own.b : own.a;
    const char end = at_b ? 2 : 1;
    for (const auto& [centre, radius] : balls)
      own.groups->for_each_reaching(
          centre, radius, at, at, threshold, [&](std::size_t g) { return (own.group_ends[g] & end) != 0; },
          [&](int k) {
            if ((own.made.sides()[static_cast<std::size_t>(k)] > 0) != at_b) return true;
            marks[k] = 1;
            lowest = std::min(lowest, k);
            highest = std::max(highest, k);
            return true;
          });
  }
  for (int k = lowest; k <= highest; ++k)
    if (marks[k]) {
      marks[k] = 0;
      f(static_cast<std::size_t>(k));
    }
  for (std::size_t k = own.tool_facets; k < own.plane_count(); ++k) f(k);
}

// The smallest ball about the points' mean holding them.
Ball ball_of(const std::vector<Vector3d>& points) {
  Vector3d centre = Vector3d::Zero();
  for (const Vector3d& x : points) centre += x;
  centre /= static_cast<double>(points.size());
  double radius = 0.0;
  for (const Vector3d& x : points) radius = std::max(radius, (x - centre).norm());
  return {centre, radius};
}

// Balls that together hold `points`, each grown by `margin`. A plane's value is linear, so a
// plane below a threshold in every ball is below it on the points' convex hull: any cover will
// do. A sweep facet's points lie at one end of the move or at both, and one ball about a long
// move's two ends reaches almost every plane of the sweep; so the points are split at the middle
// of the move when that gives balls much smaller than the one about them all.
std::vector<Ball> covering_balls(const std::vector<Vector3d>& points, const OwnPlanes& own, double margin) {
  Ball all = ball_of(points);
  all.second += margin;
  const Vector3d motion = own.b - own.a;
  if (motion.squaredNorm() == 0.0) return {all};
  const double middle = motion.dot(own.a + own.b) / 2;
  std::vector<Vector3d> first, second;
  for (const Vector3d& x : points) (motion.dot(x) <= middle ? first : second).push_back(x);
  if (first.empty() || second.empty()) return {all};
  Ball one = ball_of(first), two = ball_of(second);
  one.second += margin;
  two.second += margin;
  if (std::max(one.second, two.second) > 0.5 * all.second) return {all};
  return {one, two};
}

// The exact corners of `piece` lie within `margin` of these rounded ones. When every corner is
// well conditioned (the float look's condition in facet_clipping.cpp), a rounded corner is within
// about 1e-11·(|offset| + |corner|) of the exact one, and the margin is a hundred times that;
// otherwise it is the largest of the corners' forward error bounds (bounded_vertex_point()),
// which hold however close to parallel the planes are. None when such a bound fails.
std::optional<std::pair<std::vector<Vector3d>, double>> rounded_corners(const ConvexPiece& piece) {
  const std::size_t n = piece.edges.size();
  std::vector<Vector3d> points;
  double largest = 0.0, max_offset = std::fabs(piece.support.offset);
  for (const ExactPlane& e : piece.edges) max_offset = std::max(max_offset, std::fabs(e.offset));
  bool conditioned = true;
  for (std::size_t k = 0; k < n; ++k) {
    const ExactPlane& a = piece.edges[(k + n - 1) % n];
    const ExactPlane& b = piece.edges[k];
    if (const std::optional<Vector3d> look = look_vertex_point(piece.support, a, b)) {
      points.push_back(*look);
      largest = std::max(largest, points.back().norm());
      continue;
    }
    const double det = std::fabs(piece.support.normal.dot(a.normal.cross(b.normal)));
    const double scale = piece.support.normal.norm() * a.normal.norm() * b.normal.norm();
    conditioned = det > 1e-7 * scale;
    if (!conditioned) break;
    points.push_back(conditioned_vertex_point(piece.support, a, b));
    largest = std::max(largest, points.back().norm());
  }
  if (conditioned) return std::pair{std::move(points), 1e-9 * (1.0 + max_offset + largest)};
  points.clear();
  double margin = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const auto corner = bounded_vertex_point(piece.support, piece.edges[(k + n - 1) % n], piece.edges[k]);
    if (!corner) return std::nullopt;
    points.push_back(corner->point);
    margin = std::max(margin, corner->error);
  }
  return std::pair{std::move(points), margin};
}

}  // namespace

ToolIncidence tool_incidence(const SweepPolytopeBuilder& builder) {
  const ConvexPolytope& tool = builder.tool();
  ToolIncidence incidence;
  incidence.facets_at_vertex = facets_at_vertices(tool);
  incidence.edges_at_vertex.resize(tool.vertices.size());
  const std::vector<SweepPolytopeBuilder::Edge>& edges = builder.edges();
  for (std::size_t e = 0; e < edges.size(); ++e)
    for (int v : {edges[e].from, edges[e].to}) incidence.edges_at_vertex[v].push_back(static_cast<int>(e));
  return incidence;
}

OwnPlanes own_planes(const SweepPolytopeBuilder& builder, const ToolFacetGroups& groups,
                     const std::vector<std::vector<int>>& members, const ToolIncidence& incidence,
                     const Vector3d& from, const Vector3d& to, std::uint32_t move) {
  OwnPlanes own(SweepPolytopeBuilder::Planes(builder, from, to));
  own.move = move;
  own.planes.resize(own.made.size());
  own.lengths.resize(own.made.size());
  own.have.assign(own.made.size(), 0);
  own.builder = &builder;
  own.incidence = &incidence;
  own.groups = &groups;
  std::tie(own.a, own.b) =
      builder.degenerate(from, to) ? std::pair{from, from} : SweepPolytopeBuilder::ordered(from, to);
  own.tool_facets = builder.tool().facets.size();
  own.silhouette_plane.assign(builder.edges().size(), -1);
  const std::vector<int>& silhouette = own.made.silhouette();
  for (std::size_t i = 0; i < silhouette.size(); ++i)
    own.silhouette_plane[static_cast<std::size_t>(silhouette[i])] = static_cast<int>(own.tool_facets + i);
  own.exact = builder.exact(from, to);
  if (own.exact) return own;  // the groups serve own_facet()'s second loop alone
  own.group_ends.assign(groups.size(), 0);
  for (std::size_t i = 0; i < groups.size(); ++i)
    for (int k : members[i]) own.group_ends[i] |= own.made.sides()[static_cast<std::size_t>(k)] > 0 ? 2 : 1;
  return own;
}

const ExactPlane& OwnPlanes::plane(std::size_t k) {
  if (!have[k]) {
    planes[k] = sweep_plane(made[k], move, static_cast<std::uint32_t>(k));
    lengths[k] = planes[k].normal.norm();
    have[k] = 1;
  }
  return planes[k];
}

double OwnPlanes::length(std::size_t k) {
  plane(k);
  return lengths[k];
}

// The points of sweep facet `f` as the builder places it (tool vertices at the ordered ends),
// for choosing which of the sweep's planes can bound it; the exact facet is decided by all.
std::vector<Vector3d> facet_points(const SweepPolytopeBuilder& builder, const OwnPlanes& own, int f) {
  const ConvexPolytope& tool = builder.tool();
  std::vector<Vector3d> points;
  const auto nf = static_cast<int>(tool.facets.size());
  if (f < nf) {
    const int at = own.made.sides()[static_cast<std::size_t>(f)];
    for (int v : tool.facets[f].loop) {
      if (at <= 0) points.push_back(tool.vertices[v] + own.a);
      if (at >= 0) points.push_back(tool.vertices[v] + own.b);
    }
    return points;
  }
  const SweepPolytopeBuilder::Edge& e =
      builder.edges()[own.made.silhouette()[static_cast<std::size_t>(f - nf)]];
  for (int v : {e.from, e.to}) {
    points.push_back(tool.vertices[v] + own.a);
    points.push_back(tool.vertices[v] + own.b);
  }
  return points;
}

// True when `plane`'s value is below -threshold everywhere in every ball, with room for the
// rounding of this test and of any point's value in them (a millionth of the thresholds used).
// `length`: the plane's normal's. (The rounding term takes the centre's 1-norm, above its length.)
bool below_in_balls(const ExactPlane& plane, double length, const std::vector<Ball>& balls,
                    double threshold) {
  for (const auto& [centre, radius] : balls) {
    const double top = plane.normal.dot(centre) - plane.offset + length * radius;
    const double rounding =
        1e-15 * (1 + std::fabs(plane.offset) + length * (centre.cwiseAbs().sum() + radius));
    if (!(top + rounding < -threshold)) return false;
  }
  return true;
}

// A ball holding the exact corners of `piece` (rounded_corners() grown by their margin); none
// when the corners cannot be bounded.
std::optional<Ball> corner_ball(const ConvexPiece& piece) {
  const auto rounded = rounded_corners(piece);
  if (!rounded) return std::nullopt;
  Ball ball = ball_of(rounded->first);
  ball.second += rounded->second;
  return ball;
}

// Facet f of a sweep within the stock and its own polytope: first by the planes through the
// facet's vertices that pass near its points (which makes the piece small; found from what meets
// at its tool vertices, not searched for), then, unless every plane of the sweep is exact, by
// every other plane that may reach the piece's corners (the float look of intersect() skips the
// planes clearly apart, so this adds little and decides exactly). The piece is the same set of
// planes whichever loop a plane is clipped in.
// Exact planes need no second loop. Each is a supporting plane of the exact sweep P (the
// Minkowski sum of the tool and [a, b]) and meets it in a face, so a plane H holding no vertex of
// facet F holds F strictly inside, which no perturbation changes. And H holds a vertex v + e of F
// (v a tool vertex, e = a or b) only through v: a tool facet g placed at its end holds it only
// when v is on g (g placed at b has n·(b - a) > 0 and so n·(v + a) above its offset; g swept has
// both), and a silhouette plane, whose normal lies strictly inside its edge's normal cone, meets
// the tool in that edge alone. Those are the incident planes of the first loop. (Measured before
// the loop was skipped: it changed no facet of bear.nc, the four CAMotics projects or 310 stress
// cases.)
// Planes that cannot reach the piece's corners' balls are left out of the second loop: they hold
// every corner strictly inside, so clipping by them would give the piece unchanged. Nor does the
// second loop clip by a near plane again: the
// piece lies inside it, so its corners are strictly inside or on it as an edge (clip() would
// return the piece unchanged).
ConvexPiece own_facet(OwnPlanes& own, int f, const std::vector<Vector3d>& points, const StockPolytope& stock,
                      OwnFacetScratch& scratch) {
  std::vector<double>& lengths = scratch.lengths;
  lengths.clear();
  for (const Vector3d& x : points) lengths.push_back(x.norm());
  const double largest = *std::max_element(lengths.begin(), lengths.end());
  std::vector<ExactPlane>& near = scratch.near;
  near.clear();
  scratch.applied_index.clear();
  std::vector<char>& applied = scratch.applied;  // all clear between calls
  applied.resize(own.plane_count(), 0);
  const std::vector<Ball> point_balls = covering_balls(points, own, 0.0);
  // The planes through the facet's vertices: the tool facets and silhouette edges at its tool
  // vertices. They bound it (and where more than three meet at a vertex, the order of terms
  // decides which); any other plane near its points is found by the second loop below, which
  // tests every plane that may reach the piece's corners.
  std::vector<std::size_t>& incident = scratch.incident;
  incident.clear();
  const ConvexPolytope& tool = own.builder->tool();
  const auto nf = static_cast<int>(own.tool_facets);
  auto add_vertex = [&](int v) {
    for (int g : own.incidence->facets_at_vertex[static_cast<std::size_t>(v)])
      incident.push_back(static_cast<std::size_t>(g));
    for (int e : own.incidence->edges_at_vertex[static_cast<std::size_t>(v)])
      if (own.silhouette_plane[static_cast<std::size_t>(e)] >= 0)
        incident.push_back(static_cast<std::size_t>(own.silhouette_plane[static_cast<std::size_t>(e)]));
  };
  if (f < nf) {
    for (int v : tool.facets[static_cast<std::size_t>(f)].loop) add_vertex(v);
  } else {
    const SweepPolytopeBuilder::Edge& e =
        own.builder
            ->edges()[static_cast<std::size_t>(own.made.silhouette()[static_cast<std::size_t>(f - nf)])];
    add_vertex(e.from);
    add_vertex(e.to);
  }
  std::sort(incident.begin(), incident.end());
  incident.erase(std::unique(incident.begin(), incident.end()), incident.end());
  for (const std::size_t k : incident) {
    if (static_cast<int>(k) == f) continue;
    const ExactPlane& h = own.plane(k);
    const double margin = 1e-9 * (1 + std::fabs(h.offset));
    // Below the smallest threshold in the balls is below each point's (a group's bound is loose).
    if (below_in_balls(h, own.length(k), point_balls, margin * (1 + largest))) continue;
    for (std::size_t i = 0; i < points.size(); ++i)
      if (h.normal.dot(points[i]) - h.offset > -margin * (1 + lengths[i])) {
        near.push_back(h);
        applied[k] = 1;
        scratch.applied_index.push_back(k);
        break;
      }
  }
  // In decreasing rank (the same piece in any order): the tightest perturbations first, so the
  // planes through a tool vertex where many facets meet (a fan about the ball's pole) do not pile
  // up tiny edges there, each costing an exact tie at every later plane through it.
  std::reverse(near.begin(), near.end());
  // A polytope stock that is not a box (a cylinder's prism of hundreds of sides) cuts the facet's
  // plane in a polygon of as many corners, which every clip by the facet's own planes would visit:
  // those planes first, then the stock's, which mostly find the few corners left inside. The same
  // set in another order (a box's six planes go first, as before).
  const ExactPlane& support = own.plane(static_cast<std::size_t>(f));
  ConvexPiece piece = stock.box || stock.mesh
                          ? intersect(piece_in_stock(support, stock), near)
                          : intersect(intersect(piece_in_bounds(support, stock.bounds), near), stock.planes);
  if (own.exact) {
    for (std::size_t k : scratch.applied_index) applied[k] = 0;
    return piece;
  }
  std::vector<ExactPlane>& reaching = scratch.reaching;
  reaching.clear();
  if (!piece.empty()) {
    const auto rounded = rounded_corners(piece);
    if (!rounded) {
      for (std::size_t k = 0; k < own.plane_count(); ++k)
        if (!applied[k]) reaching.push_back(own.plane(k));
    } else {
      // A plane below zero in the balls holds the exact corners strictly inside: clipping by it
      // would give the piece unchanged (the margin covers its rounded look, as RoughCorners').
      const std::vector<Ball> balls = covering_balls(rounded->first, own, rounded->second);
      for_each_plane_reaching(own, balls, 0.0, scratch.marks, [&](std::size_t k) {
        if (applied[k]) return;
        const ExactPlane& h = own.plane(k);
        if (!below_in_balls(h, own.length(k), balls, 1e-9 * (1 + std::fabs(h.offset)))) reaching.push_back(h);
      });
    }
  }
  for (std::size_t k : scratch.applied_index) applied[k] = 0;
  if (piece.empty()) return piece;
  return intersect(std::move(piece), reaching);
}

}  // namespace morph
