// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/planar_region.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "planar/planar_intersect.h"

namespace morph::planar {

namespace {

/// Crossing of the ray from p towards +x with a y-monotone piece from a to b whose x at height
/// p.y is given by x_at.
template <class XAt>
int monotone_crossing(const Vec2& a, const Vec2& b, const Vec2& p, XAt x_at) {
  if ((a.y() > p.y()) == (b.y() > p.y())) return 0;
  return x_at() > p.x() ? 1 : 0;
}

std::string where(const std::string& what, std::size_t loop, std::size_t element) {
  std::ostringstream out;
  out << what << ": loop " << loop << ", element " << element;
  return out.str();
}

std::string format_point(const Vec2& p) {
  std::ostringstream out;
  out << '(' << p.x() << ", " << p.y() << ')';
  return out.str();
}

}  // namespace

double signed_area(const Loop& loop) {
  double sum = 0.0;
  for (const Curve& c : loop.curves) sum += area_term(c);
  return sum;
}

double perimeter(const Loop& loop) {
  double sum = 0.0;
  for (const Curve& c : loop.curves) sum += length(c);
  return sum;
}

double area(const Region& region) {
  double sum = 0.0;
  for (const Loop& loop : region.loops) sum += signed_area(loop);
  return sum;
}

double perimeter(const Region& region) {
  double sum = 0.0;
  for (const Loop& loop : region.loops) sum += perimeter(loop);
  return sum;
}

std::size_t hole_count(const Region& region) {
  std::size_t n = 0;
  for (const Piece& piece : region.pieces) n += piece.holes.size();
  return n;
}

Box2 bounds(const Region& region) {
  Box2 box;
  for (const Loop& loop : region.loops)
    for (const Curve& c : loop.curves) box.extend(bounds(c));
  return box;
}

int crossings(const Curve& c, const Vec2& p) {
  if (!c.is_arc())
    return monotone_crossing(c.start, c.end, p, [&] {
      const double t = (p.y() - c.start.y()) / (c.end.y() - c.start.y());
      return c.start.x() + t * (c.end.x() - c.start.x());
    });
  // Split the arc at its top and bottom into y-monotone pieces, each on one half of the circle.
  const double a0 = start_angle(c);
  const double span = std::abs(c.sweep);
  std::vector<double> cuts{0.0, span};
  for (int k = 0; k < 2; ++k) {
    const double phi = M_PI * (0.5 + k);
    double delta = c.sweep > 0.0 ? phi - a0 : a0 - phi;
    delta = std::fmod(delta, 2.0 * M_PI);
    if (delta < 0.0) delta += 2.0 * M_PI;
    if (delta > 0.0 && delta < span) cuts.push_back(delta);
  }
  std::sort(cuts.begin(), cuts.end());
  const double dir = c.sweep > 0.0 ? 1.0 : -1.0;
  auto at = [&](double delta) -> Vec2 {
    if (delta == 0.0) return c.start;
    if (delta == span) return c.end;
    const double phi = a0 + dir * delta;
    // Exact top and bottom points where the cut is one.
    return c.center + c.radius * Vec2(std::cos(phi), std::sin(phi));
  };
  int n = 0;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double mid = 0.5 * (cuts[i] + cuts[i + 1]);
    const bool right = std::cos(a0 + dir * mid) >= 0.0;
    n += monotone_crossing(at(cuts[i]), at(cuts[i + 1]), p, [&] {
      const double dy = p.y() - c.center.y();
      const double half = std::sqrt(std::max(0.0, c.radius * c.radius - dy * dy));
      return right ? c.center.x() + half : c.center.x() - half;
    });
  }
  return n;
}

int crossings(const Loop& loop, const Vec2& p) {
  int n = 0;
  for (const Curve& c : loop.curves) n += crossings(c, p);
  return n;
}

bool contains(const Region& region, const Vec2& p) {
  int n = 0;
  for (const Loop& loop : region.loops) n += crossings(loop, p);
  return (n & 1) != 0;
}

