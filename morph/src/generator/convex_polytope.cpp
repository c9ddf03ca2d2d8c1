// SPDX-License-Identifier: Apache-2.0
#include <morph/convex_polytope.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace morph {

namespace {

using Eigen::Vector3d;

// Closest point of the triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
Vector3d closest_on_triangle(const Vector3d& p, const Vector3d& a, const Vector3d& b, const Vector3d& c) {
  const Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + d1 / (d1 - d3) * ab;
  const Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

Vector3d loop_area_vector(const std::vector<Vector3d>& vertices, const std::vector<int>& loop) {
  Vector3d sum = Vector3d::Zero();
  const Vector3d& origin = vertices[loop.front()];
  for (std::size_t i = 1; i + 1 < loop.size(); ++i)
    sum += (vertices[loop[i]] - origin).cross(vertices[loop[i + 1]] - origin);
  return 0.5 * sum;
}

double ConvexPolytope::volume() const {
  double sum = 0.0;
  for (const PolytopeFacet& facet : facets)
    sum += loop_area_vector(vertices, facet.loop).dot(vertices[facet.loop[0]]);
  return sum / 3.0;
}

double ConvexPolytope::area() const {
  double sum = 0.0;
  for (const PolytopeFacet& facet : facets) sum += loop_area_vector(vertices, facet.loop).norm();
  return sum;
}

double ConvexPolytope::projected_area(const Vector3d& u) const {
  double sum = 0.0;
  for (const PolytopeFacet& facet : facets) sum += std::abs(loop_area_vector(vertices, facet.loop).dot(u));
  return 0.5 * sum;
}

double ConvexPolytope::plane_value(const Vector3d& p) const {
  double value = -std::numeric_limits<double>::infinity();
  for (const PolytopeFacet& facet : facets) value = std::max(value, facet.normal.dot(p) - facet.offset);
  return value;
}

Eigen::AlignedBox3d ConvexPolytope::bounds() const {
  Eigen::AlignedBox3d box;
  for (const Vector3d& v : vertices) box.extend(v);
  return box;
}

ConvexPolytope ConvexPolytope::translated(const Vector3d& shift) const {
  ConvexPolytope moved = *this;
  for (Vector3d& v : moved.vertices) v += shift;
  for (PolytopeFacet& facet : moved.facets) {
    facet.offset += facet.normal.dot(shift);
    if (!facet.exact.set()) continue;
    const std::optional<GridPoint> on_grid = grid_point(shift, facet.exact.grid_exponent);
    facet.exact = on_grid ? facet.exact.translated(*on_grid) : IntegerPlane{};
  }
  return moved;
}

std::size_t ConvexPolytope::unmatched_edges() const {
  std::map<std::pair<int, int>, int> uses;
  for (const PolytopeFacet& facet : facets)
    for (std::size_t i = 0; i < facet.loop.size(); ++i)
      ++uses[{facet.loop[i], facet.loop[(i + 1) % facet.loop.size()]}];
  std::size_t unmatched = 0;
  for (const auto& [edge, count] : uses) {
    const auto reverse = uses.find({edge.second, edge.first});
    if (count != 1 || reverse == uses.end() || reverse->second != 1) ++unmatched;
  }
  return unmatched;
}

double boundary_distance(const ConvexPolytope& polytope, const Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const PolytopeFacet& facet : polytope.facets) {
    const Vector3d& a = polytope.vertices[facet.loop[0]];
    for (std::size_t i = 1; i + 1 < facet.loop.size(); ++i) {
      const Vector3d q =
          closest_on_triangle(p, a, polytope.vertices[facet.loop[i]], polytope.vertices[facet.loop[i + 1]]);
      best = std::min(best, (q - p).norm());
    }
  }
  return best;
}

}  // namespace morph
