// SPDX-License-Identifier: Apache-2.0
#include <morph/facet_clipping.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>

namespace morph {

std::optional<CornerLook> corner_look(const ExactPlane& s, const ExactPlane& a, const ExactPlane& b) {
  CornerLook c;
  if (const std::optional<Eigen::Vector3d> look = look_vertex_point(s, a, b)) {
    c.point = *look;
  } else {
    const double det = std::fabs(s.normal.dot(a.normal.cross(b.normal)));
    const double scale = s.normal.norm() * a.normal.norm() * b.normal.norm();
    if (det > 1e-7 * scale) {
      c.point = conditioned_vertex_point(s, a, b);
    } else {
      const auto bounded = bounded_vertex_point(s, a, b);
      if (!bounded) return std::nullopt;
      c.point = bounded->point;
      c.error = bounded->error;
    }
  }
  c.length = c.point.norm();
  c.slack = 1e-9 * c.length + c.error;
  return c;
}

RoughCorners::RoughCorners(const ConvexPiece& piece, const RoughCorners* old,
                           const std::vector<int>& from_old) {
  make(piece, old, from_old);
}

void RoughCorners::remake(const ConvexPiece& piece, const RoughCorners& old,
                          const std::vector<int>& from_old) {
  make(piece, &old, from_old);
}

void RoughCorners::make(const ConvexPiece& piece, const RoughCorners* old, const std::vector<int>& from_old) {
  const std::size_t n = piece.edges.size();
  corners_.clear();
  usable_ = true;
  corners_.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (old && old->usable_ && from_old[k] >= 0) {
      corners_.push_back(old->corners_[static_cast<std::size_t>(from_old[k])]);
      continue;
    }
    const std::optional<CornerLook> look =
        corner_look(piece.support, piece.edges[(k + n - 1) % n], piece.edges[k]);
    if (!look) {
      usable_ = false;
      return;
    }
    Corner c;
    static_cast<CornerLook&>(c) = *look;
    corners_.push_back(c);
  }
}

template <class Corners, class Keep>
int RoughCorners::sides(Corners& corners, const ExactPlane& plane, Keep&& keep) {
  std::size_t below = 0, above = 0;
  const double length = plane.normal.norm();
  for (auto& c : corners) {
    const int look = look_side(c, plane, length);
    keep(c, look);
    below += look < 0;
    above += look > 0;
  }
  return below == corners.size() ? -1 : (above == corners.size() ? 1 : 0);
}

int RoughCorners::side(const ExactPlane& plane) {
  if (!usable_) return 0;
  return sides(corners_, plane, [](Corner& c, int look) { c.look = look; });
}

int RoughCorners::peek(const ExactPlane& plane) const {
  if (!usable_) return 0;
  return sides(corners_, plane, [](const Corner&, int) {});
}

bool RoughCorners::outside(const ExactPlane& plane) const {
  if (!usable_) return false;
  const double length = plane.normal.norm();
  for (const Corner& c : corners_)
    if (look_side(c, plane, length) <= 0) return false;
  return true;
}

int RoughCorners::exact_side(const ConvexPiece& piece, std::size_t k, const ExactPlane& plane) const {
  const std::size_t n = piece.edges.size();
  const ExactPlane& a = piece.edges[(k + n - 1) % n];
  const ExactPlane& b = piece.edges[k];
  if (!usable_) return side_at_vertex(piece.support, a, b, plane);
  const Corner& c = corners_[k];  // its look is well within a grid step of the vertex
  return side_at_vertex_near(piece.support, a, b, c.point, c.grid, plane);
}

namespace {

ExactPlane box_plane(int axis, bool upper, double offset, std::uint32_t index) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  n[axis] = upper ? 1.0 : -1.0;
  return ExactPlane{n, upper ? offset : -offset, stock_rank(index), -1};
}

