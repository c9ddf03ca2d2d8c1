// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/sweep_polytope.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <unordered_map>

namespace morph {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

// A facet is parallel to the motion when |n·v| is within rounding of zero (n unit).
constexpr double kParallel = 1e-12;

std::uint64_t edge_key(int from, int to) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(from)) << 32) |
         static_cast<std::uint32_t>(to);
}

double cross(const Vector2d& o, const Vector2d& a, const Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Vertex ids of the convex hull (counter-clockwise about `normal`, collinear points dropped) of
// the facet's loop at the start (ids as in the tool) and at the end (ids + tool_size).
std::vector<int> swept_face(const ConvexPolytope& tool, const PolytopeFacet& facet, const Vector3d& motion) {
  const Vector3d& n = facet.normal;
  const Vector3d e1 = n.unitOrthogonal(), e2 = n.cross(e1);
  const int tool_size = static_cast<int>(tool.vertices.size());
  struct Point {
    Vector2d p;
    int id;
  };
  std::vector<Point> points;
  for (int v : facet.loop) {
    const Vector3d& x = tool.vertices[v];
    points.push_back({{x.dot(e1), x.dot(e2)}, v});
    points.push_back({{(x + motion).dot(e1), (x + motion).dot(e2)}, v + tool_size});
  }
  std::sort(points.begin(), points.end(), [](const Point& a, const Point& b) {
    return a.p.x() < b.p.x() || (a.p.x() == b.p.x() && a.p.y() < b.p.y());
  });
  double extent = 0.0;
  for (const Point& q : points) extent = std::max(extent, q.p.cwiseAbs().maxCoeff());
  const double flat = 1e-13 * extent * extent;
  // Andrew's monotone chain.
  std::vector<Point> hull(2 * points.size());
  std::size_t k = 0;
  for (const Point& q : points) {
    while (k >= 2 && cross(hull[k - 2].p, hull[k - 1].p, q.p) <= flat) --k;
    hull[k++] = q;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2].p, hull[k - 1].p, points[i].p) <= flat) --k;
    hull[k++] = points[i];
  }
  std::vector<int> loop;
  for (std::size_t i = 0; i + 1 < k; ++i) loop.push_back(hull[i].id);
  return loop;
}

}  // namespace

int motion_side(const Vector3d& normal, const Vector3d& motion) {
  const double s = normal.dot(motion), length = motion.norm();
  return s > kParallel * length ? 1 : s < -kParallel * length ? -1 : 0;
}

void motion_sides(const ConvexPolytope& tool, const Vector3d& motion, std::vector<signed char>& sides) {
  const double length = motion.norm();
  sides.resize(tool.facets.size());
  for (std::size_t f = 0; f < sides.size(); ++f) {
    const double s = tool.facets[f].normal.dot(motion);
    sides[f] = static_cast<signed char>(s > kParallel * length ? 1 : s < -kParallel * length ? -1 : 0);
  }
}

SweepPolytopeBuilder::SweepPolytopeBuilder(ConvexPolytope tool) : tool_(std::move(tool)) {
  if (tool_.facets.empty()) throw InputError("sweep polytope: the tool polytope is empty");
  std::unordered_map<std::uint64_t, int> owner;
  for (int f = 0; f < static_cast<int>(tool_.facets.size()); ++f) {
    const std::vector<int>& loop = tool_.facets[f].loop;
    for (std::size_t i = 0; i < loop.size(); ++i) owner[edge_key(loop[i], loop[(i + 1) % loop.size()])] = f;
  }
  for (const auto& [key, left] : owner) {
    const int from = static_cast<int>(key >> 32), to = static_cast<int>(key & 0xffffffffu);
    if (from > to) continue;
    const auto right = owner.find(edge_key(to, from));
    if (right == owner.end()) throw InputError("sweep polytope: the tool polytope is not closed");
    edges_.push_back({from, to, left, right->second});
  }
  std::sort(edges_.begin(), edges_.end(), [](const Edge& a, const Edge& b) {
    return a.from < b.from || (a.from == b.from && a.to < b.to);
  });
  size_ = tool_.bounds().diagonal().norm();
  const int grid = tool_.facets.front().exact.grid_exponent;
  bool exact = true;
  for (const PolytopeFacet& f : tool_.facets) exact = exact && f.exact.set() && f.exact.grid_exponent == grid;
  for (const Vector3d& v : tool_.vertices) {
    if (!exact) break;
    const std::optional<GridPoint> p = grid_point(v, grid);
    if (p) grid_vertices_.push_back(*p);
    exact = exact && p.has_value();
  }
  if (!exact) return;
  grid_ = grid;
  for (const GridPoint& v : grid_vertices_)
    for (std::int64_t c : v) largest_vertex_ = std::max(largest_vertex_, c < 0 ? -c : c);
  for (const Edge& e : edges_)
    for (int i = 0; i < 3; ++i) {
      const std::int64_t c = grid_vertices_[e.to][i] - grid_vertices_[e.from][i];
      largest_edge_ = std::max(largest_edge_, c < 0 ? -c : c);
    }
}

