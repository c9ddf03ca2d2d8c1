// SPDX-License-Identifier: Apache-2.0
#include <morph/planar_curve.h>

#include <algorithm>
#include <cmath>

namespace morph::planar {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;

/// Angle turned from the start in the arc's own direction to reach angle phi, in [0, 2*pi).
double angle_from_start(const Curve& c, double phi) {
  double delta = c.sweep > 0.0 ? phi - start_angle(c) : start_angle(c) - phi;
  delta = std::fmod(delta, kTwoPi);
  if (delta < 0.0) delta += kTwoPi;
  return delta;
}

}  // namespace

Curve make_segment(const Vec2& a, const Vec2& b, Provenance from) {
  Curve c;
  c.start = a;
  c.end = b;
  c.from = from;
  return c;
}

Curve make_arc(const Vec2& center, double r, double angle0, double sweep, Provenance from) {
  Curve c;
  c.center = center;
  c.radius = r;
  c.sweep = sweep;
  c.start = center + r * Vec2(std::cos(angle0), std::sin(angle0));
  c.end = std::abs(std::abs(sweep) - kTwoPi) == 0.0
              ? c.start
              : Vec2(center + r * Vec2(std::cos(angle0 + sweep), std::sin(angle0 + sweep)));
  c.from = from;
  return c;
}

Curve make_arc_between(const Vec2& center, const Vec2& a, const Vec2& b, bool ccw, Provenance from) {
  const double r = (a - center).norm();
  const double a0 = std::atan2(a.y() - center.y(), a.x() - center.x());
  const double a1 = std::atan2(b.y() - center.y(), b.x() - center.x());
  double sweep = ccw ? a1 - a0 : a0 - a1;
  sweep = std::fmod(sweep, kTwoPi);
  if (sweep < 0.0) sweep += kTwoPi;
  if (sweep == 0.0) sweep = kTwoPi;  // a == b: the full circle
  Curve c = make_arc(center, r, a0, ccw ? sweep : -sweep, from);
  c.start = a;
  if (std::abs(sweep) < kTwoPi) c.end = center + r * (b - center).normalized();
  return c;
}

Curve make_bulge(const Vec2& a, const Vec2& b, double bulge, Provenance from) {
  if (bulge == 0.0 || a == b) return make_segment(a, b, from);
  // sweep = 4 atan(bulge); the centre lies on the chord's bisector at distance d = h / tan(s/2)
  // with h the half chord, on the left of a->b for a counter-clockwise arc of less than pi.
  const double sweep = 4.0 * std::atan(bulge);
  const Vec2 chord = b - a;
  const double half = 0.5 * chord.norm();
  const double offset = half / std::tan(0.5 * sweep);
  const Vec2 center = 0.5 * (a + b) + offset * left_normal(chord.normalized());
  Curve c = make_arc(center, std::hypot(half, offset), std::atan2(a.y() - center.y(), a.x() - center.x()),
                     sweep, from);
  c.start = a;
  c.end = b;
  return c;
}

double start_angle(const Curve& c) {
  return std::atan2(c.start.y() - c.center.y(), c.start.x() - c.center.x());
}

Vec2 point_at(const Curve& c, double t) {
  if (t <= 0.0) return c.start;
  if (t >= 1.0) return c.end;
  if (!c.is_arc()) return c.start + t * (c.end - c.start);
  const double angle = start_angle(c) + t * c.sweep;
  return c.center + c.radius * Vec2(std::cos(angle), std::sin(angle));
}

Vec2 tangent_at(const Curve& c, double t) {
  if (!c.is_arc()) return (c.end - c.start).normalized();
  const double angle = start_angle(c) + std::clamp(t, 0.0, 1.0) * c.sweep;
  const Vec2 radial(std::cos(angle), std::sin(angle));
  return c.sweep > 0.0 ? left_normal(radial) : Vec2(-left_normal(radial));
}

double curvature(const Curve& c) {
  if (!c.is_arc()) return 0.0;
  return c.sweep > 0.0 ? 1.0 / c.radius : -1.0 / c.radius;
}

double length(const Curve& c) {
  return c.is_arc() ? c.radius * std::abs(c.sweep) : (c.end - c.start).norm();
}

double area_term(const Curve& c) {
  const double chord = 0.5 * cross(c.start, c.end);
  if (!c.is_arc()) return chord;
  return chord + 0.5 * c.radius * c.radius * (c.sweep - std::sin(c.sweep));
}

Box2 bounds(const Curve& c) {
  Box2 box(c.start);
  box.extend(c.end);
  if (!c.is_arc()) return box;
  // The axis-extreme points (angles k pi/2) the arc passes.
  for (int k = 0; k < 4; ++k) {
    const double phi = k * 0.5 * M_PI;
    if (angle_from_start(c, phi) <= std::abs(c.sweep))
      box.extend(c.center + c.radius * Vec2(std::cos(phi), std::sin(phi)));
  }
  return box;
}

Curve reversed(const Curve& c) {
  Curve r = c;
  std::swap(r.start, r.end);
  r.sweep = -c.sweep;
  return r;
}

Curve sub_curve(const Curve& c, double t0, double t1, const Vec2& p0, const Vec2& p1) {
  Curve s = c;
  s.start = p0;
  s.end = p1;
  if (c.is_arc()) s.sweep = c.sweep * (t1 - t0);
  return s;
}

ClosestPoint closest_point(const Curve& c, const Vec2& p) {
  ClosestPoint best;
  if (!c.is_arc()) {
    const Vec2 d = c.end - c.start;
    const double dd = d.squaredNorm();
    best.t = dd > 0.0 ? std::clamp((p - c.start).dot(d) / dd, 0.0, 1.0) : 0.0;
    best.point = best.t >= 1.0 ? c.end : Vec2(c.start + best.t * d);
    best.distance = (p - best.point).norm();
    return best;
  }
  const Vec2 radial = p - c.center;
  const double rn = radial.norm();
  if (rn > 0.0) {
    const double delta = angle_from_start(c, std::atan2(radial.y(), radial.x()));
    if (delta <= std::abs(c.sweep)) {
      best.t = delta / std::abs(c.sweep);
      best.point = c.center + (c.radius / rn) * radial;
      best.distance = std::abs(rn - c.radius);
      return best;
    }
  }
  const double ds = (p - c.start).norm(), de = (p - c.end).norm();
  if (ds <= de) {
    best.point = c.start;
    best.t = 0.0;
    best.distance = ds;
  } else {
    best.point = c.end;
    best.t = 1.0;
    best.distance = de;
  }
  return best;
}

double parameter_of(const Curve& c, const Vec2& p) {
  if (!c.is_arc()) {
    const Vec2 d = c.end - c.start;
    const double dd = d.squaredNorm();
    return dd > 0.0 ? std::clamp((p - c.start).dot(d) / dd, 0.0, 1.0) : 0.0;
  }
  const double span = std::abs(c.sweep);
  const double delta = angle_from_start(c, std::atan2(p.y() - c.center.y(), p.x() - c.center.x()));
  if (delta <= span) return delta / span;
  // Past the end: the nearer end by angle.
  return (delta - span) < (kTwoPi - delta) ? 1.0 : 0.0;
}

}  // namespace morph::planar
