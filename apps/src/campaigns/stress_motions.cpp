// SPDX-License-Identifier: Apache-2.0
// The motion families of `morphmill stress --families motion`: the motions real programs make and
// on which a generator that trims each patch on its own breaks (issue 18): a pass retraced, a
// plunge and its retract, a reversal at any angle up to 179.99 degrees, a sub-micron move, arcs in
// every plane and helices, a sheet with parts and slugs cut out, a path crossing itself dozens of
// times, several tools in one job. Box stock. The tool is drawn from every tool of revolution.
//
// What is known by construction: blind cuts leave one piece of genus 0; each contour cut through
// a sheet frees what it encloses and opens one tunnel. Volumes come from closed forms where the
// motion has one: a level pass of length L at depth d removes L * S(d) + V(d) (Cavalieri: S the
// tool's meridian section below the top, V the tool's volume below it), a retrace removes nothing
// more, a vertical plunge removes pi * integral of rmax(h)^2 (rmax the widest radius up to h), a
// level full circle of radius rho >= R removes 2 pi rho S(d) (Pappus).
#include <morph/exceptions.h>
#include <morph/tool.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <limits>
#include <sstream>

#include "campaigns/stress_builder.h"

namespace morphmill::stress {

namespace {

// --- tools ---------------------------------------------------------------------------------------

/// A drawn tool: its job JSON and the same tool built by morph, for the closed forms.
struct DrawnTool {
  nlohmann::json json;
  morph::Tool tool;
  std::string word;           ///< "flat r 2.5", for the variant text
  double point_height = 0.0;  ///< tool point above the tip (the sphere's centre)
  double height = 0.0;        ///< the tool's height above its tip
};

DrawnTool drawn(nlohmann::json json, morph::Tool tool, const std::string& word) {
  DrawnTool t{std::move(json), std::move(tool), word, 0.0, 0.0};
  t.point_height = t.tool.profile.point_height();
  t.height = t.tool.profile.height();
  return t;
}

/// Every tool of revolution MorphMill knows.
DrawnTool draw_tool(CaseRandom& rng) {
  const double r = round3(rng.uniform(1.5, 3.0));
  const double length = round3(rng.uniform(8.0, 14.0));
  switch (rng.integer(0, 6)) {
    case 0:
      return drawn({{"type", "sphere"}, {"radius", r}}, morph::sphere_tool(r), fmt::format("sphere r {}", r));
    case 1:
      return drawn({{"type", "ballend"}, {"radius", r}, {"length", length}}, morph::ball_tool(r, length),
                   fmt::format("ballend r {}", r));
    case 2:
      return drawn({{"type", "flat"}, {"radius", r}, {"length", length}}, morph::flat_tool(r, length),
                   fmt::format("flat r {}", r));
    case 3: {
      const double corner = round3(r * rng.uniform(0.2, 0.8));
      return drawn({{"type", "bullnose"}, {"radius", r}, {"corner_radius", corner}, {"length", length}},
                   morph::bullnose_tool(r, corner, length),
                   fmt::format("bullnose r {} corner {}", r, corner));
    }
    case 4: {
      static const double angles[] = {60.0, 90.0, 120.0};
      const double angle = angles[rng.integer(0, 2)];
      const double tip = rng.chance(0.5) ? 0.0 : round3(r * rng.uniform(0.1, 0.4));
      const double total = round3(morph::cone_height(r, angle, tip) + rng.uniform(3.0, 8.0));
      nlohmann::json json = {{"type", "vbit"}, {"radius", r}, {"angle", angle}, {"length", total}};
      if (tip > 0) json["tip_radius"] = tip;
      return drawn(json, morph::conical_tool(r, angle, total, tip),
                   fmt::format("vbit r {} {} deg tip {}", r, angle, tip));
    }
    case 5: {
      const double tip = round3(r * rng.uniform(0.3, 0.7));
      return drawn({{"type", "tapered"}, {"tip_radius", tip}, {"radius", r}, {"length", length}},
                   morph::tapered_tool(tip, r, length), fmt::format("tapered tip {} r {}", tip, r));
    }
    default: {
      const double ball = round3(r * rng.uniform(0.3, 0.6));
      const double taper = round3(rng.uniform(3.0, 15.0));
      return drawn({{"type", "tapered_ball"}, {"tip_radius", ball}, {"angle", taper}, {"length", length}},
                   morph::tapered_ball_tool(ball, taper, length),
                   fmt::format("tapered_ball ball {} taper {} deg", ball, taper));
    }
  }
}

// --- closed forms --------------------------------------------------------------------------------

/// Integral of f over [a, b] by tanh-sinh quadrature: exact to ~1e-14 relative for a function
/// smooth inside the interval even with square-root ends, as a profile's radius is on each piece
/// (its flat bottom and a ball's tip have vertical tangents r'(h) there).
template <class F>
double tanh_sinh(F f, double a, double b) {
  if (!(b > a)) return 0.0;
  const double half = 0.5 * (b - a);
  constexpr double kStep = 1.0 / 64.0;
  double sum = 0.0;
  for (int k = -256; k <= 256; ++k) {
    const double t = k * kStep, u = 0.5 * M_PI * std::sinh(t);
    const double x = std::tanh(u), w = 0.5 * M_PI * std::cosh(t) / (std::cosh(u) * std::cosh(u));
    if (1.0 - std::abs(x) < 1e-300 || w < 1e-300) continue;
    // Offset from the nearer end computed directly, so points next to an end are not rounded onto it.
    const double from_end = half / (std::exp(2.0 * std::abs(u)) + 1.0) * 2.0;
    const double h = x < 0 ? a + from_end : b - from_end;
    if (h <= a || h >= b) continue;
    sum += w * f(h);
  }
  return sum * half * kStep;
}

/// Integral of f(h) over [0, depth], split where the profile's pieces meet.
template <class F>
double over_profile(const morph::Tool& tool, double depth, F f) {
  std::vector<double> breaks = {0.0};
  for (const morph::ProfilePiece& piece : tool.profile.pieces())
    if (piece.to.y() > breaks.back() && piece.to.y() < depth) breaks.push_back(piece.to.y());
  breaks.push_back(depth);
  double sum = 0.0;
  for (std::size_t i = 0; i + 1 < breaks.size(); ++i) sum += tanh_sinh(f, breaks[i], breaks[i + 1]);
  return sum;
}

}  // namespace

double section_below(const morph::Tool& tool, double depth) {
  return over_profile(tool, depth, [&](double h) { return 2.0 * tool.profile.radius_at(h); });
}

double volume_below(const morph::Tool& tool, double depth) {
  return over_profile(tool, depth, [&](double h) {
    const double r = tool.profile.radius_at(h);
    return M_PI * r * r;
  });
}

double plunge_volume(const morph::Tool& tool, double depth) {
  // Up to the lowest height where the profile is widest, the plunge removes the tool itself; above
  // it (only the closed shapes, sphere and spheroid, narrow again) the widest radius stays.
  const double widest = tool.profile.radius();
  double widest_height = std::numeric_limits<double>::infinity();
  for (const morph::ProfilePiece& piece : tool.profile.pieces()) {
    if (piece.from.x() >= widest) widest_height = std::min(widest_height, piece.from.y());
    if (piece.to.x() >= widest) widest_height = std::min(widest_height, piece.to.y());
    if (piece.kind != morph::ProfilePiece::Kind::Segment && piece.centre.x() + piece.radii.x() >= widest)
      widest_height = std::min(widest_height, piece.centre.y());
  }
  const double up_to = std::min(depth, widest_height);
  return volume_below(tool, up_to) + M_PI * widest * widest * (depth - up_to);
}

namespace {

// --- layout --------------------------------------------------------------------------------------

/// A box stock holding every point of `points` (tool positions, xy) with `margin` around them,
/// height `height`; the box's min corner is the origin's lattice point below.
void box_around(Builder& b, const std::vector<Vector3d>& points, double margin, double height) {
  Eigen::AlignedBox2d box;
  for (const auto& p : points) box.extend(p.head<2>());
  const Eigen::Vector2d lo = (box.min().array() - margin).floor(), hi = (box.max().array() + margin).ceil();
  b.box(Vector3d(lo.x(), lo.y(), 0), Vector3d(hi.x(), hi.y(), height));
}

/// Depth of a blind cut for tool t in a stock of height H: within the tool's height and well
/// above the bottom.
double blind_depth(CaseRandom& rng, const DrawnTool& t, double height) {
  return round3(std::min(0.8 * t.height, height * rng.uniform(0.3, 0.6)));
}

Vector3d unit_in_plane(double angle) {
  return Vector3d(std::cos(angle), std::sin(angle), 0.0);
}

/// A level blind pass through the origin in a stock of height `height`: the tool (tool 1 of the
/// job), the depth, and the pass from `start` to `end` (tool points), of `length` in a drawn direction.
struct BlindPass {
  DrawnTool tool;
  double height = 0, depth = 0, length = 0;
  Vector3d start, end;
};

BlindPass draw_blind_pass(CaseRandom& rng, Builder& b) {
  BlindPass pass;
  pass.tool = draw_tool(rng);
  b.tool(1, pass.tool.json, pass.tool.tool.radius);
  pass.height = round3(rng.uniform(4.0, 10.0));
  pass.depth = blind_depth(rng, pass.tool, pass.height);
  pass.length = round3(rng.uniform(5.0, 25.0));
  const Vector3d u = unit_in_plane(rng.uniform(0.0, M_PI));
  const Vector3d centre(0, 0, pass.height - pass.depth + pass.tool.point_height);
  pass.start = centre - 0.5 * pass.length * u;
  pass.end = centre + 0.5 * pass.length * u;
  return pass;
}

void blind_result(Builder& b, const std::string& variant) {
  b.expected_genus(0);
  b.finish(variant, 1);
}

/// A closed box mesh whose top face is a fan of slivers from its (lo.x, lo.y) corner to points on
/// its two far top edges (x = hi.x at `far_y`, y = hi.y at `far_x`, each strictly inside its edge,
/// any order), as CAD exports triangulate a face; the two side faces holding those points are fans
/// from a bottom corner, the other faces two triangles each. Wound outward.
morph::TriangleMesh sliver_box_mesh(const Vector3d& lo, const Vector3d& hi, std::vector<double> far_y,
                                    std::vector<double> far_x) {
  std::sort(far_y.begin(), far_y.end());
  std::sort(far_x.begin(), far_x.end(), std::greater<double>());
  morph::TriangleMesh mesh;
  auto vertex = [&](double x, double y, double z) {
    mesh.vertices.emplace_back(x, y, z);
    return static_cast<std::uint32_t>(mesh.vertices.size() - 1);
  };
  std::uint32_t corner[8];  // bit 0: x, bit 1: y, bit 2: z at hi
  for (int i = 0; i < 8; ++i)
    corner[i] = vertex(i & 1 ? hi.x() : lo.x(), i & 2 ? hi.y() : lo.y(), i & 4 ? hi.z() : lo.z());
  // The top's outline from (hi.x, lo.y) round to (lo.x, hi.y), counter-clockwise seen from above.
  std::vector<std::uint32_t> rim{corner[5]};
  for (double y : far_y) rim.push_back(vertex(hi.x(), y, hi.z()));
  rim.push_back(corner[7]);
  const std::size_t rim_corner = rim.size() - 1;
  for (double x : far_x) rim.push_back(vertex(x, hi.y(), hi.z()));
  rim.push_back(corner[6]);
  for (std::size_t i = 0; i + 1 < rim.size(); ++i) mesh.triangles.push_back({corner[4], rim[i], rim[i + 1]});
  // Side x = hi.x, seen from +x: bottom (hi.x, lo.y) -> (hi.x, hi.y), then the top edge back.
  for (std::size_t i = 0; i < rim_corner; ++i) mesh.triangles.push_back({corner[1], rim[i + 1], rim[i]});
  mesh.triangles.push_back({corner[1], corner[3], rim[rim_corner]});
  // Side y = hi.y, seen from +y: bottom (hi.x, hi.y) -> (lo.x, hi.y), then the top edge back.
  for (std::size_t i = rim_corner; i + 1 < rim.size(); ++i)
    mesh.triangles.push_back({corner[3], rim[i + 1], rim[i]});
  mesh.triangles.push_back({corner[3], corner[2], rim.back()});
  // The plain faces: bottom (z = lo), x = lo, y = lo.
  for (const morph::Triangle& t :
       std::initializer_list<morph::Triangle>{{corner[0], corner[2], corner[1]},
                                              {corner[1], corner[2], corner[3]},  // bottom
                                              {corner[0], corner[4], corner[2]},
                                              {corner[2], corner[4], corner[6]},  // x = lo
                                              {corner[0], corner[1], corner[4]},
                                              {corner[1], corner[5], corner[4]}})  // y = lo
    mesh.triangles.push_back(t);
  return mesh;
}

// --- families ------------------------------------------------------------------------------------

// A level blind pass driven there and back, several laps, partly back, or repeated as separate
// paths: exactly the single pass.
void retrace(CaseRandom& rng, Builder& b) {
  const BlindPass pass = draw_blind_pass(rng, b);
  const DrawnTool& t = pass.tool;
  const double height = pass.height, d = pass.depth, length = pass.length;
  const Vector3d a = pass.start, c = pass.end;
  box_around(b, {a, c}, t.tool.radius + 2.0, height);
  const int variant = rng.integer(0, 3);
  std::string what;
  if (variant == 0) {
    b.path({a, c, a});
    what = "there and back";
  } else if (variant == 1) {
    const int laps = rng.integer(2, 4);
    std::vector<Vector3d> points;
    for (int i = 0; i <= 2 * laps; ++i) points.push_back(i % 2 ? c : a);
    b.path(points);
    what = fmt::format("{} laps there and back", laps);
  } else if (variant == 2) {
    const double s = round3(rng.uniform(0.1, 0.9));
    b.path({a, c, a + s * (c - a)});
    what = fmt::format("there and {:.0f}% back", 100 * (1 - s));
  } else {
    b.path({a, c});
    if (rng.chance(0.5))
      b.path({a, c});
    else
      b.path({c, a});
    what = "repeated as a second path";
  }
  b.expected_volume(b.stock_volume() - (length * section_below(t.tool, d) + volume_below(t.tool, d)));
  blind_result(b, fmt::format("{}, depth {}, {} mm pass {}", t.word, d, length, what));
}

// Vertical plunges to a depth and straight back up, travelling above the stock between them; a
// peck (half depth, out, full depth) removes what the deepest plunge removes.
void plunge_retract(CaseRandom& rng, Builder& b) {
  const DrawnTool t = draw_tool(rng);
  b.tool(1, t.json, t.tool.radius);
  const double height = round3(rng.uniform(4.0, 10.0)), d = blind_depth(rng, t, height);
  const int count = rng.integer(1, 3);
  const double pitch = round3(2 * t.tool.radius * (1 + kGapInRadii));
  const double above = height + 1.0 + t.point_height, low = height - d + t.point_height;
  const bool peck = rng.chance(0.3), one_path = rng.chance(0.5);
  std::vector<Vector3d> centres, all;
  for (int i = 0; i < count; ++i) centres.push_back(Vector3d(i * pitch, 0, 0));
  for (const auto& c : centres) {
    std::vector<Vector3d> points = {c + Vector3d(0, 0, above)};
    if (peck) {
      points.push_back(c + Vector3d(0, 0, (above + low) / 2));
      points.push_back(c + Vector3d(0, 0, above));
    }
    points.push_back(c + Vector3d(0, 0, low));
    points.push_back(c + Vector3d(0, 0, above));
    if (one_path)
      all.insert(all.end(), points.begin(), points.end());
    else
      b.path(points);
  }
  if (one_path) b.path(all);
  box_around(b, centres, t.tool.radius + 2.0, height);
  b.expected_volume(b.stock_volume() - count * plunge_volume(t.tool, d));
  blind_result(b, fmt::format("{}, {} plunge(s) and retract(s) to depth {}{}{}", t.word, count, d,
                              peck ? ", pecked" : "", one_path ? ", one path" : ""));
}

// A level pass that turns by an angle up to a full reversal (0: straight on).
void reversal(CaseRandom& rng, Builder& b) {
  const DrawnTool t = draw_tool(rng);
  b.tool(1, t.json, t.tool.radius);
  static const double turns[] = {0.0, 30.0, 90.0, 135.0, 170.0, 179.0, 179.9, 179.99, 180.0};
  const double turn = turns[rng.integer(0, 8)];
  const double height = round3(rng.uniform(4.0, 10.0)), d = blind_depth(rng, t, height);
  const double first = round3(rng.uniform(6.0, 20.0)), second = round3(rng.uniform(3.0, first));
  const double heading = rng.uniform(0.0, 2 * M_PI);
  const double z = height - d + t.point_height;
  const Vector3d a(0, 0, z);
  const Vector3d corner = a + first * unit_in_plane(heading);
  const Vector3d end = corner + second * unit_in_plane(heading + turn * M_PI / 180.0);
  b.path({a, corner, end});
  box_around(b, {a, corner, end}, t.tool.radius + 2.0, height);
  if (turn == 0.0)
    b.expected_volume(b.stock_volume() -
                      ((first + second) * section_below(t.tool, d) + volume_below(t.tool, d)));
  if (turn == 180.0)  // the way back ends within the first pass
    b.expected_volume(b.stock_volume() - (first * section_below(t.tool, d) + volume_below(t.tool, d)));
  blind_result(b, fmt::format("{}, depth {}, turn of {} degrees", t.word, d, turn));
}

// A move of a micron or less inside a pass, at a corner, or as a step down.
void submicron(CaseRandom& rng, Builder& b) {
  const DrawnTool t = draw_tool(rng);
  b.tool(1, t.json, t.tool.radius);
  static const double tiny[] = {1e-6, 1e-5, 1e-4, 1e-3};
  const double delta = tiny[rng.integer(0, 3)];
  const double height = round3(rng.uniform(4.0, 10.0)), d = blind_depth(rng, t, height);
  const double length = round3(rng.uniform(6.0, 20.0));
  const double z = height - d + t.point_height;
  const Vector3d u = unit_in_plane(rng.uniform(0.0, 2 * M_PI)), n(-u.y(), u.x(), 0.0);
  const Vector3d a(0, 0, z), mid = a + 0.5 * length * u, c = a + length * u;
  const int variant = rng.integer(0, 2);
  std::string what;
  if (variant == 0) {
    b.path({a, mid, mid + delta * u, c});
    box_around(b, {a, c}, t.tool.radius + 2.0, height);
    b.expected_volume(b.stock_volume() - (length * section_below(t.tool, d) + volume_below(t.tool, d)));
    what = "inside the pass";
  } else if (variant == 1) {
    const Vector3d side = c + delta * n, end = side + 0.5 * length * n;
    b.path({a, c, side, end});
    box_around(b, {a, c, end}, t.tool.radius + 2.0, height);
    what = "at a right-angle corner";
  } else {
    const Vector3d step = c - Vector3d(0, 0, delta), back = step - 0.5 * length * u + 0.3 * length * n;
    b.path({a, c, step, back});
    box_around(b, {a, c, back}, t.tool.radius + 2.0, height);
    what = "as a step down at a turn";
  }
  blind_result(b, fmt::format("{}, depth {}, a {:g} mm move {}", t.word, d, delta, what));
}

std::string number(double v) {
  std::ostringstream out;
  out.precision(12);
  out << v;
  return out.str();
}

// Arcs as G-code: a level full circle (G17, Pappus), a dip under the top in G18, a 300-degree arc
// in G19 whose tangent turns vertical twice, and a helix down and the same arc reversed.
void arcs(CaseRandom& rng, Builder& b) {
  const DrawnTool t = draw_tool(rng);
  b.tool(1, t.json, t.tool.radius);
  const double height = round3(rng.uniform(6.0, 12.0)), d = blind_depth(rng, t, height);
  const double r = t.tool.radius, rho = round3(r + rng.uniform(1.0, 6.0));
  const double top = height + t.point_height, low = height - d + t.point_height, above = top + 1.0;
  const double cx = round3(rho + r + 3.0), cy = cx;
  std::string g = "G21 G90 G17\n";
  const int variant = rng.integer(0, 3);
  std::string what;
  const std::string cw = rng.chance(0.5) ? "G2" : "G3";
  if (variant == 0) {
    g += fmt::format("G0 X{} Y{} Z{}\nG1 Z{} F300\n{} X{} Y{} I{} J0\nG0 Z{}\n", number(cx + rho), number(cy),
                     number(above), number(low), cw, number(cx + rho), number(cy), number(-rho),
                     number(above));
    b.box(Vector3d(0, 0, 0), Vector3d(2 * cx, 2 * cy, height));
    // The plunge's widest radius up to the depth is within the ring the circle sweeps, unless a
    // sphere plunges past its equator (it widens below the depth there).
    if (!(t.tool.type == morph::ToolType::Sphere && d > t.point_height))
      b.expected_volume(b.stock_volume() - 2 * M_PI * rho * section_below(t.tool, d));
    what = fmt::format("G17 full circle radius {} ({})", rho, cw);
  } else if (variant == 1) {
    // From above the top on one side, under it, to above the top on the other: G2 in G18 goes
    // from -X through -Z to +X.
    const double sag = round3(std::min(d, rho));
    const double zc = low + sag;  // the arc's lowest point is at the tool point of depth d
    g += fmt::format("G18\nG0 X{} Y{} Z{}\nG1 Z{} F300\nG2 X{} Z{} I{} K0\nG0 Z{}\n", number(cx - sag),
                     number(cy), number(above), number(zc), number(cx + sag), number(zc), number(sag),
                     number(above));
    b.box(Vector3d(0, 0, 0), Vector3d(2 * cx, 2 * cy, height));
    what = fmt::format("G18 half circle of radius {} dipping to depth {}", sag, d);
  } else if (variant == 2) {
    // In G19 (Y first, then Z), counter-clockwise from 120 to 420 degrees: 300 degrees.
    const double arc = round3(std::min(rho, 0.45 * d));
    const double zc = low + arc;
    auto at = [&](double degrees) {
      const double a = degrees * M_PI / 180.0;
      return std::array<double, 2>{cy + arc * std::cos(a), zc + arc * std::sin(a)};
    };
    const auto s = at(120.0), e = at(60.0);
    g += fmt::format("G19\nG0 X{} Y{} Z{}\nG1 Z{} F300\nG3 Y{} Z{} J{} K{}\nG0 Z{}\n", number(cx),
                     number(s[0]), number(above), number(s[1]), number(e[0]), number(e[1]), number(cy - s[0]),
                     number(zc - s[1]), number(above));
    b.box(Vector3d(0, 0, 0), Vector3d(2 * cx, 2 * cy, height));
    what = fmt::format("G19 arc of 300 degrees, radius {}", arc);
  } else {
    const int turns = rng.integer(1, 3);
    g += fmt::format("G0 X{} Y{} Z{}\n{} X{} Y{} Z{} I{} J0 P{}\n", number(cx + rho), number(cy),
                     number(above), cw, number(cx + rho), number(cy), number(low), number(-rho), turns);
    const std::string back = cw == "G2" ? "G3" : "G2";
    g += fmt::format("{} X{} Y{} I{} J0\nG0 Z{}\n", back, number(cx - rho), number(cy), number(-rho),
                     number(above));
    b.box(Vector3d(0, 0, 0), Vector3d(2 * cx, 2 * cy, height));
    what = fmt::format("helix of {} turn(s) down to depth {}, then half the circle reversed", turns, d);
  }
  g += "M2\n";
  b.gcode(g);
  blind_result(b, fmt::format("{}, {}", t.word, what));
}

/// A tool that cuts through a sheet with vertical walls (the sphere: centred in a sheet thinner
/// than 1.2 radii); `half_kerf` is the kerf's half width at both faces.
struct ThroughCut {
  DrawnTool tool;
  double height = 0, tool_z = 0, half_kerf = 0;
  bool vertical_walls = true;
};

ThroughCut draw_through_cut(CaseRandom& rng) {
  ThroughCut cut;
  const double r = round3(rng.uniform(1.5, 3.0)), length = round3(rng.uniform(10.0, 14.0));
  const int shape = rng.integer(0, 3);
  if (shape == 0) {
    cut.tool =
        drawn({{"type", "sphere"}, {"radius", r}}, morph::sphere_tool(r), fmt::format("sphere r {}", r));
    cut.height = round3(r * rng.uniform(0.5, 1.0));
    cut.tool_z = cut.height / 2;
    cut.half_kerf = std::sqrt(r * r - cut.height * cut.height / 4);
    cut.vertical_walls = false;
    return cut;
  }
  double below = 0;  // how far the tip must be under the bottom for vertical walls through the sheet
  if (shape == 1) {
    cut.tool = drawn({{"type", "ballend"}, {"radius", r}, {"length", length}}, morph::ball_tool(r, length),
                     fmt::format("ballend r {}", r));
    below = r;
  } else if (shape == 2) {
    cut.tool = drawn({{"type", "flat"}, {"radius", r}, {"length", length}}, morph::flat_tool(r, length),
                     fmt::format("flat r {}", r));
  } else {
    const double corner = round3(r * rng.uniform(0.2, 0.8));
    cut.tool =
        drawn({{"type", "bullnose"}, {"radius", r}, {"corner_radius", corner}, {"length", length}},
              morph::bullnose_tool(r, corner, length), fmt::format("bullnose r {} corner {}", r, corner));
    below = corner;
  }
  cut.height = round3(rng.uniform(2.0, 5.0));
  cut.tool_z = -below - round3(rng.uniform(0.2, 1.0));
  cut.half_kerf = r;
  return cut;
}

/// The closed rectangle (half sizes ax, ay about c) as a path, from its lower left corner.
std::vector<Vector3d> rectangle(const Vector3d& c, double ax, double ay) {
  return {c + Vector3d(-ax, -ay, 0), c + Vector3d(ax, -ay, 0), c + Vector3d(ax, ay, 0),
          c + Vector3d(-ax, ay, 0), c + Vector3d(-ax, -ay, 0)};
}

/// Area of the band a disc of radius h sweeps along the closed rectangle path (h < ax, ay).
double rectangle_kerf_area(double ax, double ay, double h) {
  const double outer = 4 * ax * ay + 2 * (2 * ax + 2 * ay) * h + M_PI * h * h;
  return outer - (2 * ax - 2 * h) * (2 * ay - 2 * h);
}

// A sheet with parts cut out through its thickness, some with a hole whose slug falls free:
// 1 + parts + slugs pieces; the sheet keeps a tunnel per part and a part with a hole has one.
void cutout(CaseRandom& rng, Builder& b) {
  const ThroughCut cut = draw_through_cut(rng);
  const DrawnTool& t = cut.tool;
  b.tool(1, t.json, t.tool.radius);
  const double r = t.tool.radius, h = cut.half_kerf, gap = kGapInRadii * r;
  const int parts = rng.integer(1, 3);
  double x = 0, kerf_area = 0;
  int slugs = 0;
  std::vector<Vector3d> corners;
  for (int i = 0; i < parts; ++i) {
    const bool hole = rng.chance(0.5);
    const double hx = round3(h + r * rng.uniform(kGapInRadii, kGapInRadii + 1.0));
    const double hy = round3(h + r * rng.uniform(kGapInRadii, kGapInRadii + 1.0));
    // The outline clears the hole's kerf (or, without one, the part's own) by a gap.
    const double clear_x = (hole ? hx + 2 * h : h) + gap, clear_y = (hole ? hy + 2 * h : h) + gap;
    const double ax = round3(clear_x + r * rng.uniform(0.0, 1.0));
    const double ay = round3(std::max(clear_y, ax * rng.uniform(0.7, 1.3)));
    const Vector3d centre(round3(x + ax + h), 0, cut.tool_z);
    if (hole) {
      b.path(rectangle(centre, hx, hy));
      kerf_area += rectangle_kerf_area(hx, hy, h);
      ++slugs;
    }
    const auto outline = rectangle(centre, ax, ay);
    b.path(outline);
    kerf_area += rectangle_kerf_area(ax, ay, h);
    corners.push_back(outline[0]);
    corners.push_back(outline[2]);
    x = centre.x() + ax + h + gap;
  }
  box_around(b, corners, h + gap + 1.0, cut.height);
  if (cut.vertical_walls) b.expected_volume(b.stock_volume() - cut.height * kerf_area);
  b.expected_genus(parts + slugs);
  b.finish(
      fmt::format("{}, sheet {} thick, {} part(s) cut out, {} with a slug", t.word, cut.height, parts, slugs),
      1 + parts + slugs);
}

// A star polygon {n/k} cut blind, once or twice round: n (k - 1) self-crossings.
void self_crossing(CaseRandom& rng, Builder& b) {
  const DrawnTool t = draw_tool(rng);
  b.tool(1, t.json, t.tool.radius);
  static const int points[] = {5, 7, 9, 11, 13};
  const int n = points[rng.integer(0, 4)], k = rng.integer(2, (n - 1) / 2);
  const double height = round3(rng.uniform(4.0, 10.0)), d = blind_depth(rng, t, height);
  const double rho = round3(t.tool.radius * rng.uniform(4.0, 8.0)), phase = rng.uniform(0.0, 2 * M_PI);
  const int laps = rng.chance(0.3) ? 2 : 1;
  const double z = height - d + t.point_height;
  std::vector<Vector3d> star;
  for (int j = 0; j <= laps * n; ++j) {
    const double a = phase + 2 * M_PI * (j % n) * k / n;
    star.push_back(Vector3d(rho * std::cos(a), rho * std::sin(a), z));
  }
  b.path(star);
  box_around(b, star, t.tool.radius + 2.0, height);
  const std::string variant =
      fmt::format("{}, depth {}, star {{{}/{}}} of radius {} ({} crossings){}", t.word, d, n, k, rho,
                  n * (k - 1), laps == 2 ? ", twice round" : "");
  // A sphere whose centre runs below the top is widest under it: where three grooves nearly meet
  // they undercut the material between them and can free a chip of it (real pieces, a fraction of
  // a voxel: the exact field confirms them), or bridge a groove. Neither pieces nor genus are
  // known by construction.
  if (t.tool.type == morph::ToolType::Sphere && d > t.tool.radius) {
    b.finish(variant + ", undercut", -1);
    return;
  }
  blind_result(b, variant);
}

// Two tools in one job: parallel passes apart (the volumes add) or the second crossing the first.
void mixed_tools(CaseRandom& rng, Builder& b) {
  const DrawnTool t1 = draw_tool(rng), t2 = draw_tool(rng);
  b.tool(1, t1.json, t1.tool.radius);
  b.tool(2, t2.json, t2.tool.radius);
  const double height = round3(rng.uniform(4.0, 10.0));
  const double d1 = blind_depth(rng, t1, height), d2 = blind_depth(rng, t2, height);
  const double length = round3(rng.uniform(8.0, 20.0));
  const bool crossing = rng.chance(0.5);
  const double z1 = height - d1 + t1.point_height, z2 = height - d2 + t2.point_height;
  const Vector3d a(0, 0, z1), c(length, 0, z1);
  b.path({a, c}, 1);
  Vector3d p, q;
  if (crossing) {
    p = Vector3d(length / 2, -length / 2, z2);
    q = Vector3d(length / 2, length / 2, z2);
  } else {
    const double y =
        round3(t1.tool.radius + t2.tool.radius + kGapInRadii * std::max(t1.tool.radius, t2.tool.radius));
    p = Vector3d(0, y, z2);
    q = Vector3d(length, y, z2);
  }
  b.path({p, q}, 2);
  box_around(b, {a, c, p, q}, std::max(t1.tool.radius, t2.tool.radius) + 2.0, height);
  if (!crossing)
    b.expected_volume(b.stock_volume() - (length * section_below(t1.tool, d1) + volume_below(t1.tool, d1)) -
                      (length * section_below(t2.tool, d2) + volume_below(t2.tool, d2)));
  blind_result(b, fmt::format("T1 {} depth {}, T2 {} depth {}, {}", t1.word, d1, t2.word, d2,
                              crossing ? "crossing" : "side by side"));
}

// A blind level pass in a box stock given as a mesh whose top is a fan of slivers, some a
// micrometre wide, crossing the groove (issue 18's "mesh stock with slivers near a groove"):
// exactly the pass in a plain box.
void mesh_stock(CaseRandom& rng, Builder& b) {
  const BlindPass pass = draw_blind_pass(rng, b);
  const DrawnTool& t = pass.tool;
  const double height = pass.height, d = pass.depth, length = pass.length;
  const Vector3d a = pass.start, c = pass.end;
  Eigen::AlignedBox2d reach;
  for (const Vector3d& p : {a, c}) reach.extend(p.head<2>());
  const double margin = t.tool.radius + 2.0;
  const Eigen::Vector2d lo = (reach.min().array() - margin).floor(),
                        hi = (reach.max().array() + margin).ceil();
  // The far edges' points: a few spread along each, and a cluster where the slivers from the
  // corner pass over the groove's middle (the origin), spaced down to a micrometre.
  const double spacing = std::pow(10.0, rng.uniform(-3.0, -1.0));
  // Where the line from the corner through the origin meets the edge x = hi.x (lo < 0 < hi).
  const double y_mid = lo.y() - lo.y() * (hi.x() - lo.x()) / -lo.x();
  std::vector<double> far_y, far_x;
  const int spread = rng.integer(2, 8), cluster = rng.integer(3, 12);
  for (int i = 0; i < spread; ++i) far_y.push_back(round3(rng.uniform(lo.y() + 0.5, hi.y() - 0.5)));
  for (int i = 0; i < spread; ++i) far_x.push_back(round3(rng.uniform(lo.x() + 0.5, hi.x() - 0.5)));
  const double centre = std::clamp(y_mid, lo.y() + 1.0, hi.y() - 1.0);
  for (int i = 0; i < cluster; ++i) far_y.push_back(centre + (i - cluster / 2) * spacing);
  std::sort(far_y.begin(), far_y.end());
  far_y.erase(std::unique(far_y.begin(), far_y.end()), far_y.end());
  std::sort(far_x.begin(), far_x.end());
  far_x.erase(std::unique(far_x.begin(), far_x.end()), far_x.end());
  b.mesh_stock(sliver_box_mesh(Vector3d(lo.x(), lo.y(), 0), Vector3d(hi.x(), hi.y(), height), far_y, far_x),
               "slivers");
  b.path({a, c});
  b.expected_volume(b.stock_volume() - (length * section_below(t.tool, d) + volume_below(t.tool, d)));
  blind_result(b, fmt::format("{}, depth {}, {} mm pass over {} slivers {:.3g} mm apart", t.word, d, length,
                              far_y.size() + far_x.size() + 1, spacing));
}

// A level blind pass written as many short moves, as CAM output at a fine step is: along an axis
// (the points exactly collinear, one sweep for generator 2), or in a drawn direction (the points
// a rounding off the line, each joint a turn of about 1e-10 radians): exactly the single pass.
void fine_steps(CaseRandom& rng, Builder& b) {
  BlindPass pass = draw_blind_pass(rng, b);
  const DrawnTool& t = pass.tool;
  const double height = pass.height, d = pass.depth, length = pass.length;
  const bool along_axis = rng.chance(0.5);
  if (along_axis) {
    const Vector3d centre = 0.5 * (pass.start + pass.end),
                   u = rng.chance(0.5) ? Vector3d::UnitX() : Vector3d::UnitY();
    pass.start = centre - 0.5 * length * u;
    pass.end = centre + 0.5 * length * u;
  }
  // Off an axis every joint is a sweep of its own: fewer of them.
  static const double axis_steps[] = {0.01, 0.05, 0.1, 0.5}, drawn_steps[] = {0.25, 0.5, 1.0};
  const double step = along_axis ? axis_steps[rng.integer(0, 3)] : drawn_steps[rng.integer(0, 2)];
  const int moves = static_cast<int>(std::ceil(length / step));
  const Vector3d u = (pass.end - pass.start).normalized();
  std::vector<Vector3d> points;
  for (int k = 0; k < moves; ++k) points.push_back(pass.start + (k * step) * u);
  points.push_back(pass.end);
  b.path(points);
  box_around(b, {pass.start, pass.end}, t.tool.radius + 2.0, height);
  b.expected_volume(b.stock_volume() - (length * section_below(t.tool, d) + volume_below(t.tool, d)));
  blind_result(b, fmt::format("{}, depth {}, {} mm pass as {} moves of {} mm {}", t.word, d, length, moves,
                              step, along_axis ? "along an axis" : "in a drawn direction"));
}

}  // namespace

const std::vector<std::pair<std::string, Family>>& motion_family_table() {
  static const std::vector<std::pair<std::string, Family>> table = {
      {"retrace", retrace},
      {"plunge_retract", plunge_retract},
      {"reversal", reversal},
      {"submicron", submicron},
      {"arcs", arcs},
      {"cutout", cutout},
      {"self_crossing", self_crossing},
      {"mixed_tools", mixed_tools},
      {"mesh_stock", mesh_stock},
      {"fine_steps", fine_steps},
  };
  return table;
}

}  // namespace morphmill::stress