namespace {

// Offsets of the sweeps' exact planes stay far below the 2^106 the predicates read exactly.
IntegerPlane bounded(const IntegerPlane& plane) {
  const __int128 limit = static_cast<__int128>(1) << 100;
  return plane.offset < limit && plane.offset > -limit ? plane : IntegerPlane{};
}

}  // namespace

std::optional<GridPoint> SweepPolytopeBuilder::on_grid(const Vector3d& x) const {
  if (!grid_) return std::nullopt;
  return grid_point(x, *grid_);
}

Halfspace SweepPolytopeBuilder::placed(int f, const Vector3d& at, const GridPoint* grid_at) const {
  const PolytopeFacet& facet = tool_.facets[f];
  Halfspace h{facet.normal, facet.offset + facet.normal.dot(at)};
  if (grid_at) h.exact = bounded(facet.exact.translated(*grid_at));
  return h;
}

std::pair<Vector3d, Vector3d> SweepPolytopeBuilder::ordered(const Vector3d& start, const Vector3d& end) {
  const bool swap = std::lexicographical_compare(end.data(), end.data() + 3, start.data(), start.data() + 3);
  return swap ? std::pair{end, start} : std::pair{start, end};
}

bool SweepPolytopeBuilder::degenerate(const Vector3d& start, const Vector3d& end) const {
  const auto [a, b] = ordered(start, end);
  return !((b - a).norm() > 1e-12 * size_);
}

bool SweepPolytopeBuilder::exact(const Vector3d& start, const Vector3d& end) const {
  const std::optional<GridPoint> a = on_grid(start), b = on_grid(end);
  if (!a || !b) return false;
  // Offsets: |n·X| <= 3·2^52·max|X| stays below bounded()'s 2^100 when max|X| < 2^46.
  constexpr std::int64_t kLargestPoint = std::int64_t{1} << 46;
  std::int64_t point = largest_vertex_, step = 0;
  GridPoint motion{};
  for (int i = 0; i < 3; ++i) {
    point = std::max({point, std::abs((*a)[i]) + largest_vertex_, std::abs((*b)[i]) + largest_vertex_});
    motion[i] = (*b)[i] - (*a)[i];
  }
  if (point >= kLargestPoint) return false;
  if (degenerate(start, end)) return true;
  // A silhouette normal reduced(edge) × reduced(motion) has components <= 2·|edge|·|motion|.
  for (std::int64_t c : reduced(motion)) step = std::max(step, c < 0 ? -c : c);
  return static_cast<__int128>(2) * largest_edge_ * step <= kMaxIntegerNormal;
}

std::int64_t SweepPolytopeBuilder::largest_exact_step() const {
  if (!grid_ || largest_edge_ == 0) return 0;
  return kMaxIntegerNormal / (2 * largest_edge_);
}

Halfspace SweepPolytopeBuilder::silhouette_look(const Edge& e, const Vector3d& a,
                                                const Vector3d& motion) const {
  Vector3d normal = (tool_.vertices[e.to] - tool_.vertices[e.from]).cross(motion).normalized();
  if (normal.dot(tool_.facets[e.left].normal + tool_.facets[e.right].normal) < 0.0) normal = -normal;
  return {normal, normal.dot(tool_.vertices[e.from] + a), {}};
}

Halfspace SweepPolytopeBuilder::silhouette_plane(const Edge& e, const Vector3d& a,
                                                 const Vector3d& motion) const {
  const std::optional<GridPoint> start = on_grid(a), step = on_grid(motion);
  if (!start || !step || !on_grid(a + motion)) return silhouette_look(e, a, motion);
  return silhouette_plane(e, a, motion, *start, reduced(*step));
}

Halfspace SweepPolytopeBuilder::silhouette_plane(const Edge& e, const Vector3d& a, const Vector3d& motion,
                                                 const GridPoint& start, const GridPoint& step) const {
  Halfspace h = silhouette_look(e, a, motion);
  // Exactly through both ends of the edge at both placements: the edge and the motion reduced to
  // coprime integers keep the normal small (an axis move's motion is a unit vector).
  GridPoint edge{};
  for (int i = 0; i < 3; ++i) edge[i] = grid_vertices_[e.to][i] - grid_vertices_[e.from][i];
  GridPoint through = grid_vertices_[e.from];
  for (int i = 0; i < 3; ++i) through[i] += start[i];
  std::optional<IntegerPlane> exact = plane_through(integer_cross(reduced(edge), step), through, *grid_);
  if (!exact) return h;
  const double look = double(exact->normal[0]) * h.normal.x() + double(exact->normal[1]) * h.normal.y() +
                      double(exact->normal[2]) * h.normal.z();
  h.exact = bounded(look < 0.0 ? exact->negated() : *exact);
  return h;
}

