// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/tool_polytope.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

namespace morph {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kMaxCount = 65536.0;

// One chord of the inscribed meridian polygon and how far the exact profile bulges beyond it.
struct Chord {
  Vector2d from, to;
  double sagitta = 0.0;
};

int checked_count(double count, const char* what) {
  if (!(count <= kMaxCount))
    throw LimitError(std::string("tool polytope: ") + what + " would need more than 65536 pieces");
  return std::max(1, static_cast<int>(std::ceil(count)));
}

// The angle a curved piece turns through from its end on the axis with a level tangent (a
// pole: a ball's tip, a sphere's top) to where a level chord cut off there bulges by `sagitta`;
// zero where that end is no pole. Such a flat cap, not a fan of facets about an apex, is what
// keeps two passes at one depth apart: their caps lie in one exact plane, and the order of
// terms decides between them, where two fans of nearly level facets about apexes a hair apart
// cross in a cloud of distinct exact points finer than any rounding.
double pole_cap_angle(const ProfilePiece& piece, double angle, double sagitta) {
  if (piece.centre.x() != 0.0 || std::abs(std::cos(angle)) > 1e-12) return 0.0;
  return std::acos(std::max(-1.0, 1.0 - sagitta / piece.radii.y()));
}

Vector2d point_at(const ProfilePiece& piece, double angle) {
  return piece.centre + Vector2d(piece.radii.x() * std::cos(angle), piece.radii.y() * std::sin(angle));
}

// Chords of one profile piece, each within `sagitta` of it (lines stay whole; a pole becomes a
// level chord, pole_cap_angle).
void append_chords(const ProfilePiece& piece, double sagitta, std::vector<Chord>& chords) {
  if (piece.kind == ProfilePiece::Kind::Segment) {
    chords.push_back({piece.from, piece.to, 0.0});
    return;
  }
  double cap0 = pole_cap_angle(piece, piece.angle0, sagitta);
  double cap1 = pole_cap_angle(piece, piece.angle1, sagitta);
  if (cap0 + cap1 >= 0.5 * (piece.angle1 - piece.angle0)) cap0 = cap1 = 0.0;
  const double angle0 = piece.angle0 + cap0, angle1 = piece.angle1 - cap1;
  const double span = angle1 - angle0;
  const double a = piece.radii.x(), b = piece.radii.y();
  int count;
  double bulge;  // largest sagitta of one chord of `count`
  if (piece.kind == ProfilePiece::Kind::Arc) {
    const double step = 2.0 * std::acos(std::max(-1.0, 1.0 - sagitta / a));
    count = checked_count(span / step, "the meridian");
    bulge = a * (1.0 - std::cos(0.5 * span / count));
  } else {
    // Curvature of an ellipse is at most max(a/b², b/a²); a chord of length l bulges at most
    // curvature·l²/8, and l is at most the arc length, at most max(a, b) per radian.
    const double curvature = std::max(a / (b * b), b / (a * a)), speed = std::max(a, b);
    count = checked_count(span * speed * std::sqrt(curvature / (8.0 * sagitta)), "the meridian");
    const double length = speed * span / count;
    bulge = curvature * length * length / 8.0;
  }
  Vector2d previous = cap0 > 0.0 ? point_at(piece, angle0) : piece.from;
  if (cap0 > 0.0) chords.push_back({Vector2d(0.0, previous.y()), previous, b * (1.0 - std::cos(cap0))});
  for (int i = 1; i <= count; ++i) {
    const Vector2d next = i < count    ? point_at(piece, angle0 + span * i / count)
                          : cap1 > 0.0 ? point_at(piece, angle1)
                                       : piece.to;
    chords.push_back({previous, next, bulge});
    previous = next;
  }
  if (cap1 > 0.0) chords.push_back({previous, Vector2d(0.0, previous.y()), b * (1.0 - std::cos(cap1))});
}

double cross(const Vector2d& u, const Vector2d& v) {
  return u.x() * v.y() - u.y() * v.x();
}

// Chords without zero-length pieces, and straight runs of unbulged chords merged into one.
std::vector<Chord> tidy(const std::vector<Chord>& chords, double scale) {
  std::vector<Chord> kept;
  for (const Chord& chord : chords) {
    if ((chord.to - chord.from).norm() <= 1e-12 * scale) continue;
    if (!kept.empty() && kept.back().sagitta == 0.0 && chord.sagitta == 0.0 &&
        std::abs(cross(kept.back().to - kept.back().from, chord.to - chord.from)) <=
            1e-12 * (kept.back().to - kept.back().from).norm() * (chord.to - chord.from).norm()) {
      kept.back().to = chord.to;
      continue;
    }
    kept.push_back(chord);
  }
  return kept;
}

// The straddling meridian: each chord's line pushed out (to the right of travel) by half its
// sagitta; vertices where consecutive lines meet, the ends where the first and last lines meet
// the axis (the profile's mirror image closes it there).
std::vector<Vector2d> straddling_meridian(const std::vector<Chord>& chords) {
  auto normal = [](const Chord& c) {
    const Vector2d d = (c.to - c.from).normalized();
    return Vector2d(d.y(), -d.x());
  };
  auto line_offset = [&](const Chord& c) { return normal(c).dot(c.from) + 0.5 * c.sagitta; };
  auto on_axis = [&](const Chord& c) {
    const Vector2d n = normal(c);
    if (std::abs(n.y()) < 1e-12) return Vector2d(0.0, c.from.y());
    return Vector2d(0.0, line_offset(c) / n.y());
  };
  std::vector<Vector2d> points{on_axis(chords.front())};
  for (std::size_t i = 0; i + 1 < chords.size(); ++i) {
    const Vector2d n0 = normal(chords[i]), n1 = normal(chords[i + 1]);
    const double det = cross(n0, n1), c0 = line_offset(chords[i]), c1 = line_offset(chords[i + 1]);
    if (std::abs(det) < 1e-12) {
      points.push_back(chords[i].to + 0.5 * chords[i].sagitta * n0);
      continue;
    }
    points.emplace_back((c0 * n1.y() - c1 * n0.y()) / det, (n0.x() * c1 - n1.x() * c0) / det);
  }
  points.push_back(on_axis(chords.back()));
  // A level line stays exactly level (flat bottoms and tops, and pole caps, become one facet).
  for (std::size_t i = 0; i < chords.size(); ++i)
    if (chords[i].from.y() == chords[i].to.y())
      points[i].y() = points[i + 1].y() =
          chords[i].from.y() + 0.5 * chords[i].sagitta * normal(chords[i]).y();
  return points;
}

// The exact plane of a loop of grid points: the integer Newell normal (twice the area vector,
// exact), through the first point; unset if the loop is not exactly planar (it always is here).
IntegerPlane exact_plane(const std::vector<GridPoint>& points, const std::vector<int>& loop,
                         int grid_exponent) {
  std::array<__int128, 3> normal{};
  for (std::size_t i = 0; i < loop.size(); ++i) {
    const std::array<__int128, 3> c = integer_cross(points[loop[i]], points[loop[(i + 1) % loop.size()]]);
    for (int k = 0; k < 3; ++k) normal[k] += c[k];
  }
  const std::optional<IntegerPlane> plane = plane_through(normal, points[loop.front()], grid_exponent);
  if (!plane) return {};
  for (int v : loop)
    if (plane->value_at(points[v]) != 0) return {};
  return *plane;
}

PolytopeFacet make_facet(const std::vector<Vector3d>& vertices, const std::vector<GridPoint>& points,
                         std::vector<int> loop, int grid_exponent) {
  PolytopeFacet f;
  f.loop = std::move(loop);
  f.normal = loop_area_vector(vertices, f.loop).normalized();
  Vector3d centre = Vector3d::Zero();
  for (int v : f.loop) centre += vertices[v];
  f.offset = f.normal.dot(centre / static_cast<double>(f.loop.size()));
  f.exact = exact_plane(points, f.loop, grid_exponent);
  return f;
}

// Length of the rings' integer directions: a ring of radius ρ has its vertices at s·d_k grid
// steps, s = round(ρ / (M·step)); the radius is then within M·step/2 ≤ max_deviation/8 (with
// grid_exponent_for's step) and |d_k| within ~0.1 of M (the best of a small window), a relative
// 2.5e-5 of the radius.
constexpr std::int64_t kDirectionLength = 4096;

// Integer directions of length about kDirectionLength at angles 2πk/N (N a multiple of 4): the
// first quadrant searched, the others its exact quarter turns (the tool's quarter symmetry).
std::vector<std::array<std::int64_t, 2>> ring_directions(int sectors) {
  const int quarter = sectors / 4;
  const double length = static_cast<double>(kDirectionLength);
  std::vector<std::array<std::int64_t, 2>> d(sectors);
  for (int k = 0; k < quarter; ++k) {
    const double angle = 2.0 * M_PI * k / sectors;
    const auto x0 = std::llround(length * std::cos(angle)), y0 = std::llround(length * std::sin(angle));
    double best = 1e300;
    for (std::int64_t dx = -2; dx <= 2; ++dx)
      for (std::int64_t dy = -2; dy <= 2; ++dy) {
        const double x = double(x0 + dx), y = double(y0 + dy);
        // radial error first; the angular one (≤ 3/M rad) only breaks ties
        const double error = std::fabs(std::hypot(x, y) - length) +
                             1e-6 * std::hypot(x - length * std::cos(angle), y - length * std::sin(angle));
        if (k == 0 && dy != 0) continue;  // keep the first direction on the x axis
        if (error < best) {
          best = error;
          d[k] = {x0 + dx, y0 + dy};
        }
      }
    for (int q = 1; q < 4; ++q) {
      const auto& p = d[k + (q - 1) * quarter];
      d[k + q * quarter] = {-p[1], p[0]};
    }
  }
  return d;
}

// Every point of the polytope is within half a meridian chord's sagitta plus half a ring side's
// (straddling halves both) plus the grid's eighth of the budget of the tool: so the sagittas may
// add up to 1.75 budgets, half each. (A meridian of lines only could give its rings all of it;
// that doubles a flat or conical tool's radial error, and a thin pillar between V-bit grooves
// vanished: error_budget.h.)
double chord_sagitta(double max_deviation) {
  return (1.0 - 1.0 / 8.0) * max_deviation;
}

// The inscribed meridian's chords within the budget (checked: the tool and the deviation).
std::vector<Chord> meridian_chords(const ToolProfile& profile, double max_deviation) {
  if (profile.empty()) throw InputError("tool polytope: the tool has no profile");
  if (!(max_deviation > 0.0) || !std::isfinite(max_deviation))
    throw InputError("tool polytope: the deviation must be positive and finite, got " +
                     std::to_string(max_deviation));
  const double scale = std::max(profile.radius(), profile.height());
  std::vector<Chord> chords;
  for (const ProfilePiece& piece : profile.pieces())
    append_chords(piece, chord_sagitta(max_deviation), chords);
  chords = tidy(chords, scale);
  if (chords.size() > kMaxCount)
    throw LimitError("tool polytope: the meridian would need more than 65536 pieces");
  return chords;
}

// Sectors of every ring, a multiple of 4 so the polytope keeps the tool's quarter symmetry.
int sector_count(const ToolProfile& profile, double max_deviation) {
  const double half_step = std::acos(std::max(-1.0, 1.0 - chord_sagitta(max_deviation) / profile.radius()));
  return 4 * checked_count(M_PI / half_step / 4.0, "the rings");
}

}  // namespace

