// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/planar_dilation.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace morph::planar {

namespace {

double angle_of(const Vec2& v) {
  return std::atan2(v.y(), v.x());
}

/// The half circle of `radius` about p on the side of -tangent (behind the tangent), from
/// p + radius * left(tangent) counter-clockwise to p - radius * left(tangent).
Curve back_half_circle(const Vec2& p, const Vec2& tangent, double radius, const Provenance& from) {
  const Vec2 n = left_normal(tangent);
  Curve c = make_arc(p, radius, angle_of(n), M_PI, from);
  c.start = p + radius * n;
  c.end = p - radius * n;
  return c;
}

std::string move_name(std::size_t index, const Move& move) {
  return "move " + std::to_string(index) + (move.line > 0 ? " (line " + std::to_string(move.line) + ")" : "");
}

}  // namespace

double distance_to_move(const Curve& move, const Vec2& p) {
  return closest_point(move, p).distance;
}

void dilation_boundary(const Curve& move, double radius, std::vector<Curve>& out) {
  const Provenance& from = move.from;
  if (!move.is_arc()) {
    const Vec2 d = move.end - move.start;
    const double len = d.norm();
    if (len == 0.0) {
      out.push_back(make_arc(move.start, radius, 0.0, 2.0 * M_PI, from));
      return;
    }
    const Vec2 u = d / len, n = left_normal(u);
    out.push_back(make_segment(move.start - radius * n, move.end - radius * n, from));
    // The half circle ahead of the end, from the right parallel's end to the left one's start.
    Curve front = make_arc(move.end, radius, angle_of(-n), M_PI, from);
    front.start = move.end - radius * n;
    front.end = move.end + radius * n;
    out.push_back(front);
    out.push_back(make_segment(move.end + radius * n, move.start + radius * n, from));
    out.push_back(back_half_circle(move.start, u, radius, from));
    return;
  }
  const double rho = move.radius;
  const double a0 = start_angle(move);
  out.push_back(make_arc(move.center, rho + radius, a0, move.sweep, from));
  if (rho > radius) out.push_back(make_arc(move.center, rho - radius, a0, move.sweep, from));
  out.push_back(back_half_circle(move.start, tangent_at(move, 0.0), radius, from));
  const Vec2 te = tangent_at(move, 1.0);
  Curve front = make_arc(move.end, radius, angle_of(-left_normal(te)), M_PI, from);
  front.start = move.end - radius * left_normal(te);
  front.end = move.end + radius * left_normal(te);
  out.push_back(front);
}

Box2 dilation_bounds(const Curve& move, double radius) {
  Box2 box = bounds(move);
  box.min().array() -= radius;
  box.max().array() += radius;
  return box;
}

Trajectory planar_trajectory(const std::vector<const Move*>& moves, double cutting_height) {
  Trajectory out;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const Move& m = *moves[i];
    const Provenance from{Origin::Sweep, static_cast<std::int32_t>(i), m.line};
    // The part of the move at or below the cutting height: z is linear in t for lines and helices.
    const double z0 = m.start.z(), z1 = m.end.z();
    double t0 = 0.0, t1 = 1.0;
    if (z0 > cutting_height && z1 > cutting_height) continue;
    if (z0 != z1) {
      const double tc = std::clamp((cutting_height - z0) / (z1 - z0), 0.0, 1.0);
      if (z0 > cutting_height) t0 = tc;
      if (z1 > cutting_height) t1 = tc;
    }
    const Eigen::Vector3d p0 = point_at(m, t0), p1 = point_at(m, t1);
    const Vec2 a(p0.x(), p0.y()), b(p1.x(), p1.y());
    if (!m.is_arc()) {
      out.push_back(make_segment(a, b, from));
      continue;
    }
    if (std::abs(std::abs(m.axis.z()) - 1.0) > 1e-9)
      throw InputError(move_name(i, m) + ": an arc outside the XY plane has no planar trajectory (axis " +
                       std::to_string(m.axis.x()) + ", " + std::to_string(m.axis.y()) + ", " +
                       std::to_string(m.axis.z()) + ")");
    const Vec2 c(m.center.x(), m.center.y());
    const double r = (a - c).norm();
    if (r == 0.0) {
      out.push_back(make_segment(a, a, from));
      continue;
    }
    double sweep = m.sweep * (t1 - t0) * (m.axis.z() > 0.0 ? 1.0 : -1.0);
    sweep = std::clamp(sweep, -2.0 * M_PI, 2.0 * M_PI);
    if (sweep == 0.0) {
      out.push_back(make_segment(a, a, from));
      continue;
    }
    out.push_back(make_arc(c, r, angle_of(a - c), sweep, from));
    out.back().start = a;
  }
  return out;
}

}  // namespace morph::planar
