// SPDX-License-Identifier: Apache-2.0
// Exact self-intersection test of a triangle mesh: a bounding-volume hierarchy finds the pairs
// whose boxes overlap, and each pair is decided by CGAL's filtered exact predicates. Pairs lying in
// one axis-aligned plane (a stock face and its cuts: the common case, and one where every 3D
// orientation is exactly zero) are decided in that plane's 2D coordinates, which is exact too.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <morph/aabb_tree.h>
#include <morphmill/self_intersections.h>
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <initializer_list>
#include <stdexcept>
#include <string>

namespace morphmill {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Segment = Kernel::Segment_3;
using TriangleShape = Kernel::Triangle_3;
using Point2 = Kernel::Point_2;

// The axis along which all the points have the very same coordinate, or -1.
int common_axis(std::initializer_list<const Eigen::Vector3d*> points) {
  for (int axis = 0; axis < 3; ++axis) {
    const double value = (*points.begin())->coeff(axis);
    if (std::all_of(points.begin(), points.end(),
                    [&](const Eigen::Vector3d* p) { return p->coeff(axis) == value; }))
      return axis;
  }
  return -1;
}

Point point3(const Eigen::Vector3d& p) {
  return Point(p.x(), p.y(), p.z());
}
// The coordinates other than `axis`, in cyclic order so that orientation is kept.
Point2 point2(const Eigen::Vector3d& p, int axis) {
  return Point2(p.coeff((axis + 1) % 3), p.coeff((axis + 2) % 3));
}

// Closed convex polygons in the plane (a triangle, or a segment as two points) are disjoint
// exactly when a line through an edge of one has the other strictly on its far side. Only
// orientation predicates are used: exact, and fast through CGAL's static filters.
bool beyond_edge(const Point2& a, const Point2& b, const Point2& inner,
                 std::initializer_list<Point2> others) {
  const CGAL::Orientation inside = CGAL::orientation(a, b, inner);
  return std::all_of(others.begin(), others.end(),
                     [&](const Point2& o) { return CGAL::orientation(a, b, o) == -inside; });
}

bool apart(const Point2& p, const Point2& q, const Point2& r, std::initializer_list<Point2> polygon) {
  return beyond_edge(p, q, r, polygon) || beyond_edge(q, r, p, polygon) || beyond_edge(r, p, q, polygon);
}

// Proper triangles.
bool meet(const Point2& p, const Point2& q, const Point2& r, const Point2& a, const Point2& b,
          const Point2& c) {
  return !apart(p, q, r, {a, b, c}) && !apart(a, b, c, {p, q, r});
}

// Whether two proper triangles sharing the corner v, the first's other corners p, q and the
// second's c, d (in either order), meet anywhere but at v. Near v each is its cone (the rays
// toward its other corners, less than a half turn apart), so they meet beyond v exactly when the
// cones do: when no line through v along one of the four rays has the cones on its two sides, or
// when they share a ray. Two convex cones with a common apex whose interiors are disjoint are
// always split by the line along one of their rays; a line that splits them meets them only in
// its rays, so they share more than v only where one ray of each points the same way along it.
bool cones_meet(const Point2& v, Point2 p, Point2 q, Point2 c, Point2 d) {
  if (CGAL::orientation(v, p, q) == CGAL::NEGATIVE) std::swap(p, q);  // both turning left
  if (CGAL::orientation(v, c, d) == CGAL::NEGATIVE) std::swap(c, d);
  // x and y on one line through v: whether on the same side of v (exact: the signs of
  // coordinate differences are).
  auto same_way = [&](const Point2& x, const Point2& y) {
    for (int k = 0; k < 2; ++k) {
      const int sx = CGAL::sign(x[k] - v[k]), sy = CGAL::sign(y[k] - v[k]);
      if (sx != 0 || sy != 0) return sx == sy;
    }
    return false;
  };
  // The cone [from, to] on the left of the line v-from (left: from is its first ray) or on the
  // right of v-to, the other cone's rays `x`, `y` on the far closed side: split, unless a ray lies
  // on the line pointing the way of the cone's own.
  auto split_by = [&](const Point2& ray, CGAL::Orientation far, const Point2& x, const Point2& y) {
    const CGAL::Orientation ox = CGAL::orientation(v, ray, x), oy = CGAL::orientation(v, ray, y);
    if ((ox != far && ox != CGAL::COLLINEAR) || (oy != far && oy != CGAL::COLLINEAR)) return false;
    return !(ox == CGAL::COLLINEAR && same_way(ray, x)) && !(oy == CGAL::COLLINEAR && same_way(ray, y));
  };
  return !(split_by(p, CGAL::RIGHT_TURN, c, d) || split_by(q, CGAL::LEFT_TURN, c, d) ||
           split_by(c, CGAL::RIGHT_TURN, p, q) || split_by(d, CGAL::LEFT_TURN, p, q));
}

// Whether triangles s and t (distinct, each with three distinct indices and not collinear) meet
// anywhere other than in the vertices and edge they share by index.
bool triangles_intersect(const morph::TriangleMesh& mesh, const morph::Triangle& s,
                         const morph::Triangle& t) {
  int shared = 0, s_at = -1, t_at = -1;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (s[i] == t[j]) {
        ++shared;
        s_at = i;
        t_at = j;
      }
  if (shared == 3) return true;  // the same three vertices: coincident faces
  const auto& v = mesh.vertices;
  const Eigen::Vector3d *s0 = &v[s[0]], *s1 = &v[s[1]], *s2 = &v[s[2]];
  const Eigen::Vector3d *t0 = &v[t[0]], *t1 = &v[t[1]], *t2 = &v[t[2]];
  if (shared == 2) {
    // Along a common edge u-w, two triangles meet elsewhere only when folded flat: coplanar, with
    // their third vertices on the same side of the edge.
    int s_other = 0, t_other = 0;
    while (s_other < 3 && std::find(t.begin(), t.end(), s[s_other]) != t.end()) ++s_other;
    while (t_other < 3 && std::find(s.begin(), s.end(), t[t_other]) != s.end()) ++t_other;
    const Eigen::Vector3d& u = v[s[(s_other + 1) % 3]];
    const Eigen::Vector3d& w = v[s[(s_other + 2) % 3]];
    const Eigen::Vector3d& p = v[s[s_other]];
    const Eigen::Vector3d& q = v[t[t_other]];
    // Seen along the axis where s's normal is largest, s is not flat, so when the triangles are
    // coplanar that view keeps each side of the edge; third vertices strictly on opposite sides
    // there cannot be folded (and non-coplanar triangles never meet beyond their edge). Exact 2D
    // orientations decide it, sparing the exact 3D test where a surface is flat.
    const Eigen::Vector3d normal = (w - u).cross(p - u);
    int axis = common_axis({&u, &w, &p, &q});
    if (axis < 0) normal.cwiseAbs().maxCoeff(&axis);
    const CGAL::Orientation p_side = CGAL::orientation(point2(u, axis), point2(w, axis), point2(p, axis));
    const CGAL::Orientation q_side = CGAL::orientation(point2(u, axis), point2(w, axis), point2(q, axis));
    if (p_side != CGAL::COLLINEAR && q_side == -p_side) return false;
    if (common_axis({&u, &w, &p, &q}) >= 0) return p_side == q_side;
    return CGAL::coplanar(point3(u), point3(w), point3(p), point3(q)) &&
           CGAL::coplanar_orientation(point3(u), point3(w), point3(p), point3(q)) == CGAL::POSITIVE;
  }
  // Decided in 2D along one axis: exactly when all six points lie in a plane normal to it;
  // otherwise only "apart" counts (disjoint shadows mean disjoint triangles), seen along the axis
  // where s's normal is largest, which keeps near-coplanar neighbours apart in the view.
  int axis = common_axis({s0, s1, s2, t0, t1, t2});
  const bool flat = axis >= 0;
  if (!flat) ((*s1 - *s0).cross(*s2 - *s0)).cwiseAbs().maxCoeff(&axis);
  const Point2 sp[3] = {point2(*s0, axis), point2(*s1, axis), point2(*s2, axis)};
  const Point2 tp[3] = {point2(*t0, axis), point2(*t1, axis), point2(*t2, axis)};
  // A shadow may be degenerate (a triangle seen edge-on): the 2D tests need proper triangles.
  if (CGAL::orientation(sp[0], sp[1], sp[2]) != CGAL::COLLINEAR &&
      CGAL::orientation(tp[0], tp[1], tp[2]) != CGAL::COLLINEAR) {
    bool shadows_meet;
    if (shared == 1) {
      // Near the common vertex each is its cone there (cones_meet()).
      shadows_meet = cones_meet(sp[s_at], sp[(s_at + 1) % 3], sp[(s_at + 2) % 3], tp[(t_at + 1) % 3],
                                tp[(t_at + 2) % 3]);
    } else {
      shadows_meet = meet(sp[0], sp[1], sp[2], tp[0], tp[1], tp[2]);
    }
    if (flat || !shadows_meet) return shadows_meet;
  }
  const TriangleShape s_shape(point3(*s0), point3(*s1), point3(*s2));
  const TriangleShape t_shape(point3(*t0), point3(*t1), point3(*t2));
  if (shared == 1) {
    const Segment s_opposite(point3(v[s[(s_at + 1) % 3]]), point3(v[s[(s_at + 2) % 3]]));
    const Segment t_opposite(point3(v[t[(t_at + 1) % 3]]), point3(v[t[(t_at + 2) % 3]]));
    return CGAL::do_intersect(s_shape, t_opposite) || CGAL::do_intersect(t_shape, s_opposite);
  }
  return CGAL::do_intersect(s_shape, t_shape);
}

bool proper(const morph::TriangleMesh& mesh, const morph::Triangle& t) {
  if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) return false;
  const auto& v = mesh.vertices;
  return !CGAL::collinear(point3(v[t[0]]), point3(v[t[1]]), point3(v[t[2]]));
}

}  // namespace

