// SPDX-License-Identifier: Apache-2.0
#include "planar/planar_intersect.h"

#include <algorithm>
#include <cmath>

namespace morph::planar {

namespace {

/// Adds p if it lies on both curves within eps (the candidate points all lie on the supporting
/// lines or circles; this restricts them to the curves themselves).
void add_if_on_both(const Curve& a, const Curve& b, const Vec2& p, double eps, std::vector<CurveHit>& hits) {
  const ClosestPoint ca = closest_point(a, p);
  if (ca.distance > eps) return;
  const ClosestPoint cb = closest_point(b, p);
  if (cb.distance > eps) return;
  hits.push_back({p, ca.t, cb.t});
}

/// Ends of each curve lying on the other: T-junctions, touching ends and overlaps.
void add_touching_ends(const Curve& a, const Curve& b, double eps, std::vector<CurveHit>& hits) {
  for (const Vec2* p : {&b.start, &b.end}) {
    const ClosestPoint ca = closest_point(a, *p);
    if (ca.distance <= eps) hits.push_back({*p, ca.t, p == &b.start ? 0.0 : 1.0});
  }
  for (const Vec2* p : {&a.start, &a.end}) {
    const ClosestPoint cb = closest_point(b, *p);
    if (cb.distance <= eps) hits.push_back({*p, p == &a.start ? 0.0 : 1.0, cb.t});
  }
}

void segment_segment(const Curve& a, const Curve& b, double eps, std::vector<CurveHit>& hits) {
  const Vec2 da = a.end - a.start, db = b.end - b.start;
  const double la = da.norm(), lb = db.norm();
  if (la == 0.0 || lb == 0.0) return;
  const double denom = cross(da, db);
  // Parallel within rounding: only touching ends or overlaps (handled by the ends).
  if (std::abs(denom) <= 1e-14 * la * lb) return;
  const Vec2 w = b.start - a.start;
  const double ta = cross(w, db) / denom;
  const double tb = cross(w, da) / denom;
  const double slack_a = eps / la, slack_b = eps / lb;
  if (ta < -slack_a || ta > 1.0 + slack_a || tb < -slack_b || tb > 1.0 + slack_b) return;
  hits.push_back(
      {a.start + std::clamp(ta, 0.0, 1.0) * da, std::clamp(ta, 0.0, 1.0), std::clamp(tb, 0.0, 1.0)});
}

/// Segment s against arc c; `swapped` says which argument order the caller used.
void segment_arc(const Curve& s, const Curve& c, double eps, bool swapped, std::vector<CurveHit>& hits) {
  const Vec2 d = s.end - s.start;
  const double len = d.norm();
  if (len == 0.0) return;
  const Vec2 u = d / len;
  const double along = (c.center - s.start).dot(u);
  const Vec2 foot = s.start + along * u;
  const double h = (c.center - foot).norm();
  std::vector<CurveHit> found;
  if (std::abs(h - c.radius) <= eps) {
    add_if_on_both(s, c, foot, eps, found);  // tangent
  } else if (h < c.radius) {
    const double half = std::sqrt((c.radius - h) * (c.radius + h));
    add_if_on_both(s, c, foot - half * u, eps, found);
    add_if_on_both(s, c, foot + half * u, eps, found);
  }
  for (CurveHit& hit : found) {
    if (swapped) std::swap(hit.ta, hit.tb);
    hits.push_back(hit);
  }
}

void arc_arc(const Curve& a, const Curve& b, double eps, std::vector<CurveHit>& hits) {
  const Vec2 d = b.center - a.center;
  const double dist = d.norm();
  const double ra = a.radius, rb = b.radius;
  if (dist <= eps) return;  // concentric: the same circle (overlap by the ends) or none
  if (dist > ra + rb + eps || dist < std::abs(ra - rb) - eps) return;
  const Vec2 u = d / dist;
  if (std::abs(dist - (ra + rb)) <= eps || std::abs(dist - std::abs(ra - rb)) <= eps) {
    // Tangent: the contact point on the line of centres.
    const double along = std::abs(dist - (ra + rb)) <= eps ? ra : (ra > rb ? ra : -ra);
    add_if_on_both(a, b, a.center + along * u, eps, hits);
    return;
  }
  const double x = (dist * dist + ra * ra - rb * rb) / (2.0 * dist);
  const double y = std::sqrt(std::max(0.0, ra * ra - x * x));
  const Vec2 base = a.center + x * u;
  add_if_on_both(a, b, base + y * left_normal(u), eps, hits);
  add_if_on_both(a, b, base - y * left_normal(u), eps, hits);
}

}  // namespace

void intersect(const Curve& a, const Curve& b, double eps, std::vector<CurveHit>& hits) {
  if (!a.is_arc() && !b.is_arc())
    segment_segment(a, b, eps, hits);
  else if (!a.is_arc())
    segment_arc(a, b, eps, false, hits);
  else if (!b.is_arc())
    segment_arc(b, a, eps, true, hits);
  else
    arc_arc(a, b, eps, hits);
  add_touching_ends(a, b, eps, hits);
}

double distance(const Curve& c, const Vec2& p) {
  return closest_point(c, p).distance;
}

}  // namespace morph::planar