// clip(), with the float look's sides of the corners it is sure of (the exact sides, as
// RoughCorners' margin holds) when `rough` is given: the exact predicates only for the others.
// `from_old`, when given, receives for each corner of the result the index of the same corner
// in `piece`, or -1 for a corner on `plane`.
// The part of `piece` whose corners' exact sides of `plane` are `sides` (of corner k, between
// edges k-1 and k) take as inside (negative): the edges with a corner inside, and `plane` put after
// the edge that leaves. Exact signs on a convex piece change twice. `from_old`, when given,
// receives for each corner of the result the index of the same corner in `piece`, or -1 for a
// corner on `plane`.
// Made in `out` (not `piece`), whose storage is reused.
void part_inside(const ConvexPiece& piece, const ExactPlane& plane, const std::vector<int>& sides, int sign,
                 std::vector<int>* from_old, ConvexPiece& out) {
  const std::size_t n = piece.edges.size();
  std::size_t inside = 0;
  for (int side : sides) inside += sign * side < 0;
  if (inside == n) {
    if (from_old) {
      from_old->resize(n);
      for (std::size_t k = 0; k < n; ++k) (*from_old)[k] = static_cast<int>(k);
    }
    out = piece;
    return;
  }
  out.support = piece.support;
  out.edges.clear();
  if (inside == 0) return;
  out.edges.reserve(n + 1);  // grown one push at a time, this was ~1% of a job in reallocation
  // Of each edge of `out`: its index in `piece`, -1 for `plane` (the thread's, as part_inside()
  // is called for every clip and does not nest).
  thread_local std::vector<int> source;
  source.clear();
  for (std::size_t k = 0; k < n; ++k) {
    const bool from_inside = sign * sides[k] < 0, to_inside = sign * sides[(k + 1) % n] < 0;
    if (from_inside || to_inside) {
      out.edges.push_back(piece.edges[k]);
      source.push_back(static_cast<int>(k));
    }
    if (from_inside && !to_inside) {
      out.edges.push_back(plane);
      source.push_back(-1);
    }
  }
  if (from_old) {
    // Corner j (between edges j-1 and j) is an old corner when both edges are old and were
    // next to each other there.
    const std::size_t m = source.size();
    from_old->resize(m);
    for (std::size_t j = 0; j < m; ++j) {
      const int here = source[j], before = source[(j + m - 1) % m];
      (*from_old)[j] =
          here >= 0 && before >= 0 && before == (here + static_cast<int>(n) - 1) % static_cast<int>(n) ? here
                                                                                                       : -1;
    }
  }
}

ConvexPiece part_inside(const ConvexPiece& piece, const ExactPlane& plane, const std::vector<int>& sides,
                        int sign, std::vector<int>* from_old) {
  ConvexPiece out;
  part_inside(piece, plane, sides, sign, from_old, out);
  return out;
}

// The exact sides of `plane` at the corners of `piece` (the float look's where it is sure, as
// RoughCorners' margin holds, when `rough` is given: the exact predicates only for the others).
// `plane` is neither the piece's support nor one of its edges' (clip_with() decides those).
// In the thread's buffer, valid until its next call (every clip asks, and they do not nest).
const std::vector<int>& corner_sides(const ConvexPiece& piece, const ExactPlane& plane,
                                     const RoughCorners* rough) {
  const std::size_t n = piece.edges.size();
  thread_local std::vector<int> sides;
  sides.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const int quick = rough ? rough->corner(k) : 0;
    sides[k] = quick != 0 ? quick
               : rough    ? rough->exact_side(piece, k, plane)
                       : side_at_vertex(piece.support, piece.edges[(k + n - 1) % n], piece.edges[k], plane);
  }
  return sides;
}

// clip(), with the float look's sides of the corners it is sure of when `rough` is given.
// `from_old`, when given, receives for each corner of the result the index of the same corner
// in `piece`, or -1 for a corner on `plane`.
// Made in `out` (not `piece`), whose storage is reused.
void clip_with(const ConvexPiece& piece, const ExactPlane& plane, const RoughCorners* rough,
               std::vector<int>* from_old, ConvexPiece& out) {
  if (from_old) {  // unchanged, unless changed below
    from_old->resize(piece.edges.size());
    for (std::size_t k = 0; k < piece.edges.size(); ++k) (*from_old)[k] = static_cast<int>(k);
  }
  if (piece.empty() || plane.rank == piece.support.rank) {
    out = piece;
    return;
  }
  for (const ExactPlane& e : piece.edges)
    if (e.rank == plane.rank) {
      if (e.direction == plane.direction) {
        out = piece;
      } else {
        out.support = piece.support;
        out.edges.clear();
      }
      return;
    }
  part_inside(piece, plane, corner_sides(piece, plane, rough), 1, from_old, out);
}