ToolPolytopeSize tool_polytope_size(const ToolProfile& profile, double max_deviation) {
  ToolPolytopeSize size;
  size.meridian_points = meridian_chords(profile, max_deviation).size() + 1;
  size.sectors = sector_count(profile, max_deviation);
  // Quads between consecutive rings, and at each end an N-gon or an apex fan (counted as a fan).
  const std::size_t rings = size.meridian_points - 2;
  size.facets = static_cast<std::size_t>(size.sectors) * (rings + 1);
  return size;
}

ToolPolytope tool_polytope(const ToolProfile& profile, double max_deviation) {
  const std::vector<Chord> chords = meridian_chords(profile, max_deviation);
  ToolPolytope result;
  result.meridian = straddling_meridian(chords);
  for (Vector2d& p : result.meridian) p.y() -= profile.point_height();
  const std::vector<Vector2d>& meridian = result.meridian;
  const int sectors = sector_count(profile, max_deviation);
  result.sectors = sectors;
  const double radial_scale = 2.0 / (1.0 + std::cos(M_PI / sectors));
  // Every vertex on the grid, the rings homothetic (one set of integer directions): each
  // trapezoid is exactly planar and its exact plane holds its four vertices (quantize.h).
  const int grid = grid_exponent_for(max_deviation);
  result.grid_exponent = grid;
  const std::vector<std::array<std::int64_t, 2>> directions = ring_directions(sectors);
  auto grid_steps = [&](double length) { return std::llround(std::ldexp(length, -grid)); };
  std::vector<GridPoint> points;
  auto add_vertex = [&](const GridPoint& p) {
    points.push_back(p);
    result.polytope.vertices.emplace_back(std::ldexp(double(p[0]), grid), std::ldexp(double(p[1]), grid),
                                          std::ldexp(double(p[2]), grid));
  };

  // A flat end (first or last chord level) is one N-gon facet; otherwise the axis point is an apex.
  const std::size_t last = meridian.size() - 1;
  const bool flat_bottom = meridian[1].y() == meridian[0].y();
  const bool flat_top = meridian[last - 1].y() == meridian[last].y();
  ConvexPolytope& polytope = result.polytope;
  std::vector<int> ring_start(meridian.size(), -1);
  for (std::size_t j = 1; j < last; ++j) {
    ring_start[j] = static_cast<int>(polytope.vertices.size());
    const std::int64_t scale = std::max<std::int64_t>(
        1, std::llround(std::ldexp(radial_scale * meridian[j].x(), -grid) / double(kDirectionLength)));
    const std::int64_t z = grid_steps(meridian[j].y());
    for (int k = 0; k < sectors; ++k) add_vertex({scale * directions[k][0], scale * directions[k][1], z});
  }
  auto ring = [&](std::size_t j, int k) { return ring_start[j] + (k % sectors); };
  int bottom_apex = -1, top_apex = -1;
  if (!flat_bottom) {
    bottom_apex = static_cast<int>(polytope.vertices.size());
    add_vertex({0, 0, grid_steps(meridian[0].y())});
  }
  if (!flat_top) {
    top_apex = static_cast<int>(polytope.vertices.size());
    add_vertex({0, 0, grid_steps(meridian[last].y())});
  }
  const std::vector<Vector3d>& v = polytope.vertices;
  auto facet = [&](std::vector<int> loop) { return make_facet(v, points, std::move(loop), grid); };
  if (flat_bottom) {
    std::vector<int> loop;
    for (int k = sectors - 1; k >= 0; --k) loop.push_back(ring(1, k));
    polytope.facets.push_back(facet(loop));
  }
  for (int k = 0; k < sectors; ++k) {
    if (!flat_bottom) polytope.facets.push_back(facet({bottom_apex, ring(1, k + 1), ring(1, k)}));
    for (std::size_t j = 1; j + 1 < last; ++j)
      polytope.facets.push_back(facet({ring(j, k), ring(j, k + 1), ring(j + 1, k + 1), ring(j + 1, k)}));
    if (!flat_top) polytope.facets.push_back(facet({ring(last - 1, k), ring(last - 1, k + 1), top_apex}));
  }
  if (flat_top) {
    std::vector<int> loop;
    for (int k = 0; k < sectors; ++k) loop.push_back(ring(last - 1, k));
    polytope.facets.push_back(facet(loop));
  }
  return result;
}

}  // namespace morph