SelfIntersections find_self_intersections(const morph::TriangleMesh& mesh, std::size_t keep, bool threaded) {
  const std::size_t vertex_count = mesh.vertices.size();
  const std::size_t triangle_count = mesh.triangles.size();
  for (std::size_t i = 0; i < triangle_count; ++i)
    for (std::uint32_t v : mesh.triangles[i])
      if (v >= vertex_count)
        throw std::invalid_argument("self-intersection test: triangle " + std::to_string(i) +
                                    " refers to vertex " + std::to_string(v) + " but there are " +
                                    std::to_string(vertex_count) + " vertices");
  // Improper triangles keep a point box for the tree but take part in no pair.
  std::vector<char> tested(triangle_count);
  std::vector<Eigen::AlignedBox3d> boxes(triangle_count);
  auto prepare = [&](const tbb::blocked_range<std::size_t>& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) {
      const morph::Triangle& t = mesh.triangles[i];
      tested[i] = proper(mesh, t);
      boxes[i] = Eigen::AlignedBox3d(mesh.vertices[t[0]]);
      if (tested[i]) boxes[i].extend(mesh.vertices[t[1]]).extend(mesh.vertices[t[2]]);
    }
  };
  const tbb::blocked_range<std::size_t> all(0, triangle_count);
  if (threaded)
    tbb::parallel_for(all, prepare);
  else
    prepare(all);
  const morph::AabbTree tree(boxes);

  using Pairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;
  tbb::enumerable_thread_specific<Pairs> found;
  // The tree against itself, in parts walked in parallel: each pair of overlapping boxes once.
  const std::vector<morph::AabbTree::PairWalk> walks = tree.pair_walks(threaded ? 1024 : 1);
  auto search = [&](const tbb::blocked_range<std::size_t>& range) {
    Pairs& mine = found.local();
    for (std::size_t w = range.begin(); w != range.end(); ++w)
      tree.for_each_overlapping_pair(walks[w], [&](std::uint32_t a, std::uint32_t b) {
        if (tested[a] && tested[b] && triangles_intersect(mesh, mesh.triangles[a], mesh.triangles[b]))
          mine.emplace_back(a, b);
      });
  };
  const tbb::blocked_range<std::size_t> all_walks(0, walks.size());
  if (threaded)
    tbb::parallel_for(all_walks, search);
  else
    search(all_walks);

  Pairs pairs;
  for (const Pairs& part : found) pairs.insert(pairs.end(), part.begin(), part.end());
  SelfIntersections result;
  result.pairs = pairs.size();
  const std::size_t kept = std::min(pairs.size(), keep);
  std::partial_sort(pairs.begin(), pairs.begin() + static_cast<std::ptrdiff_t>(kept), pairs.end());
  pairs.resize(kept);
  result.first_pairs = std::move(pairs);
  return result;
}

}  // namespace morphmill