// intersect() by the planes in [first, last), in that order.
template <class Iterator>
ConvexPiece clip_in_order(ConvexPiece piece, RoughCorners rough, Iterator first, Iterator last) {
  // The thread's (clip_in_order() does not nest): from_old, and the storage of each clip's look,
  // swapped with the last one's.
  thread_local std::vector<int> from_old;
  thread_local RoughCorners next;
  thread_local ConvexPiece clipped;  // storage, swapped with the last piece's
  for (; first != last; ++first) {
    const ExactPlane& plane = *first;
    if (piece.empty()) break;
    const int quick = rough.side(plane);
    if (quick < 0) continue;
    if (quick > 0) return ConvexPiece{piece.support, {}};
    clip_with(piece, plane, &rough, &from_old, clipped);
    std::swap(piece, clipped);
    if (!piece.empty()) {
      next.remake(piece, rough, from_old);
      std::swap(rough, next);
    }
  }
  return piece;
}

// clip_in_order() of `whole` with its look, copied only once a plane cuts it: a cutter's planes
// mostly hold the piece inside, or one misses it.
template <class Iterator>
ConvexPiece intersect_in_order(const ConvexPiece& whole, const RoughCorners& whole_look, Iterator first,
                               Iterator last) {
  if (whole.empty()) return whole;
  for (; first != last; ++first) {
    const int quick = whole_look.peek(*first);
    if (quick > 0) return ConvexPiece{whole.support, {}};
    if (quick == 0) break;
  }
  if (first == last) return whole;
  return clip_in_order(whole, whole_look, first, last);
}

}  // namespace

ExactPlane flipped(const ExactPlane& p) {
  return ExactPlane{-p.normal, -p.offset, p.rank, -p.direction, p.exact.set() ? p.exact.negated() : p.exact};
}

std::array<ExactPlane, 6> box_planes(const Eigen::AlignedBox3d& box) {
  std::array<ExactPlane, 6> planes;
  for (int axis = 0; axis < 3; ++axis) {
    planes[2 * axis] = box_plane(axis, false, box.min()[axis], 2 * axis);
    planes[2 * axis + 1] = box_plane(axis, true, box.max()[axis], 2 * axis + 1);
  }
  return planes;
}

ConvexPiece piece_in_box(const ExactPlane& support, const std::array<ExactPlane, 6>& box) {
  // Along the support's dominant axis a, its plane is a graph over the other two (b, c), so the
  // box's b and c planes bound a quadrilateral of it; then the two a planes clip that.
  int a = 0;
  support.normal.cwiseAbs().maxCoeff(&a);
  const int b = (a + 1) % 3, c = (a + 2) % 3;
  ConvexPiece piece{support, {box[2 * c], box[2 * b + 1], box[2 * c + 1], box[2 * b]}};
  // Counter-clockwise seen from +a in the (b, c) plane; from -a the other way round.
  if (support.normal[a] < 0) std::swap(piece.edges[1], piece.edges[3]);
  // With the float look of the corners: the exact predicates decide only those it is not sure of.
  const std::array<ExactPlane, 2> ends{box[2 * a], box[2 * a + 1]};
  RoughCorners rough(piece);
  return clip_in_order(std::move(piece), std::move(rough), ends.begin(), ends.end());
}

ConvexPiece clip(const ConvexPiece& piece, const ExactPlane& plane) {
  ConvexPiece out;
  clip_with(piece, plane, nullptr, nullptr, out);
  return out;
}

ConvexPiece intersect(ConvexPiece piece, const std::vector<ExactPlane>& planes) {
  RoughCorners rough(piece);
  return clip_in_order(std::move(piece), std::move(rough), planes.begin(), planes.end());
}

bool subtract(const ConvexPiece& piece, const std::vector<ExactPlane>& cutter,
              std::vector<ConvexPiece>& out) {
  return subtract(piece, RoughCorners(piece), cutter, out);
}