void validate_loops(std::vector<Loop>& loops, const std::string& what, double gap) {
  for (std::size_t l = 0; l < loops.size(); ++l) {
    std::vector<Curve>& curves = loops[l].curves;
    if (curves.empty()) throw InputError(what + ": loop " + std::to_string(l) + " is empty");
    for (std::size_t i = 0; i < curves.size(); ++i) {
      if (length(curves[i]) <= gap) throw InputError(where(what, l, i) + ": zero-length element");
      Curve& next = curves[(i + 1) % curves.size()];
      const double g = (next.start - curves[i].end).norm();
      if (g > gap)
        throw InputError(where(what, l, i) + ": the loop is open: it ends at " + format_point(curves[i].end) +
                         " but the next element starts at " + format_point(next.start));
      next.start = curves[i].end;
    }
  }
  // Pairwise crossings (bounding boxes first); neighbours may share their common end only.
  struct Item {
    std::size_t loop, index;
    Box2 box;
  };
  std::vector<Item> items;
  for (std::size_t l = 0; l < loops.size(); ++l)
    for (std::size_t i = 0; i < loops[l].curves.size(); ++i)
      items.push_back({l, i, bounds(loops[l].curves[i]).extend(bounds(loops[l].curves[i]))});
  std::sort(items.begin(), items.end(),
            [](const Item& a, const Item& b) { return a.box.min().x() < b.box.min().x(); });
  std::vector<CurveHit> hits;
  for (std::size_t i = 0; i < items.size(); ++i) {
    for (std::size_t j = i + 1; j < items.size() && items[j].box.min().x() <= items[i].box.max().x() + gap;
         ++j) {
      if (items[j].box.min().y() > items[i].box.max().y() + gap ||
          items[i].box.min().y() > items[j].box.max().y() + gap)
        continue;
      const Curve& a = loops[items[i].loop].curves[items[i].index];
      const Curve& b = loops[items[j].loop].curves[items[j].index];
      hits.clear();
      intersect(a, b, gap, hits);
      const std::size_t n = loops[items[i].loop].curves.size();
      const bool same_loop = items[i].loop == items[j].loop;
      for (const CurveHit& hit : hits) {
        // A shared end of neighbours in the same loop is the loop's own vertex.
        const bool a_next_b = same_loop && (items[i].index + 1) % n == items[j].index;
        const bool b_next_a = same_loop && (items[j].index + 1) % n == items[i].index;
        if (a_next_b && (hit.point - a.end).norm() <= gap && (hit.point - b.start).norm() <= gap) continue;
        if (b_next_a && (hit.point - b.end).norm() <= gap && (hit.point - a.start).norm() <= gap) continue;
        throw InputError(where(what, items[i].loop, items[i].index) + " meets loop " +
                         std::to_string(items[j].loop) + ", element " + std::to_string(items[j].index) +
                         " at " + format_point(hit.point) + ": boundary loops must not cross or touch");
      }
    }
  }
}

Region make_region(std::vector<Loop> loops) {
  const std::size_t n = loops.size();
  // Nesting depth: how many other loops contain a point of this loop (its first curve's middle).
  std::vector<int> depth(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 probe = point_at(loops[i].curves.front(), 0.5);
    for (std::size_t j = 0; j < n; ++j)
      if (j != i && (crossings(loops[j], probe) & 1)) ++depth[i];
  }
  for (std::size_t i = 0; i < n; ++i) {
    const bool ccw = signed_area(loops[i]) > 0.0;
    if (ccw != (depth[i] % 2 == 0)) loops[i] = reversed(loops[i]);
  }
  return group_pieces(std::move(loops));
}

Loop reversed(const Loop& loop) {
  Loop r;
  r.curves.reserve(loop.curves.size());
  for (auto it = loop.curves.rbegin(); it != loop.curves.rend(); ++it) r.curves.push_back(reversed(*it));
  return r;
}

Region group_pieces(std::vector<Loop> loops) {
  Region region;
  const std::size_t n = loops.size();
  std::vector<double> areas(n);
  for (std::size_t i = 0; i < n; ++i) areas[i] = signed_area(loops[i]);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  // Outer loops first by decreasing area, then holes by decreasing size (stable: ties keep input order).
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if ((areas[a] > 0.0) != (areas[b] > 0.0)) return areas[a] > 0.0;
    return std::abs(areas[a]) > std::abs(areas[b]);
  });
  for (std::size_t k = 0; k < n; ++k) region.loops.push_back(std::move(loops[order[k]]));
  std::vector<double> sorted_areas(n);
  for (std::size_t k = 0; k < n; ++k) sorted_areas[k] = areas[order[k]];
  std::size_t outer_count = 0;
  while (outer_count < n && sorted_areas[outer_count] > 0.0) {
    region.pieces.push_back(Piece{outer_count, {}});
    ++outer_count;
  }
  // A hole belongs to the smallest outer loop that contains it.
  for (std::size_t k = outer_count; k < n; ++k) {
    const Curve& longest =
        *std::max_element(region.loops[k].curves.begin(), region.loops[k].curves.end(),
                          [](const Curve& a, const Curve& b) { return length(a) < length(b); });
    const Vec2 probe = point_at(longest, 0.5);
    std::size_t best = outer_count;
    for (std::size_t m = 0; m < outer_count; ++m)
      if ((crossings(region.loops[m], probe) & 1) &&
          (best == outer_count || sorted_areas[m] < sorted_areas[best]))
        best = m;
    if (best < outer_count) region.pieces[best].holes.push_back(k);
  }
  return region;
}

}  // namespace morph::planar