SweepPolytopeBuilder::Planes::Planes(const SweepPolytopeBuilder& builder, const Vector3d& start,
                                     const Vector3d& end)
    : builder_(&builder) {
  const ConvexPolytope& tool = builder.tool_;
  side_.assign(tool.facets.size(), -1);
  if (builder.degenerate(start, end)) {
    a_ = b_ = start;
    motion_ = Vector3d::Zero();
    grid_a_ = builder.on_grid(start);
    exact_ = grid_a_.has_value();
    return;
  }
  std::tie(a_, b_) = ordered(start, end);
  motion_ = b_ - a_;
  grid_a_ = builder.on_grid(a_);
  grid_b_ = builder.on_grid(b_);
  exact_ = grid_a_ && grid_b_;
  motion_sides(tool, motion_, side_);
  // The silhouette planes are exact when the motion is on the grid too (b - a rounds exactly
  // when both ends are on it, unless far apart: then on_grid(a + motion) is checked).
  const std::optional<GridPoint> step = exact_ ? builder.on_grid(motion_) : std::nullopt;
  exact_silhouettes_ = step && builder.on_grid(a_ + motion_);
  if (exact_silhouettes_) step_ = reduced(*step);
  const std::vector<Edge>& edges = builder.edges_;
  for (std::size_t e = 0; e < edges.size(); ++e)
    if (side_[edges[e].left] * side_[edges[e].right] < 0) silhouette_.push_back(static_cast<int>(e));
}

Halfspace SweepPolytopeBuilder::Planes::operator[](std::size_t k) const {
  if (k < side_.size()) {
    const bool end = side_[k] > 0;
    return builder_->placed(static_cast<int>(k), end ? b_ : a_,
                            exact_ ? (end ? &*grid_b_ : &*grid_a_) : nullptr);
  }
  const Edge& e = builder_->edges_[silhouette_[k - side_.size()]];
  return exact_silhouettes_ ? builder_->silhouette_plane(e, a_, motion_, *grid_a_, step_)
                            : builder_->silhouette_look(e, a_, motion_);
}

std::vector<Halfspace> SweepPolytopeBuilder::halfspaces(const Vector3d& start, const Vector3d& end) const {
  const Planes source(*this, start, end);
  std::vector<Halfspace> planes;
  planes.reserve(source.size());
  for (std::size_t k = 0; k < source.size(); ++k) planes.push_back(source[k]);
  return planes;
}

ConvexPolytope SweepPolytopeBuilder::operator()(const Vector3d& start, const Vector3d& end) const {
  if (degenerate(start, end)) return tool_.translated(start);  // exact planes kept on the grid
  const auto [a, b] = ordered(start, end);
  const Vector3d motion = b - a;
  const std::vector<Halfspace> planes = halfspaces(start, end);  // in facet order

  // Side of each tool facet: -1 back (kept at a), +1 forward (kept at b), 0 swept whole.
  std::vector<signed char> side;
  motion_sides(tool_, motion, side);
  const int n = static_cast<int>(tool_.vertices.size());
  ConvexPolytope sweep;
  std::vector<int> used(2 * n, -1);
  auto vertex = [&](int id) {
    if (used[id] < 0) {
      used[id] = static_cast<int>(sweep.vertices.size());
      sweep.vertices.push_back(id < n ? tool_.vertices[id] + a : tool_.vertices[id - n] + b);
    }
    return used[id];
  };
  auto add = [&](const std::vector<int>& ids, const Halfspace& plane) {
    PolytopeFacet facet;
    for (int id : ids) facet.loop.push_back(vertex(id));
    facet.normal = plane.normal;
    facet.offset = plane.offset;
    facet.exact = plane.exact;
    sweep.facets.push_back(std::move(facet));
  };
  for (std::size_t f = 0; f < side.size(); ++f) {
    const PolytopeFacet& facet = tool_.facets[f];
    const Halfspace& plane = planes[f];
    if (side[f] == 0) {
      add(swept_face(tool_, facet, motion), plane);
      continue;
    }
    std::vector<int> ids = facet.loop;
    if (side[f] > 0)
      for (int& id : ids) id += n;
    add(ids, plane);
  }
  for (const Edge& e : edges_) {
    const int s_left = side[e.left], s_right = side[e.right];
    if (s_left * s_right >= 0) continue;  // not a silhouette edge (or a swept face holds it)
    const Halfspace& plane = planes[sweep.facets.size()];
    if (s_left < 0)
      add({e.to, e.from, e.from + n, e.to + n}, plane);
    else
      add({e.from, e.to, e.to + n, e.from + n}, plane);
  }
  return sweep;
}

ConvexPolytope sweep_polytope(const ConvexPolytope& tool, const Vector3d& start, const Vector3d& end) {
  return SweepPolytopeBuilder(tool)(start, end);
}

}  // namespace morph