bool subtract(const ConvexPiece& piece, const RoughCorners& look, const std::vector<ExactPlane>& cutter,
              std::vector<ConvexPiece>& out, std::vector<RoughCorners>* looks) {
  // Facet minus a convex polytope: peel off, plane by plane, the part outside that plane; what
  // is inside every plane is inside the cutter and goes. Only the cutter's planes that bound the
  // part inside it are peeled by, in rank order: the same set as peeling by all of them, and
  // pieces that depend on that part alone, not on which other planes of the cutter are listed
  // or in what order (the culled carving lists only the planes crossing a facet).
  // A piece the cutter does not reach stays whole: splitting it along planes that cross it
  // outside the cutter would only make fragments (and, for a retraced move's planes, which
  // coincide with the first pass's, vertices that round to the same point).
  // The part inside is the same set whatever the order; clipped in decreasing rank (a cutter's
  // planes come in rank order) the tightest perturbations come first, so planes through one
  // vertex (a tool vertex where many facets meet) do not pile up tiny edges there, each costing
  // an exact tie at every later plane through it. Only its edges are read below.
  const ConvexPiece inside = intersect_in_order(piece, look, cutter.rbegin(), cutter.rend());
  if (inside.empty()) {
    out.push_back(piece);
    return false;
  }
  thread_local std::vector<ExactPlane> bounding;  // subtract() does not nest
  bounding.clear();
  for (const ExactPlane& e : inside.edges) {
    const bool own = std::any_of(piece.edges.begin(), piece.edges.end(),
                                 [&](const ExactPlane& p) { return p.rank == e.rank; });
    if (!own) bounding.push_back(e);
  }
  std::sort(bounding.begin(), bounding.end(),
            [](const ExactPlane& x, const ExactPlane& y) { return x.rank < y.rank; });
  // The float look decides the corners it is sure of for both sides of each plane (the flipped
  // plane's sides are exactly the opposite).
  const ConvexPiece* rest = &piece;            // then each inner part, held in `inner_part`
  thread_local ConvexPiece inner_part, inner;  // the thread's storage (subtract() does not nest)
  thread_local RoughCorners rough, next;       // storage, swapped with the last look's
  rough = look;
  thread_local std::vector<int> from_old, from_old_outside;
  for (const ExactPlane& plane : bounding) {
    rough.side(plane);
    // A bounding plane is none of the piece's (its rank is another move's, and those already
    // peeled are not listed twice), and the flipped plane's exact sides are exactly the opposite:
    // one look at the corners for both parts.
    const std::vector<int>& sides = corner_sides(*rest, plane, &rough);
    part_inside(*rest, plane, sides, 1, &from_old, inner);
    ConvexPiece outside = part_inside(*rest, flipped(plane), sides, -1, looks ? &from_old_outside : nullptr);
    if (!outside.empty()) {
      if (looks) looks->emplace_back(outside, &rough, from_old_outside);
      out.push_back(std::move(outside));
    }
    if (inner.empty()) break;
    next.remake(inner, rough, from_old);
    std::swap(rough, next);
    std::swap(inner_part, inner);
    rest = &inner_part;
  }
  return true;
}

ConvexPiece canonical(ConvexPiece piece) {
  if (piece.empty()) return piece;
  const auto lowest =
      std::min_element(piece.edges.begin(), piece.edges.end(),
                       [](const ExactPlane& x, const ExactPlane& y) { return x.rank < y.rank; });
  std::rotate(piece.edges.begin(), lowest, piece.edges.end());
  return piece;
}

std::vector<Eigen::Vector3d> corners(const ConvexPiece& piece) {
  std::vector<Eigen::Vector3d> points;
  const std::size_t n = piece.edges.size();
  for (std::size_t k = 0; k < n; ++k)
    points.push_back(vertex_point(piece.support, piece.edges[(k + n - 1) % n], piece.edges[k]));
  return points;
}

Eigen::AlignedBox3d grown_for_rounding(Eigen::AlignedBox3d box) {
  box.min().array() -= 1e-7 * (1 + box.min().cwiseAbs().maxCoeff());
  box.max().array() += 1e-7 * (1 + box.max().cwiseAbs().maxCoeff());
  return box;
}

Eigen::AlignedBox3d reach_of(const ConvexPiece& piece) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& x : corners(piece)) box.extend(x);
  return grown_for_rounding(box);
}

Eigen::Vector3d area_vector(const ConvexPiece& piece) {
  const std::vector<Eigen::Vector3d> p = corners(piece);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k + 2 < p.size(); ++k) sum += (p[k + 1] - p[0]).cross(p[k + 2] - p[0]);
  return sum / 2;
}

}  // namespace morph
