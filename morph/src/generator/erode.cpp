// SPDX-License-Identifier: Apache-2.0
// The paper's secondary 3D model: trimmed parametric patches built from the ordered tool
// positions (side sweeps, front sweeps, stock faces), see morph/erode.h and docs/design/generator.md.
#include <morph/aabb_tree.h>
#include <morph/erode.h>
#include <morph/exceptions.h>
#include <morph/mesh_distance.h>
#include <morph/quantize.h>
#include <morph/sweep_distance.h>
#include <morph/sweep_segments.h>
#include <morph/topology.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <tuple>
#include <unordered_map>

#include <morph/convex_minimum.h>
#include "generator/erode_repair.h"
#include "generator/erode_seams.h"
#include "mesh/edge_uses.h"
#include "mesh/huge_pages.h"

namespace morph {

namespace {

using Eigen::Vector3d;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// A straight piece of a move (arcs are split by chord tolerance); the unit of sweeping.
struct Segment {
  Vector3d a, b;
  const Tool* tool = nullptr;
  int move = -1;  // global move index
  int line = 0;
  int prev = -1;  // adjacent segment in the same chain (shares a), -1 if none
  int next = -1;  // adjacent segment in the same chain (shares b)
  Eigen::AlignedBox3d box;
};

/// The shapes every patch is an instance of; all map [0,1]^2 onto the surface.
enum class Form : std::uint8_t {
  Plane,    // o + u U + v V
  Tube,     // o + u A + R (cos t e1 + sin t e2), t = t0 + v (t1 - t0)
  Sphere,   // o + R (sin p (cos f e1 + sin f e2) + cos p w), f = f0 + u (f1 - f0), p = p0 + v (p1 - p0)
  Disc,     // o + (u R) (cos f e1 + sin f e2), f = 2 pi v
  Triangle  // o + u (U + v V)   (mesh stock triangle: o, o+U, o+U+V)
};

/// A rule a front-sweep patch applies for a move adjacent to its tool position: the point is kept
/// only where it is not interior to that move's sweep. Normal rule: sign * n(x).dir > 0, where n
/// is the tool's outward normal. Position rule (flat top, horizontal move): sign * (x - centre).dir > 0.
struct OwnRule {
  Vector3d dir = Vector3d::Zero();
  bool position = false;
};

struct Patch {
  Form form = Form::Plane;
  Vector3d o = Vector3d::Zero(), U = Vector3d::Zero(), V = Vector3d::Zero();
  Vector3d e1 = Vector3d::UnitX(), e2 = Vector3d::UnitY(), w = Vector3d::UnitZ();
  double R = 0.0, t0 = 0.0, t1 = 0.0, f0 = 0.0, f1 = 0.0;
  bool periodic_u = false, periodic_v = false;
  bool pole_v0 = false, pole_v1 = false;      // Sphere: v=0 / v=1 is a pole (exact point)
  Vector3d plane_normal = Vector3d::UnitZ();  // Plane/Disc/Triangle: outward normal of the bounded solid
  bool has_interior = false;                  // orientation from a point strictly inside the convex solid
  Vector3d interior = Vector3d::Zero();

  bool sweep = false;          // surface of a sweep (result normal = -tool normal) or of the stock
  double owner = 0.0;          // sweeps: segment index (side) or index +- 0.5 (front)
  int exclude[2] = {-1, -1};   // segments not tested by distance (own segment / adjacent ones)
  int adjacent[2] = {-1, -1};  // adjacent segments (tie-break leans to keeping)
  OwnRule rules[2];
  int rule_count = 0;
  Vector3d rule_centre = Vector3d::Zero();  // centre for position rules
  double rule_radius = 1.0;

  FaceTag tag;
  int segment = -1;        // sweeps: the segment whose sweep surface this is
  bool at_vertex = false;  // front sweeps: the tool surface at `tool_point`
  Vector3d tool_point = Vector3d::Zero();
  int nu = 1, nv = 1;  // grid cells
  bool flip = false;
  Eigen::AlignedBox3d box;  // conservative bounds
};

/// cos and sin of t, remembered for the last t asked on this thread: a grid's nodes along a
/// tube's rulings share their angle, and the trimming asks for them row by row.
std::pair<double, double> cos_sin(double t) {
  thread_local double last = std::numeric_limits<double>::quiet_NaN(), last_cos = 1.0, last_sin = 0.0;
  if (t != last) {
    last = t;
    last_cos = std::cos(t);
    last_sin = std::sin(t);
  }
  return {last_cos, last_sin};
}

Vector3d evaluate(const Patch& p, double u, double v) {
  switch (p.form) {
    case Form::Plane:
      return p.o + u * p.U + v * p.V;
    case Form::Tube: {
      const auto [c, s] = cos_sin(p.t0 + v * (p.t1 - p.t0));
      return p.o + u * p.U + p.R * (c * p.e1 + s * p.e2);
    }
    case Form::Sphere: {
      if ((p.pole_v0 && v <= 0.0)) return p.o + p.R * std::cos(p.t0) * p.w;
      if ((p.pole_v1 && v >= 1.0)) return p.o + p.R * std::cos(p.t1) * p.w;
      const double f = p.f0 + u * (p.f1 - p.f0);
      const double t = p.t0 + v * (p.t1 - p.t0);
      return p.o + p.R * (std::sin(t) * (std::cos(f) * p.e1 + std::sin(f) * p.e2) + std::cos(t) * p.w);
    }
    case Form::Disc: {
      if (u <= 0.0) return p.o;
      const double f = 2.0 * M_PI * v;
      return p.o + (u * p.R) * (std::cos(f) * p.e1 + std::sin(f) * p.e2);
    }
    case Form::Triangle: {
      if (u <= 0.0) return p.o;
      return p.o + u * (p.U + v * p.V);
    }
  }
  return p.o;
}

/// Outward normal of the solid whose surface the patch is (tool or stock) at parameter (u, v).
Vector3d solid_normal(const Patch& p, double u, double v) {
  switch (p.form) {
    case Form::Tube: {
      const auto [c, s] = cos_sin(p.t0 + v * (p.t1 - p.t0));
      return c * p.e1 + s * p.e2;
    }
    case Form::Sphere:
      return (evaluate(p, u, v) - p.o) / p.R;
    default:
      return p.plane_normal;
  }
}

// Lower bound of a convex f over [lo, hi] from its values at lo <= x1 < x2 <= hi (f_lo, f_hi
// NaN where unknown): the secant through x1, x2 extended outwards bounds f beyond them, the
// secants through (lo, x1) and (x2, hi) extended inwards bound it between x1 and x2.
// -infinity if nothing is known.
double convex_lower_bound(double lo, double f_lo, double x1, double f1, double x2, double f2, double hi,
                          double f_hi) {
  const double inf = std::numeric_limits<double>::infinity();
  if (!(lo <= x1 && x1 < x2 && x2 <= hi)) return -inf;
  const double slope = (f2 - f1) / (x2 - x1);
  const double left = slope > 0.0 ? f1 - slope * (x1 - lo) : f1;
  const double right = slope < 0.0 ? f2 + slope * (hi - x2) : f2;
  const bool has_lo = !std::isnan(f_lo) && lo < x1, has_hi = !std::isnan(f_hi) && x2 < hi;
  double middle = -inf;
  if (has_lo || has_hi) {
    const double a1 = has_lo ? (f1 - f_lo) / (x1 - lo) : 0.0;  // f1 + a1 (t - x1) <= f(t), t >= x1
    const double a2 = has_hi ? (f_hi - f2) / (hi - x2) : 0.0;  // f2 + a2 (t - x2) <= f(t), t <= x2
    auto h = [&](double t) {
      return std::max(has_lo ? f1 + a1 * (t - x1) : -inf, has_hi ? f2 + a2 * (t - x2) : -inf);
    };
    middle = std::min(h(x1), h(x2));
    if (has_lo && has_hi && a1 != a2) {
      const double t = (f2 - f1 + a1 * x1 - a2 * x2) / (a1 - a2);
      if (t > x1 && t < x2) middle = std::min(middle, h(t));
    }
  }
  return std::min({left, middle, right});
}

// detail::golden_minimum of a convex f on [0, 1] (the same points, the same value), stopped as
// soon as convexity proves the minimum >= floor: then a lower bound of it that is >= floor.
// `margin` covers the rounding of f's values.
template <class F>
double golden_minimum_above(F&& f, double floor, double margin) {
  return detail::golden_minimum(std::forward<F>(f), 0.0, 1.0,
                                [&](const detail::GoldenBracket& b, double* value) {
                                  const double bound =
                                      convex_lower_bound(b.lo, b.f_lo, b.x1, b.f1, b.x2, b.f2, b.hi, b.f_hi);
                                  *value = bound - margin * (1.0 + std::abs(bound));
                                  return *value >= floor;
                                })
      .second;
}

/// The closed-form parts of a ball end's sweep distance at p: the tip's capsule (`ball`, the
/// distance wherever the body is no nearer) and a lower bound of the body sweep's distance.
struct BallEndParts {
  Vector3d c0, d;  // the tip sphere's centre at the start, and its move
  double ball;
  double body_lower;
  double margin = 0.0;  // rounding of the body's computed distances (0 where the tip decides)
};

BallEndParts ball_end_parts(const Tool& tool, const Vector3d& a, const Vector3d& b, const Vector3d& p) {
  BallEndParts parts;
  const Vector3d& d = parts.d = b - a;
  const double dd = d.squaredNorm();
  const double r = tool.radius;
  const Vector3d& c0 = parts.c0 = a + Vector3d(0, 0, r);
  const double tb = dd > 0.0 ? std::clamp((p - c0).dot(d) / dd, 0.0, 1.0) : 0.0;
  parts.ball = (p - (c0 + tb * d)).norm() - r;
  // Lower bounds of the body sweep's distance: it lies above the lowest centre, and within r
  // (horizontally) of the centres' horizontal track.
  const double lowest = std::min(c0.z(), c0.z() + d.z());
  // Below the lowest centre by more than the tip's distance the tip decides: every caller takes
  // the tip's value whatever the body's bound is, as long as it is no less.
  if (lowest - p.z() >= parts.ball) {
    parts.body_lower = lowest - p.z();
    return parts;
  }
  double across;
  {
    const Eigen::Vector2d ph(p.x() - c0.x(), p.y() - c0.y()), dh(d.x(), d.y());
    const double hh = dh.squaredNorm();
    const double th = hh > 0.0 ? std::clamp(ph.dot(dh) / hh, 0.0, 1.0) : 0.0;
    across = (ph - th * dh).norm() - r;
  }
  parts.body_lower = std::max(lowest - p.z(), across);
  // (Then the tip decides: the margin is not needed.)
  if (parts.body_lower >= parts.ball) return parts;
  // Rounding of the body's computed values, relative to the coordinates' magnitude: a bound
  // that clears it by this much is below every value the search could compute.
  parts.margin = 1e-12 * (1.0 + p.cwiseAbs().maxCoeff() + c0.cwiseAbs().maxCoeff() + d.cwiseAbs().maxCoeff());
  // A sharper bound: the body sweep lies in the vertical prism over that track widened by r (a
  // stadium), from the lowest centre to the highest centre plus the body length: the exact
  // distance to that prism, less the margin.
  const double highest = std::max(c0.z(), c0.z() + d.z()) + tool.length;
  const double vertical = std::max(lowest - p.z(), p.z() - highest);
  const double prism = std::sqrt(std::max(across, 0.0) * std::max(across, 0.0) +
                                 std::max(vertical, 0.0) * std::max(vertical, 0.0)) +
                       std::min(std::max(across, vertical), 0.0);
  parts.body_lower = prism - parts.margin * (1.0 + std::abs(prism));
  return parts;
}

// The exact swept-volume distance of morph/sweep_distance.h, evaluated faster where possible:
// the body's golden-section search only runs while a lower bound of the body's distance could
// beat the tip's capsule (closed form) and `cap`. Bit for bit the value of the full search
// wherever that is below `cap`; elsewhere possibly only a lower bound of it that is >= cap.
// `searches`, when given, counts the golden-section searches run (the cost of the value).
double sweep_distance(const Tool& tool, const Vector3d& a, const Vector3d& b, const Vector3d& p,
                      double cap = std::numeric_limits<double>::infinity(),
                      std::uint64_t* searches = nullptr) {
  if (tool.type == ToolType::Sphere) {
    const Vector3d d = b - a;
    const double dd = d.squaredNorm();
    const double t = dd > 0.0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
    return (p - (a + t * d)).norm() - tool.radius;
  }
  if (tool.type != ToolType::BallEnd) return swept_signed_distance(tool, a, b, p);
  const BallEndParts parts = ball_end_parts(tool, a, b, p);
  const double ball = parts.ball;
  // Where the body's bound is no less than the capsule, the full search returns the capsule's
  // value; where it is no less than the cap, it is a lower bound.
  if (parts.body_lower >= std::min(ball, cap)) return std::min(ball, parts.body_lower);
  const Vector3d &c0 = parts.c0, &d = parts.d;
  const double r = tool.radius;
  auto body = [&](double t) {
    return detail::capped_cylinder_distance(p - (c0 + t * d), r, 0.0, tool.length);
  };
  // The body distance is convex in t. Beside the body it is the horizontal distance to the
  // centre at the parameter nearest horizontally, within the parameters whose body spans p's
  // height: try that parameter and accept it if it is a local (hence global) minimum.
  {
    double t_lo = 0.0, t_hi = 1.0;
    const double rise = d.z(), below = p.z() - c0.z();  // need below - t*rise in [0, length]
    if (std::abs(rise) > 1e-15) {
      const double ta = below / rise, tb = (below - tool.length) / rise;
      t_lo = std::max(0.0, std::min(ta, tb));
      t_hi = std::min(1.0, std::max(ta, tb));
    }
    if (t_lo <= t_hi) {
      const Eigen::Vector2d ph(p.x() - c0.x(), p.y() - c0.y()), dh(d.x(), d.y());
      const double hh = dh.squaredNorm();
      const double t = std::clamp(hh > 0.0 ? ph.dot(dh) / hh : 0.5 * (t_lo + t_hi), t_lo, t_hi);
      const double f = body(t), h = 1e-9;
      if ((t - h < 0.0 || body(t - h) >= f) && (t + h > 1.0 || body(t + h) >= f)) return std::min(ball, f);
    }
  }
  // Otherwise golden section on the convex body distance along the move, stopped once the body
  // is proven no nearer than the tip (then the tip's value, as the full search gives it) or
  // than the cap (then a lower bound >= cap).
  if (searches) ++*searches;
  return std::min(ball, golden_minimum_above(body, std::min(ball, cap), parts.margin));
}

/// Cheap lower and upper bounds of sweep_distance: the tip's capsule bounds it from above, the
/// body's bound from below (both exact where the capsule is nearer than that bound).
std::pair<double, double> sweep_distance_bounds(const Tool& tool, const Vector3d& a, const Vector3d& b,
                                                const Vector3d& p) {
  if (tool.type != ToolType::BallEnd) {
    const double d = sweep_distance(tool, a, b, p);
    return {d, d};
  }
  const BallEndParts parts = ball_end_parts(tool, a, b, p);
  return {std::min(parts.ball, parts.body_lower), parts.ball};
}

/// A plane bounding a sphere's or a ball end's sweep from outside: the sweep lies in
/// {y : n.y <= h}, so n.x - h is a lower bound of its signed distance at every x (the sweep is
/// convex, |n| = 1; `h` includes a margin for the rounding of the distances and of the bound).
/// n is chosen to face `x` from the sweep, where the bound is nearly the distance. Other tools,
/// or x on the centre line: n = 0, h = infinity (no bound).
struct SupportPlane {
  Vector3d n = Vector3d::Zero();
  double h = std::numeric_limits<double>::infinity();
  double at(const Vector3d& x) const { return n.dot(x) - h; }
};

/// A sphere's or a ball end's sweep seen from outside: the tip's centre line c0 + t d (t in
/// [0, 1]) and radius; with n.z <= 0 the ball end's body (above the tip's centre, no wider)
/// adds nothing to the support function, which is then the capsule's.
struct Capsule {
  Vector3d c0 = Vector3d::Zero(), d = Vector3d::Zero();
  double inv_dd = 0.0;  // 1 / |d|^2, 0 for a point
  double r = 0.0;
  double margin = 0.0;  // rounding of the distances and of the bound (but for x's part)
  bool valid = false;   // a sphere or a ball end
  bool ballend = false;

  Capsule() = default;
  Capsule(const Tool& tool, const Vector3d& a, const Vector3d& b) {
    if (tool.type != ToolType::Sphere && tool.type != ToolType::BallEnd) return;
    valid = true;
    ballend = tool.type == ToolType::BallEnd;
    r = tool.radius;
    c0 = ballend ? Vector3d(a.x(), a.y(), a.z() + r) : a;
    d = b - a;
    const double dd = d.squaredNorm();
    inv_dd = dd > 0.0 ? 1.0 / dd : 0.0;
    margin = 1e-12 * (1.0 + c0.cwiseAbs().maxCoeff() + d.cwiseAbs().maxCoeff() + r + tool.length);
  }
  /// The centre line's unit direction (zero for a point) and its length.
  std::pair<Vector3d, double> unit_axis() const {
    const double length = d.norm();
    return {length > 0.0 ? Vector3d(d / length) : Vector3d::Zero(), length};
  }
};

/// Whether the sweep's signed distance at x is at least `bound` (false: not shown), from closed
/// forms without square roots: the tip's capsule, and for a ball end the body's bounds (above the
/// lowest centre, within r horizontally of the centres' track). No bound where `bound` is not
/// finite or the capsule is not valid.
bool sweep_at_least(const Capsule& c, const Vector3d& x, double bound) {
  if (!c.valid || !(bound < std::numeric_limits<double>::infinity())) return false;
  const double reach = bound + c.r;  // the capsule: |x - centre| - r >= bound
  if (reach > 0.0) {
    const double t = std::clamp((x - c.c0).dot(c.d) * c.inv_dd, 0.0, 1.0);
    if ((x - (c.c0 + t * c.d)).squaredNorm() < reach * reach) return false;
  }
  if (!c.ballend) return true;
  const double lowest = std::min(c.c0.z(), c.c0.z() + c.d.z());
  if (lowest - x.z() >= bound || reach <= 0.0) return true;
  const Eigen::Vector2d ph(x.x() - c.c0.x(), x.y() - c.c0.y()), dh(c.d.x(), c.d.y());
  const double hh = dh.squaredNorm();
  const double th = hh > 0.0 ? std::clamp(ph.dot(dh) / hh, 0.0, 1.0) : 0.0;
  return (ph - th * dh).squaredNorm() >= reach * reach;
}

/// The support plane of the sweep facing x (`x_margin`: 1e-12 |x|, the rounding of n.x).
SupportPlane support_plane(const Capsule& c, const Vector3d& x, double x_margin) {
  SupportPlane plane;
  if (!c.valid) return plane;
  const double t = std::clamp((x - c.c0).dot(c.d) * c.inv_dd, 0.0, 1.0);
  Vector3d n = x - (c.c0 + t * c.d);
  // Above the tip's centre a ball end's body is nearer: face x horizontally.
  if (c.ballend && n.z() > 0.0) n.z() = 0.0;
  const double length = n.norm();
  if (!(length > 1e-9 * c.r)) return plane;
  n /= length;
  const double base = n.dot(c.c0), along = n.dot(c.d);
  plane.n = n;
  plane.h = base + std::max(0.0, along) + c.r + c.margin + x_margin;
  return plane;
}

/// Everything a patch's trimming function needs, shared read-only by all threads.
struct Context {
  const Job* job = nullptr;
  std::vector<Segment> segments;
  std::vector<Capsule> capsules;  // per segment, for support planes
  AabbTree tree;
  std::optional<MeshDistance> stock_mesh;
  Eigen::AlignedBox3d stock_box;
  double tie = 1e-9;            // coincident-surface tie-break distance
  double max_depth = 0.0;       // deepest possible sweep distance (largest radius + tie)
  double trim_tolerance = 0.0;  // the job's tolerance: scale of the features worth resolving

  double stock_distance(const Vector3d& x) const {
    if (stock_mesh) return stock_mesh->signed_distance(x);
    return analytic_signed_distance(job->stock, x);
  }
};

/// A depth at which x lies inside segment j's sweep (negative: not shown inside): the depth in
/// the tip's capsule, or in the ball end's body at the tool position nearest horizontally. Each
/// is a convex piece of the sweep.
double certified_depth(const Context& ctx, int j, const Vector3d& x) {
  const Capsule& c = ctx.capsules[static_cast<std::size_t>(j)];
  const double t = std::clamp((x - c.c0).dot(c.d) * c.inv_dd, 0.0, 1.0);
  double depth = c.r - (x - (c.c0 + t * c.d)).norm();
  if (c.ballend) {
    const Eigen::Vector2d ph(x.x() - c.c0.x(), x.y() - c.c0.y()), dh(c.d.x(), c.d.y());
    const double hh = dh.squaredNorm();
    const double th = hh > 0.0 ? std::clamp(ph.dot(dh) / hh, 0.0, 1.0) : 0.0;
    const double length = ctx.segments[static_cast<std::size_t>(j)].tool->length;
    depth = std::max(depth, -detail::capped_cylinder_distance(x - (c.c0 + th * c.d), c.r, 0.0, length));
  }
  return depth;
}

/// Whether segment j's sweep holds, beyond the tie shifts, every point within `gap` of the convex
/// hull of `corners`: each corner lies at least `gap` (and a margin) inside a convex piece of the
/// sweep, and the sweep is convex, so it holds the hull of those balls.
bool sweep_holds(const Context& ctx, int j, const std::array<Vector3d, 4>& corners, double gap) {
  if (!ctx.capsules[static_cast<std::size_t>(j)].valid) return false;
  const double need = gap + 1e3 * ctx.tie;
  for (const Vector3d& x : corners)
    if (certified_depth(ctx, j, x) < need) return false;
  return true;
}

/// Whether some segment's sweep (not one the patch leaves out) holds every point within `gap` of
/// the convex hull of `corners` (see sweep_holds): g < 0 there.
bool inside_one_sweep(const Context& ctx, const Patch& patch, const std::array<Vector3d, 4>& corners,
                      double gap) {
  Eigen::AlignedBox3d box(corners[0]);
  for (const Vector3d& x : corners) box.extend(x);
  bool inside = false;
  ctx.tree.for_each_overlapping(box, [&](std::size_t j) {
    const int js = static_cast<int>(j);
    if (inside || js == patch.exclude[0] || js == patch.exclude[1]) return;
    inside = sweep_holds(ctx, js, corners, gap);
  });
  return inside;
}

/// The angles the patch's parameters u and v turn through (0 along straight lines).
std::array<double, 2> parameter_angles(const Patch& p) {
  switch (p.form) {
    case Form::Tube:
      return {0.0, std::abs(p.t1 - p.t0)};
    case Form::Sphere:
      return {std::abs(p.f1 - p.f0), std::abs(p.t1 - p.t0)};
    case Form::Disc:
      return {0.0, 2.0 * M_PI};
    default:
      return {0.0, 0.0};
  }
}

/// How far the image of the parameter block [u0, u1] x [v0, v1] can lie from the convex hull
/// of its corners' images; infinity where no bound is known (arcs of a half turn or more).
double hull_gap(const Patch& p, double u0, double u1, double v0, double v1) {
  // Sagitta of a circular arc of the given radius and angle (infinity from a half turn on).
  auto sagitta = [](double radius, double angle) {
    return angle < M_PI ? radius * (1.0 - std::cos(0.5 * angle)) : std::numeric_limits<double>::infinity();
  };
  switch (p.form) {
    case Form::Plane:
    case Form::Triangle:  // bilinear: inside the hull
      return 0.0;
    case Form::Tube:  // straight along u; along v an arc, within its sagitta of its chord
      return sagitta(p.R, std::abs(p.t1 - p.t0) * (v1 - v0));
    case Form::Sphere:  // a parallel's arc near the chord between two meridians' arcs, each near its chord
      return sagitta(p.R, std::abs(p.f1 - p.f0) * (u1 - u0)) +
             sagitta(p.R, std::abs(p.t1 - p.t0) * (v1 - v0));
    case Form::Disc:  // straight along u; along v an arc of radius at most u1 R
      return sagitta(u1 * p.R, 2.0 * M_PI * (v1 - v0));
  }
  return std::numeric_limits<double>::infinity();
}

/// Per-patch evaluator of the keep function g: g > 0 where the patch bounds the result.
class Trimmer {
 public:
  Trimmer(const Context& ctx, const Patch& patch) : ctx_(ctx), patch_(patch) {
    std::size_t count = 0;
    ctx.tree.for_each_overlapping(patch.box, [&](std::size_t j) {
      const int js = static_cast<int>(j);
      if (js == patch.exclude[0] || js == patch.exclude[1]) return;
      if (++count <= kListLimit) candidates_.push_back(js);
    });
    // Few candidates: test them in a list; many (stock faces): best-first search of the BVH.
    use_tree_ = count > kListLimit;
    if (use_tree_) candidates_.clear();
    std::sort(candidates_.begin(), candidates_.end());
  }

  /// Terms of g: the stock, the patch's own rules, and the sweep of segment j >= 0.
  static constexpr int kStockTerm = -1;
  static constexpr int kRuleTerm = -2;  // rule r is kRuleTerm - r
  static constexpr int kNoTerm = std::numeric_limits<int>::min();

  double operator()(double u, double v) const { return evaluate_with_term(u, v, nullptr); }

  /// Whether the sweep terms come from the tree's search (many candidates), not from a list.
  bool searches_tree() const { return use_tree_; }

  /// An upper bound of g at (u, v) without the tree's search: the patch's own terms, and each
  /// sweep whose bounds hold X(u, v) by its tip's capsule (which the sweep holds; a tie shift
  /// and rounding above it at most). Nearly exact inside another move's tip.
  double upper_bound(double u, double v) const {
    const Vector3d x = evaluate(patch_, u, v);
    return std::min(own_terms(x, u, v), tips_upper_bound(x));
  }

  /// g and, if `term` is given, which term attains it (the trimming curve through a root of g
  /// lies on that term's surface).
  double evaluate_with_term(double u, double v, int* term) const {
    const Vector3d x = evaluate(patch_, u, v);
    int active = kNoTerm;
    double g = own_terms(x, u, v, &active);
    // Clearly removed by the stock or a rule: no need for the sweeps. Near zero they decide
    // (a root of the stock's term inside another sweep is no root of g).
    if (g < -1e3 * ctx_.tie && !term) return g;
    if (use_tree_) {
      double best = std::numeric_limits<double>::infinity();
      const std::int64_t item = nearest_sweep_term(x, u, v, &best);
      if (best < g) {
        g = best;
        active = static_cast<int>(item);
      }
    } else {
      for (int j : candidates_) {
        // Inside its bounds a sweep may be nearer than any bound says (down to -max_depth):
        // skipping it there would make g's zero set that of a shallower sweep.
        const double outside = ctx_.segments[j].box.exteriorDistance(x);
        if ((outside > 0.0 ? outside : -ctx_.max_depth) >= g) continue;
        const double d = distance(j, x, u, v, g);
        if (d < g) {
          g = d;
          active = j;
        }
      }
    }
    if (term) *term = active;
    return g;
  }

  /// A sweep term of g and a lower bound of its distance at the centre of the list holding it.
  struct SweepTerm {
    int segment;
    double lower;
    SupportPlane plane;  // a lower bound of its distance anywhere (less two ties)
  };
  /// Sweep terms, the one of least `lower` first, their centre, and an upper bound of the least
  /// of their distances there (infinity if unknown).
  struct TermList {
    const SweepTerm* terms;
    std::size_t count;
    Vector3d centre;
    double upper;
  };

  /// The same value as operator() from the sweep terms in `list` alone, wherever the list holds
  /// every term that can be the least one at (u, v) (a block's list, see near_terms). The list
  /// is searched for its exact minimum, the nearest term first, skipping the terms whose bound
  /// (their bound at the centre less the distance moved, the distances being 1-Lipschitz but
  /// for the tie shift's jumps) shows that they cannot be below it. That minimum is the full
  /// searches' value unless they skip the term attaining it (its box's bound above it, by
  /// rounding or the tie shift): then the full search decides.
  double operator()(double u, double v, const TermList& list) const {
    return evaluate_with_term(u, v, list, nullptr);
  }

  /// The same value and term as evaluate_with_term(u, v, term) from the sweep terms in `list`
  /// alone (see operator() above). The term attaining the minimum is the full searches' one
  /// when no other term ties with it; with a tie the full search decides (its order breaks it).
  double evaluate_with_term(double u, double v, const TermList& list, int* term) const {
    const Vector3d x = evaluate(patch_, u, v);
    int own_term = kNoTerm;
    const double own = own_terms(x, u, v, &own_term);
    if (own < -1e3 * ctx_.tie && !term) return own;
    const double moved = (x - list.centre).norm() + 4.0 * ctx_.tie;
    // The least distance is below `cap` (the list's bound moved along): distances beyond it
    // need no exact values.
    const double cap = list.upper + moved;
    const double inf = std::numeric_limits<double>::infinity();
    double best = inf;
    int best_term = kNoTerm;
    bool found = true;  // the full search reaches the term attaining `best`
    bool tied = false;  // another term attains `best` too
    for (std::size_t k = 0; k < list.count; ++k) {
      const int j = list.terms[k].segment;
      // With a term, distances equal to the least are exact too (ties show).
      const double least = std::min({own, best, cap});
      const double below = term ? std::nextafter(least, inf) : least;
      if (list.terms[k].lower - moved >= below) continue;
      if (list.terms[k].plane.at(x) - 2.0 * ctx_.tie >= below) continue;
      const double bound = box_bound(j, x);
      if (bound - 2.0 * ctx_.tie >= below) continue;
      const double d = distance(j, x, u, v, below);
      if (d < best) {
        best = d;
        best_term = j;
        found = bound <= d;
        tied = false;
      } else if (d == best) {
        tied = true;
      }
    }
    if (!(best < own)) {
      if (term) *term = own_term;
      return own;
    }
    if (!found || (term && tied)) return evaluate_with_term(u, v, term);
    if (term) *term = best_term;
    return best;
  }

  /// At x = X(u, v): writes to `near` the terms of `list` whose distance there is at most `slack`
  /// above the least distance of them (their `lower`: a bound of it), and returns an
  /// upper bound of that least distance. The other terms of `list` cannot be the least one
  /// anywhere within (slack - 4 ties) / 2 of that point. With `fresh_planes` the terms' support
  /// planes are made to face X(u, v) (tight near it), else they keep those of `list`.
  double near_terms(const Vector3d& x, const TermList& list, double slack, std::vector<SweepTerm>& near,
                    bool fresh_planes = true) const {
    const double moved = (x - list.centre).norm() + 4.0 * ctx_.tie;
    near.clear();
    double best = list.upper + moved;
    // `best`: an upper bound of the least distance; each term kept with a lower bound of its
    // own (cheap bounds: the exact distances only matter for the values). First the bounds that
    // cost no distance: the list's, the support plane's, the box's.
    for (std::size_t k = 0; k < list.count; ++k) {
      const int j = list.terms[k].segment;
      const double below = best + slack;
      if (list.terms[k].lower - moved >= below) continue;
      const double plane = list.terms[k].plane.at(x) - 2.0 * ctx_.tie;
      if (plane >= below) continue;
      // The box only where no plane is known (a plane beats it where there is one).
      if (std::isinf(list.terms[k].plane.h) && box_bound(j, x) - 2.0 * ctx_.tie >= below) continue;
      near.push_back({j, plane, list.terms[k].plane});
    }
    // Then the tip's capsule (an upper bound) and the body's bound for the terms that can lower
    // `best` (a plane bound at or above it shows that a term cannot), the least bound first.
    auto refine = [&](SweepTerm& t) {
      const Segment& s = ctx_.segments[t.segment];
      const auto [lower, upper] = sweep_distance_bounds(*s.tool, s.a, s.b, x);
      best = std::min(best, upper + ctx_.tie);
      t.lower = std::max(t.lower, lower - ctx_.tie);
    };
    if (!near.empty()) {
      const auto first = std::min_element(
          near.begin(), near.end(), [](const SweepTerm& a, const SweepTerm& b) { return a.lower < b.lower; });
      refine(*first);
      for (SweepTerm& t : near)
        if (&t != &*first && t.lower < best) refine(t);
    }
    near.erase(
        std::remove_if(near.begin(), near.end(), [&](const SweepTerm& t) { return t.lower > best + slack; }),
        near.end());
    if (fresh_planes) {
      const double margin = x_margin(x);
      for (SweepTerm& t : near) t.plane = plane_at(t.segment, x, margin);
    }
    nearest_first(near);
    return best;
  }

  /// The sweep terms of g (all candidates, or from the tree those near enough) that can be the
  /// least one anywhere within `radius` of X(u, v), with their boxes' bounds there; `upper`: an
  /// upper bound of the least distance there.
  std::vector<SweepTerm> terms_within(double u, double v, double radius, double* upper) const {
    const Vector3d x = evaluate(patch_, u, v);
    std::vector<SweepTerm> terms;
    *upper = std::numeric_limits<double>::infinity();
    if (!use_tree_) {
      for (int j : candidates_)
        terms.push_back({j, box_bound(j, x) - 2.0 * ctx_.tie, plane_at(j, x, x_margin(x))});
      nearest_first(terms);
      return terms;
    }
    // Any upper bound of the least distance makes a list holding every term that can be the
    // least (a few more at most): the tips' bound, else the tree's search.
    double best = tips_upper_bound(x);
    if (!std::isfinite(best)) nearest_sweep_term(x, u, v, &best);
    if (!std::isfinite(best)) return terms;
    *upper = best;
    // Within `radius` every term is within radius (and a tie jump) of its value at x.
    const double reach = best + 2.0 * radius + 4.0 * ctx_.tie;
    const double margin = x_margin(x);
    Eigen::AlignedBox3d query(x);
    query.min().array() -= std::max(reach, 0.0) + 2.0 * ctx_.tie;
    query.max().array() += std::max(reach, 0.0) + 2.0 * ctx_.tie;
    ctx_.tree.for_each_overlapping(query, [&](std::size_t j) {
      const int js = static_cast<int>(j);
      if (js == patch_.exclude[0] || js == patch_.exclude[1]) return;
      const double box = box_bound(js, x);
      if (box - 2.0 * ctx_.tie > reach) return;
      // The plane facing x bounds the distance there nearly exactly (the box barely, its sweep
      // reaching a tool length above the tip).
      const SupportPlane plane = plane_at(js, x, margin);
      const double lower = std::max(box, plane.at(x)) - 2.0 * ctx_.tie;
      if (lower <= reach) terms.push_back({js, lower, plane});
    });
    nearest_first(terms);
    return terms;
  }

  /// Lipschitz constant in space of the exact minimum of g's terms on the patch: the distances
  /// are 1-Lipschitz, position rules |dir| / rule_radius, normal rules |dir| / R on spheres and
  /// right tubes (constant on flat patches). Infinity where no bound is known (normal rules on
  /// oblique tubes): then no block is proven.
  double lipschitz() const {
    double l = 1.0;
    for (int r = 0; r < patch_.rule_count; ++r) {
      const OwnRule& rule = patch_.rules[r];
      const double length = rule.dir.norm();
      if (rule.position) {
        l = std::max(l, length / patch_.rule_radius);
      } else if (patch_.form == Form::Sphere ||
                 (patch_.form == Form::Tube && std::abs(patch_.U.dot(patch_.e1)) <= 1e-12 * patch_.U.norm() &&
                  std::abs(patch_.U.dot(patch_.e2)) <= 1e-12 * patch_.U.norm())) {
        l = std::max(l, length / patch_.R);
      } else if (patch_.form == Form::Tube) {
        l = std::numeric_limits<double>::infinity();
      }
    }
    return l;
  }

  /// Whether one sweep term of `list` holds, beyond the tie shifts, every point within `gap` of
  /// the convex hull of `corners`: then g < 0 all over that set. Each corner must lie at least
  /// `gap` (and a margin) inside a convex piece of the sweep (its tip's capsule, or the tool's body
  /// at one position); the sweep is convex, so it holds the hull of those balls.
  bool inside_one_sweep(const TermList& list, const std::array<Vector3d, 4>& corners, double gap) const {
    const double need = gap + 1e3 * ctx_.tie;
    for (std::size_t k = 0; k < list.count; ++k) {
      const SweepTerm& term = list.terms[k];
      const Capsule& c = ctx_.capsules[static_cast<std::size_t>(term.segment)];
      if (!c.valid) continue;
      bool inside = true;
      for (const Vector3d& x : corners) {
        // The plane bounds the distance from below: a corner it puts less than `need` deep is not.
        if (term.plane.at(x) - 2.0 * ctx_.tie > -need || certified_depth(ctx_, term.segment, x) < need) {
          inside = false;
          break;
        }
      }
      if (inside) return true;
    }
    return false;
  }

  /// The least of g's terms that are no sweep's (the stock, the patch's own rules) at (u, v):
  /// +infinity on stock faces.
  double own_value(double u, double v) const { return own_terms(evaluate(patch_, u, v), u, v); }

  /// Whether segment j's tie shift leans to keeping at (u, v) beyond doubt: j is a move next to
  /// the patch's own (a side sweep's), and its sweep's normal faces the same way as the patch's
  /// (well away from the gradient test's zero).
  bool tie_keeps(int j, double u, double v) const {
    if (!patch_.sweep || patch_.at_vertex || (j != patch_.adjacent[0] && j != patch_.adjacent[1]))
      return false;
    const Vector3d gradient = sweep_gradient(ctx_.segments[j], evaluate(patch_, u, v));
    return gradient.dot(solid_normal(patch_, u, v)) > 0.5 * gradient.norm();
  }

  /// The value of one term of g at (u, v).
  double term_value(int term, double u, double v) const {
    const Vector3d x = evaluate(patch_, u, v);
    if (term == kStockTerm) return -ctx_.stock_distance(x) - ctx_.tie;
    if (term <= kRuleTerm) return rule_value(kRuleTerm - term, x, u, v);
    return distance(term, x, u, v);
  }

  /// The golden-section searches the distances asked so far ran (ErodeOptions::search_limit).
  std::uint64_t searches() const { return searches_; }

 private:
  static constexpr std::size_t kListLimit = 64;
  // An upper bound of the least sweep term at x from the sweeps whose bounds hold x: the tip's
  // capsule lies in the sweep (its distance is the sweep's where the tip decides), and the term
  // is at most a tie shift and rounding above the sweep's distance. Infinity if none holds x.
  double tips_upper_bound(const Vector3d& x) const {
    double least = std::numeric_limits<double>::infinity();
    ctx_.tree.for_each_overlapping(Eigen::AlignedBox3d(x, x), [&](std::size_t j) {
      const int js = static_cast<int>(j);
      if (js == patch_.exclude[0] || js == patch_.exclude[1]) return;
      const Capsule& c = ctx_.capsules[j];
      if (!c.valid) return;
      const double t = std::clamp((x - c.c0).dot(c.d) * c.inv_dd, 0.0, 1.0);
      least = std::min(least, (x - (c.c0 + t * c.d)).norm() - c.r + 2.0 * c.margin + 2.0 * ctx_.tie);
    });
    return least;
  }
  // The tree's best-first search for the least sweep term at x (the patch's own segments left
  // out). `best` follows the search's own minimum: a distance capped there changes no decision
  // of the search (it updates on smaller values only, which the cap leaves exact).
  std::int64_t nearest_sweep_term(const Vector3d& x, double u, double v, double* best) const {
    return ctx_.tree.nearest(
        x,
        [&](std::size_t j) {
          const int js = static_cast<int>(j);
          if (js == patch_.exclude[0] || js == patch_.exclude[1])
            return std::numeric_limits<double>::infinity();
          // Proven no nearer than the least so far (the tie shift included): it cannot win.
          if (sweep_at_least(ctx_.capsules[j], x, *best + 2.0 * ctx_.tie + 1e3 * ctx_.tie))
            return std::numeric_limits<double>::infinity();
          const double d = distance(js, x, u, v, *best);
          *best = std::min(*best, d);
          return d;
        },
        best, ctx_.max_depth);
  }
  // The least of the terms that are no sweep's: the stock and the patch's own rules (sweep
  // patches only; +infinity and kNoTerm otherwise).
  double own_terms(const Vector3d& x, double u, double v, int* which) const {
    double least = std::numeric_limits<double>::infinity();
    *which = kNoTerm;
    if (!patch_.sweep) return least;
    least = -ctx_.stock_distance(x) - ctx_.tie;
    *which = kStockTerm;
    for (int r = 0; r < patch_.rule_count; ++r) {
      const double value = rule_value(r, x, u, v);
      if (value < least) {
        least = value;
        *which = kRuleTerm - r;
      }
    }
    return least;
  }
  // Moves the term of least bound to the front: searched first, it makes the cap of the
  // other distances tight. (The values do not depend on the order.)
  static void nearest_first(std::vector<SweepTerm>& terms) {
    const auto nearest =
        std::min_element(terms.begin(), terms.end(), [](const SweepTerm& a, const SweepTerm& b) {
          return a.lower < b.lower || (a.lower == b.lower && a.segment < b.segment);
        });
    if (nearest != terms.end()) std::iter_swap(terms.begin(), nearest);
  }
  // The stock's and the rules' terms of g, as evaluate_with_term takes their minimum.
  double own_terms(const Vector3d& x, double u, double v) const {
    if (!patch_.sweep) return std::numeric_limits<double>::infinity();
    double g = -ctx_.stock_distance(x) - ctx_.tie;
    for (int r = 0; r < patch_.rule_count; ++r) g = std::min(g, rule_value(r, x, u, v));
    return g;
  }
  SupportPlane plane_at(int j, const Vector3d& x, double margin) const {
    return support_plane(ctx_.capsules[static_cast<std::size_t>(j)], x, margin);
  }
  static double x_margin(const Vector3d& x) { return 1e-12 * x.cwiseAbs().maxCoeff(); }
  // The searches' lower bound of segment j's distance: its box's exterior distance, -max_depth
  // inside the box. Less two ties it is a true lower bound (the tie shift, rounding).
  double box_bound(int j, const Vector3d& x) const {
    const double outside = ctx_.segments[j].box.exteriorDistance(x);
    return outside > 0.0 ? outside : -ctx_.max_depth;
  }
  double rule_value(int r, const Vector3d& x, double u, double v) const {
    const OwnRule& rule = patch_.rules[r];
    if (rule.position) return (x - patch_.rule_centre).dot(rule.dir) / patch_.rule_radius;
    // On a sphere the normal from x = X(u, v) itself: solid_normal's value, without evaluating X again.
    if (patch_.form == Form::Sphere) return ((x - patch_.o) / patch_.R).dot(rule.dir);
    return solid_normal(patch_, u, v).dot(rule.dir);
  }
  // Distance to segment j's sweep, shifted by the tie-break where the patch lies on that sweep's
  // surface. Facing the same way (a repeated pass; a sweep inside the stock reaching one of its
  // faces) the surfaces coincide and one of them bounds the result: of two sweeps the lower
  // segment's, of a sweep and the stock neither (the material up to the face is gone). Facing
  // each other (two passes touching, a pass grazing a face from outside) the contact is interior
  // to the union of the sweeps, or to the stock: the sweeps lose it, the stock face keeps it.
  // `below`: the value is only needed where it is below `below`; elsewhere the result is some
  // value >= below (a search capped there cannot tell the minimum apart from it).
  double distance(int j, const Vector3d& x, double u, double v,
                  double below = std::numeric_limits<double>::infinity()) const {
    const Segment& s = ctx_.segments[j];
    // The shift is at least -tie: any distance from cap on ends at or above `below`.
    const double cap = below + 2.0 * ctx_.tie;
    const double d = sweep_distance(*s.tool, s.a, s.b, x, cap, &searches_);
    if (d >= cap) return d - ctx_.tie;
    bool lean_keep = j > patch_.owner || j == patch_.adjacent[0] || j == patch_.adjacent[1];
    if (std::abs(d) <= 4.0 * ctx_.tie) {
      const bool same_side = sweep_gradient(s, x).dot(solid_normal(patch_, u, v)) > 0.0;
      lean_keep = patch_.sweep ? (same_side && lean_keep) : !same_side;
      // The tool at a path vertex touching another move's side from inside (a corner lying on a
      // later pass) is inside that sweep but for the contact curve: keeping a tie-wide band of
      // it would leave a sliver. Only another tool position (a repeated corner) ties with it.
      if (patch_.at_vertex && lean_keep && touches_side_of(s, x)) lean_keep = false;
    } else if (!patch_.sweep) {
      lean_keep = true;
    }
    return d + (lean_keep ? ctx_.tie : -ctx_.tie);
  }
  // Whether x is nearest to an inner tool position of the segment rather than to an end.
  static bool touches_side_of(const Segment& s, const Vector3d& x) {
    const Vector3d ab = s.b - s.a;
    const Vector3d lift =
        s.tool->type == ToolType::BallEnd ? Vector3d(s.tool->radius * Vector3d::UnitZ()) : Vector3d::Zero();
    const double t = (x - s.a - lift).dot(ab) / ab.squaredNorm();
    return t > 1e-9 && t < 1.0 - 1e-9;
  }
  // Outward normal of a segment's sweep near its surface (central differences of the distance,
  // steps far above rounding and far below the tool's curvature radius).
  Vector3d sweep_gradient(const Segment& s, const Vector3d& x) const {
    const double h = 1e-6 * s.tool->radius;
    Vector3d gradient;
    for (int k = 0; k < 3; ++k) {
      const Vector3d step = h * Vector3d::Unit(k);
      gradient[k] = sweep_distance(*s.tool, s.a, s.b, x + step, kNoCap, &searches_) -
                    sweep_distance(*s.tool, s.a, s.b, x - step, kNoCap, &searches_);
    }
    return gradient;
  }
  static constexpr double kNoCap = std::numeric_limits<double>::infinity();
  const Context& ctx_;
  const Patch& patch_;
  mutable std::uint64_t searches_ = 0;  ///< golden-section searches of the distances asked
  std::vector<int> candidates_;
  bool use_tree_ = false;
};

struct PatchMesh {
  std::vector<Vector3d> vertices;
  std::vector<Triangle> triangles;
  std::vector<std::uint8_t> border;  // per triangle: bit k set if edge k -> k+1 is on the patch's border
  std::uint64_t searches = 0;        // the golden-section searches its trimming ran
};

void mark_border(PatchMesh& mesh) {
  std::vector<std::uint64_t> keys;
  keys.reserve(mesh.triangles.size() * 3);
  auto key = [](std::uint32_t a, std::uint32_t b) { return (static_cast<std::uint64_t>(a) << 32) | b; };
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) keys.push_back(key(t[k], t[(k + 1) % 3]));
  std::sort(keys.begin(), keys.end());
  mesh.border.assign(mesh.triangles.size(), 0);
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Triangle& t = mesh.triangles[i];
    for (int k = 0; k < 3; ++k)
      if (!std::binary_search(keys.begin(), keys.end(), key(t[(k + 1) % 3], t[k]))) mesh.border[i] |= 1u << k;
  }
}

/// Parameter in [0, 1] of the root of g along an edge whose ends have values g0, g1 of opposite
/// signs; `at(s)` gives the (u, v) of edge parameter s. Illinois false position with bisection.
template <class G, class At>
double edge_root(G&& g, double g0, double g1, At&& at) {
  double a = 0.0, b = 1.0, ga = g0, gb = g1;
  int side = 0;
  double t = 0.5;
  for (int it = 0; it < 80; ++it) {
    t = (std::abs(ga - gb) > 0.0) ? (a * gb - b * ga) / (gb - ga) : 0.5 * (a + b);
    if (!(t > a && t < b) || it % 4 == 3) t = 0.5 * (a + b);
    const std::array<double, 2> uv = at(t);
    const double gt = g(uv[0], uv[1]);
    if (std::abs(gt) < 1e-12 || b - a < 1e-13) break;
    if ((gt > 0.0) == (ga > 0.0)) {
      a = t;
      ga = gt;
      if (side == -1) gb *= 0.5;
      side = -1;
    } else {
      b = t;
      gb = gt;
      if (side == 1) ga *= 0.5;
      side = 1;
    }
  }
  return t;
}

/// Marching squares over the patch's grid: keeps the part where g > 0.
/// Largest speed of the patch's parametrisation along u and along v (job units per unit of
/// parameter): a grid edge's image is no longer than its parameter length times this.
std::array<double, 2> parameter_speeds(const Patch& p) {
  switch (p.form) {
    case Form::Plane:
      return {p.U.norm(), p.V.norm()};
    case Form::Tube:
      return {p.U.norm(), p.R * std::abs(p.t1 - p.t0)};
    case Form::Sphere:
      return {p.R * std::abs(p.f1 - p.f0), p.R * std::abs(p.t1 - p.t0)};
    case Form::Disc:
      return {p.R, 2.0 * M_PI * p.R};
    case Form::Triangle:
      return {p.U.norm() + p.V.norm(), p.V.norm()};
  }
  return {0.0, 0.0};
}

/// Upper bound of |X(u, v) - X(centre)| over the parameter block [u0, u1] x [v0, v1], X = the
/// patch's parametrisation. Curved images are not in the convex hull of the corners' images, so
/// the bounds come from the parametrisation: chords of the arcs, the ruling's length.
double block_radius(const Patch& p, double u0, double u1, double v0, double v1) {
  const double hu = 0.5 * (u1 - u0), hv = 0.5 * (v1 - v0);
  // Chord of a circular arc of the given radius and angle (the longest one if angle >= pi).
  auto chord = [](double radius, double angle) {
    return 2.0 * radius * std::sin(0.5 * std::min(angle, M_PI));
  };
  switch (p.form) {
    case Form::Plane:  // a parallelogram: farthest at a corner
      return std::max((hu * p.U + hv * p.V).norm(), (hu * p.U - hv * p.V).norm());
    case Form::Triangle: {  // bilinear: inside the convex hull of the corners' images
      const Vector3d centre = evaluate(p, u0 + hu, v0 + hv);
      double radius = 0.0;
      for (double u : {u0, u1})
        for (double v : {v0, v1}) radius = std::max(radius, (evaluate(p, u, v) - centre).norm());
      return radius;
    }
    case Form::Tube: {
      // Displacement a + b: a along the axis U, b a chord of the circle (in the e1-e2 plane);
      // a.b <= |a||b| times the cosine between U and that plane.
      const double length = p.U.norm();
      const double along = length * hu;
      const double across = chord(p.R, std::abs(p.t1 - p.t0) * hv);
      const double in_plane =
          length > 0.0 ? std::min(1.0, std::hypot(p.U.dot(p.e1), p.U.dot(p.e2)) / length) : 0.0;
      return std::sqrt(along * along + across * across + 2.0 * in_plane * along * across);
    }
    case Form::Sphere: {
      // Along the meridian to the polar angle, then along that parallel: an arc no longer than
      // the polar half-range plus the azimuth half-range times the largest sin on the block.
      const double pa = p.t0 + v0 * (p.t1 - p.t0), pb = p.t0 + v1 * (p.t1 - p.t0);
      const double lo = std::min(pa, pb), hi = std::max(pa, pb);
      double max_sin = 1.0;
      if (lo >= 0.0 && hi <= M_PI && !(lo <= 0.5 * M_PI && hi >= 0.5 * M_PI))
        max_sin = std::max(std::sin(lo), std::sin(hi));
      return chord(p.R, std::abs(p.t1 - p.t0) * hv + max_sin * std::abs(p.f1 - p.f0) * hu);
    }
    case Form::Disc:  // radially, then along the circle (of radius at most u1 R)
      return p.R * hu + chord(p.R * u1, 2.0 * M_PI * hv);
  }
  return std::numeric_limits<double>::infinity();
}

/// The image of a grid edge, exactly as `evaluate` traces it: a straight segment from `a` to `b`,
/// or an arc `centre + radius (cos t e1 + sin t e2)`, t from `t0` to `t1`.
struct EdgeCurve {
  bool arc = false;
  Vector3d a = Vector3d::Zero(), b = Vector3d::Zero();
  Vector3d centre = Vector3d::Zero(), e1 = Vector3d::UnitX(), e2 = Vector3d::UnitY();
  double radius = 0.0, t0 = 0.0, t1 = 0.0;
  // cos t and sin t at the ends of kArcPieces equal pieces of [t0, t1] (arcs), shared by the bounds.
  static constexpr int kArcPieces = 8;
  std::array<double, kArcPieces + 1> cos_at{}, sin_at{};
};

/// The image of the grid edge from (u0, v0) to (u1, v1) (one of them constant).
EdgeCurve edge_curve(const Patch& p, double u0, double v0, double u1, double v1) {
  EdgeCurve c;
  c.a = evaluate(p, u0, v0);
  c.b = evaluate(p, u1, v1);
  const bool along_u = v0 == v1;
  switch (p.form) {
    case Form::Tube:  // straight along u; around the axis along v
      if (!along_u) {
        c.arc = true;
        c.centre = p.o + u0 * p.U;
        c.e1 = p.e1;
        c.e2 = p.e2;
        c.radius = p.R;
        c.t0 = p.t0 + v0 * (p.t1 - p.t0);
        c.t1 = p.t0 + v1 * (p.t1 - p.t0);
      }
      break;
    case Form::Sphere: {
      c.arc = true;
      if (along_u) {  // a circle of latitude
        const double t = p.t0 + v0 * (p.t1 - p.t0);
        c.centre = p.o + p.R * std::cos(t) * p.w;
        c.e1 = p.e1;
        c.e2 = p.e2;
        c.radius = p.R * std::sin(t);
        c.t0 = p.f0 + u0 * (p.f1 - p.f0);
        c.t1 = p.f0 + u1 * (p.f1 - p.f0);
      } else {  // a meridian
        const double f = p.f0 + u0 * (p.f1 - p.f0);
        c.centre = p.o;
        c.e1 = p.w;
        c.e2 = std::cos(f) * p.e1 + std::sin(f) * p.e2;
        c.radius = p.R;
        c.t0 = p.t0 + v0 * (p.t1 - p.t0);
        c.t1 = p.t0 + v1 * (p.t1 - p.t0);
      }
      break;
    }
    case Form::Disc:  // radial along u; around the centre along v
      if (!along_u) {
        c.arc = true;
        c.centre = p.o;
        c.e1 = p.e1;
        c.e2 = p.e2;
        c.radius = u0 * p.R;
        c.t0 = 2.0 * M_PI * v0;
        c.t1 = 2.0 * M_PI * v1;
      }
      break;
    default:  // planes and triangles: straight both ways
      break;
  }
  if (c.arc) {
    if (c.t1 < c.t0) std::swap(c.t0, c.t1);
    const double step = (c.t1 - c.t0) / EdgeCurve::kArcPieces;
    for (int k = 0; k <= EdgeCurve::kArcPieces; ++k) {
      const double t = k == EdgeCurve::kArcPieces ? c.t1 : c.t0 + k * step;
      c.cos_at[k] = std::cos(t);
      c.sin_at[k] = std::sin(t);
    }
  }
  return c;
}

/// Least and greatest value of `cs cos t + sn sin t` for t along the arc `curve`.
std::pair<double, double> trig_range(double cs, double sn, const EdgeCurve& curve) {
  const double t0 = curve.t0, t1 = curve.t1;
  constexpr int kLast = EdgeCurve::kArcPieces;
  const double f0 = cs * curve.cos_at[0] + sn * curve.sin_at[0],
               f1 = cs * curve.cos_at[kLast] + sn * curve.sin_at[kLast];
  double lo = std::min(f0, f1), hi = std::max(f0, f1);
  const double amplitude = std::sqrt(cs * cs + sn * sn);
  if (amplitude > 0.0) {
    // Extremes at the peak angle (greatest) and opposite it (least), wherever they fall in [t0, t1].
    auto reached = [&](double angle) {
      const double k = std::ceil((t0 - angle) / (2.0 * M_PI));
      return angle + 2.0 * M_PI * k <= t1;
    };
    const double peak = std::atan2(sn, cs);
    if (reached(peak)) hi = amplitude;
    if (reached(peak + M_PI)) lo = -amplitude;
  }
  return {lo, hi};
}

/// Bounds along an edge curve of the squared distance to the line `origin + s axis` (|axis| = 1
/// or 0: the distance to `origin`), and of the parameter s of the nearest point of that line.
struct LineBounds {
  double square_lo, square_hi, along_lo, along_hi;
};

/// Least and greatest value over s in [s0, s1] of |w + s dw|^2 - (along + s d_along)^2, a convex
/// quadratic when |d_along| <= |dw| (the squared distance from a point moving along a segment to
/// a line, `along` its parameter on the line; to a point with along = d_along = 0).
std::pair<double, double> square_range(const Vector3d& w, const Vector3d& dw, double along, double d_along,
                                       double s0, double s1) {
  const double alpha = w.squaredNorm() - along * along, beta = 2.0 * (w.dot(dw) - along * d_along),
               gamma = dw.squaredNorm() - d_along * d_along;
  auto at = [&](double s) { return alpha + s * (beta + s * gamma); };
  double lo = std::min(at(s0), at(s1));
  const double hi = std::max(at(s0), at(s1));
  if (gamma > 0.0) {
    const double s = -beta / (2.0 * gamma);
    if (s > s0 && s < s1) lo = std::min(lo, at(s));
  }
  return {lo, hi};
}

LineBounds line_bounds(const EdgeCurve& curve, const Vector3d& origin, const Vector3d& axis) {
  LineBounds b;
  if (!curve.arc) {
    const Vector3d q = curve.a - origin, delta = curve.b - curve.a;
    const double qa = q.dot(axis), da = delta.dot(axis);
    std::tie(b.square_lo, b.square_hi) = square_range(q, delta, qa, da, 0.0, 1.0);
    b.along_lo = std::min(qa, qa + da);
    b.along_hi = std::max(qa, qa + da);
    return b;
  }
  // w(t) = q + rho (cos t e1 + sin t e2): the squared distance is a trigonometric polynomial of
  // degree 2, bounded piecewise between its values by its second derivative's bound.
  const Vector3d q = curve.centre - origin;
  const double rho = curve.radius;
  const double k0 = q.dot(axis), k1 = rho * curve.e1.dot(axis), k2 = rho * curve.e2.dot(axis);
  const double a0 = q.squaredNorm() + rho * rho - k0 * k0 - 0.5 * (k1 * k1 + k2 * k2);
  const double a1 = 2.0 * rho * q.dot(curve.e1) - 2.0 * k0 * k1,
               b1 = 2.0 * rho * q.dot(curve.e2) - 2.0 * k0 * k2;
  const double a2 = -0.5 * (k1 * k1 - k2 * k2), b2 = -k1 * k2;
  const double curvature = std::sqrt(a1 * a1 + b1 * b1) + 4.0 * std::sqrt(a2 * a2 + b2 * b2);
  constexpr int kPieces = EdgeCurve::kArcPieces;
  const double step = (curve.t1 - curve.t0) / kPieces;
  const double sag = curvature * step * step / 8.0;
  auto at = [&](int k) {
    const double c = curve.cos_at[k], s = curve.sin_at[k];
    return a0 + a1 * c + b1 * s + a2 * (c * c - s * s) + b2 * (2.0 * s * c);
  };
  b.square_lo = std::numeric_limits<double>::infinity();
  b.square_hi = -b.square_lo;
  double previous = at(0);
  for (int k = 1; k <= kPieces; ++k) {
    const double next = at(k);
    b.square_lo = std::min(b.square_lo, std::min(previous, next) - sag);
    b.square_hi = std::max(b.square_hi, std::max(previous, next) + sag);
    previous = next;
  }
  const auto [lo, hi] = trig_range(k1, k2, curve);
  b.along_lo = k0 + lo;
  b.along_hi = k0 + hi;
  return b;
}

/// The least squared distance from a straight edge curve to the segment from `origin` to
/// `origin + length axis` (|axis| = 1, or 0 with length 0: a point): the edge is cut where its
/// nearest point of the segment's line leaves the segment, and each piece's squared distance,
/// to the line or to the end beyond which it lies, is a convex quadratic.
double segment_square_lower(const EdgeCurve& curve, const Vector3d& origin, const Vector3d& axis,
                            double length) {
  const Vector3d q = curve.a - origin, delta = curve.b - curve.a;
  const double qa = q.dot(axis), da = delta.dot(axis);
  auto least = [](const Vector3d& w, const Vector3d& dw, double along, double d_along, double s0, double s1) {
    return square_range(w, dw, along, d_along, s0, s1).first;
  };
  // 0, the cuts strictly inside (at most two, in order), 1.
  std::array<double, 4> cuts{0.0, 0.0, 0.0, 0.0};
  std::size_t count = 1;
  if (da != 0.0) {
    const double first = -qa / da, second = (length - qa) / da;
    for (const double s : {std::min(first, second), std::max(first, second)})
      if (s > 0.0 && s < 1.0) cuts[count++] = s;
  }
  cuts[count++] = 1.0;
  double lower = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + 1 < count; ++k) {
    const double s0 = cuts[k], s1 = cuts[k + 1], along = qa + 0.5 * (s0 + s1) * da;
    if (along < 0.0)  // beyond the start: the distance to it
      lower = std::min(lower, least(q, delta, 0.0, 0.0, s0, s1));
    else if (along > length)  // beyond the end
      lower = std::min(lower, least(q - length * axis, delta, 0.0, 0.0, s0, s1));
    else
      lower = std::min(lower, least(q, delta, qa, da, s0, s1));
  }
  return lower;
}

/// The least squared distance from an edge curve to the segment from `origin` to
/// `origin + length axis` (|axis| = 1, or 0 with length 0): along a segment exactly (up to
/// rounding); along an arc that of the segment's line, or where the whole arc lies beyond one end
/// of the segment, that of that end (a trigonometric polynomial of degree 1).
double curve_square_lower(const EdgeCurve& curve, const Vector3d& origin, const Vector3d& axis,
                          double length) {
  if (!curve.arc) return segment_square_lower(curve, origin, axis, length);
  const LineBounds line = line_bounds(curve, origin, axis);
  if (line.along_hi >= 0.0 && line.along_lo <= length) return line.square_lo;
  const Vector3d q = curve.centre - (line.along_hi < 0.0 ? origin : Vector3d(origin + length * axis));
  return q.squaredNorm() + curve.radius * curve.radius +
         2.0 * curve.radius * trig_range(q.dot(curve.e1), q.dot(curve.e2), curve).first;
}

/// A lower bound of a sphere's or ball end's sweep term's signed distance all along an edge
/// curve: from the tip's capsule (curve_square_lower), for a ball end's body its floor at the lowest centre
/// and the centres' horizontal track, and the term's support plane. Where the capsule's bound is not above
/// `wanted` the body's is not worked out (-infinity, or the plane's). -infinity for other tools.
double sweep_lower_along(const Capsule& c, const SupportPlane& plane, const EdgeCurve& curve, double wanted) {
  const double inf = std::numeric_limits<double>::infinity();
  if (!c.valid) return -inf;
  const auto [axis, length] = c.unit_axis();
  const double square = curve_square_lower(curve, c.c0, axis, length);
  double lower = std::sqrt(std::max(square, 0.0)) - c.r;
  if (c.ballend) {
    if (lower > wanted) {
      const double lowest = std::min(c.c0.z(), c.c0.z() + c.d.z());
      const double top =
          curve.arc ? curve.centre.z() + curve.radius * trig_range(curve.e1.z(), curve.e2.z(), curve).second
                    : std::max(curve.a.z(), curve.b.z());
      double body = lowest - top;
      if (body <= wanted) {
        // Seen from above: the body lies within r of the centres' horizontal track.
        EdgeCurve flat = curve;
        flat.a.z() = flat.b.z() = flat.centre.z() = flat.e1.z() = flat.e2.z() = 0.0;
        const Vector3d track(c.d.x(), c.d.y(), 0.0);
        const double track_length = track.norm();
        const Vector3d origin(c.c0.x(), c.c0.y(), 0.0);
        const Vector3d track_axis = track_length > 0.0 ? Vector3d(track / track_length) : Vector3d::Zero();
        const double across = curve_square_lower(flat, origin, track_axis, track_length);
        body = std::max(body, std::sqrt(std::max(across, 0.0)) - c.r);
      }
      lower = std::min(lower, body);
    } else {
      lower = -inf;
    }
  }
  if (!(lower > wanted) && std::isfinite(plane.h)) {
    const double flat =
        curve.arc ? plane.n.dot(curve.centre) - plane.h +
                        curve.radius * trig_range(plane.n.dot(curve.e1), plane.n.dot(curve.e2), curve).first
                  : std::min(plane.at(curve.a), plane.at(curve.b));
    lower = std::max(lower, flat);
  }
  return lower;
}

/// Whether a sphere's or ball end's sweep holds an edge curve more than `need` deep all along:
/// its tip's capsule does (within the axis's span the distance to the axis is that to its line).
bool sweep_holds_along(const Capsule& c, const EdgeCurve& curve, double need) {
  if (!c.valid) return false;
  const auto [axis, length] = c.unit_axis();
  const LineBounds tip = line_bounds(curve, c.c0, axis);
  if (!(tip.along_lo >= 0.0 && tip.along_hi <= length)) return false;
  return std::sqrt(std::max(tip.square_hi, 0.0)) - c.r < -need;
}

/// What one round of trim_on_grid learnt that holds on a finer grid too: g at its nodes, and
/// which grid edges the strip scan found clean (both depend on the edge's ends alone, not on the
/// grid around them). A round that adds grid lines hands it to the next.
struct GridMemory {
  std::vector<double> us, vs;  // the round's grid lines
  std::vector<double> value;   // g at its nodes (NaN: not evaluated), as trim_on_grid's `value`
  std::vector<bool> clean;     // per grid edge, as trim_on_grid's `scanned`: scanned, no strip
  // Its parameter blocks (the block tree's, larger than a cell), sorted by their rectangle: each
  // proven kept or removed, or else with its list of terms (a parameter rectangle's proof and
  // terms do not depend on the grid inside it).
  struct Block {
    std::array<double, 4> rectangle;  // u0, u1, v0, v1
    std::uint8_t state;               // trim_on_grid's cell states
    std::uint32_t first, count;       // its terms in `terms` (open blocks)
    Vector3d centre;
    double upper;
    bool operator<(const Block& o) const { return rectangle < o.rectangle; }
  };
  std::vector<Block> blocks;
  std::vector<Trimmer::SweepTerm> terms;
};

PatchMesh trim_on_grid(const Context& ctx, const Patch& patch, const Trimmer& g,
                       const std::vector<double>& us, const std::vector<double>& vs,
                       std::vector<double>* extra_u, std::vector<double>* extra_v, GridMemory* memory);

/// Marching squares over the patch's grid: keeps the part where g > 0. The grid starts uniform;
/// where a kept strip narrower than a cell slips between the nodes (a pass grazing a face or an
/// edge keeps a sliver of its sweep), a grid line is added through it and the patch redone.
PatchMesh trim_patch(const Context& ctx, const Patch& patch) {
  {
    // A patch entirely inside other sweeps, piece by piece inside one (a ball end's body wall
    // inside the next row's body, a joint's cap inside the passes around it): g < 0 all over
    // it, nothing is kept; evaluating every node would find the same. Arcs are cut into pieces
    // of at most an eighth of a turn.
    const auto [angle_u, angle_v] = parameter_angles(patch);
    const int parts_u = std::max(1, static_cast<int>(std::ceil(angle_u / (0.25 * M_PI) - 1e-9)));
    const int parts_v = std::max(1, static_cast<int>(std::ceil(angle_v / (0.25 * M_PI) - 1e-9)));
    bool inside = parts_u * parts_v <= 64;
    for (int i = 0; i < parts_u && inside; ++i)
      for (int j = 0; j < parts_v && inside; ++j) {
        const double u0 = static_cast<double>(i) / parts_u, u1 = static_cast<double>(i + 1) / parts_u;
        const double v0 = static_cast<double>(j) / parts_v, v1 = static_cast<double>(j + 1) / parts_v;
        const double gap = hull_gap(patch, u0, u1, v0, v1);
        const std::array<Vector3d, 4> corners{evaluate(patch, u0, v0), evaluate(patch, u1, v0),
                                              evaluate(patch, u0, v1), evaluate(patch, u1, v1)};
        inside = std::isfinite(gap) &&
                 inside_one_sweep(ctx, patch, corners, 1.001 * gap + 100.0 * ctx.tie + 1e-12);
      }
    if (inside) return PatchMesh();
  }
  const Trimmer g(ctx, patch);
  std::vector<double> us(patch.nu + 1), vs(patch.nv + 1);
  for (int i = 0; i <= patch.nu; ++i) us[i] = static_cast<double>(i) / patch.nu;
  for (int j = 0; j <= patch.nv; ++j) vs[j] = static_cast<double>(j) / patch.nv;
  GridMemory memory;
  for (int round = 0;; ++round) {
    std::vector<double> extra_u, extra_v;
    PatchMesh out = trim_on_grid(ctx, patch, g, us, vs, round < 3 ? &extra_u : nullptr, &extra_v, &memory);
    out.searches = g.searches();
    if (extra_u.empty() && extra_v.empty()) return out;
    us.insert(us.end(), extra_u.begin(), extra_u.end());
    vs.insert(vs.end(), extra_v.begin(), extra_v.end());
    std::sort(us.begin(), us.end());
    std::sort(vs.begin(), vs.end());
    us.erase(std::unique(us.begin(), us.end()), us.end());
    vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
  }
}

// Blocks of at most this many cells give their terms support planes facing their centre;
// larger ones pass on their parent's (a plane costs about what a distance bound does).
constexpr int kFreshCells = 16;

PatchMesh trim_on_grid(const Context& ctx, const Patch& patch, const Trimmer& g,
                       const std::vector<double>& us, const std::vector<double>& vs,
                       std::vector<double>* extra_u, std::vector<double>* extra_v, GridMemory* memory) {
  PatchMesh out;
  const int nu = static_cast<int>(us.size()) - 1, nv = static_cast<int>(vs.size()) - 1;
  const int su = patch.periodic_u ? nu : nu + 1;  // distinct node columns
  const int sv = patch.periodic_v ? nv : nv + 1;
  // The previous round's column and row of each grid line (-1: a line added since).
  std::vector<int> old_i, old_j;
  auto old_lines = [](const std::vector<double>& now, const std::vector<double>& before,
                      std::vector<int>& index) {
    index.assign(now.size(), -1);
    for (std::size_t k = 0; k < now.size(); ++k) {
      const auto it = std::lower_bound(before.begin(), before.end(), now[k]);
      if (it != before.end() && *it == now[k]) index[k] = static_cast<int>(it - before.begin());
    }
  };
  const bool remembered = !memory->us.empty();
  if (remembered) {
    old_lines(us, memory->us, old_i);
    old_lines(vs, memory->vs, old_j);
  }
  const int old_nu = static_cast<int>(memory->us.size()) - 1,
            old_nv = static_cast<int>(memory->vs.size()) - 1;
  const int old_sv = patch.periodic_v ? old_nv : old_nv + 1;
  auto old_wrap_u = [&](int i) { return patch.periodic_u ? i % old_nu : i; };
  auto old_wrap_v = [&](int j) { return patch.periodic_v ? j % old_nv : j; };
  auto wrap_u = [&](int i) { return patch.periodic_u ? i % nu : i; };
  auto wrap_v = [&](int j) { return patch.periodic_v ? j % nv : j; };
  auto pu = [&](int i) { return us[static_cast<std::size_t>(i)]; };
  auto pv = [&](int j) { return vs[static_cast<std::size_t>(j)]; };

  // Other patches: the sweep terms of g that can be the least one on each cell, found block by
  // block (a block's terms from its parent's; the root's, or with many candidates those of the
  // largest blocks of a few cells, from the tree). Values on a cell then
  // come from its terms alone: the same values as from all terms, far fewer distances.
  std::vector<Trimmer::SweepTerm> term_pool;
  struct ListAt {
    std::uint32_t first, count;  // in term_pool
    Vector3d centre;
    double upper;
  };
  std::vector<ListAt> lists;
  auto term_list = [&](std::uint32_t list) {
    const ListAt& l = lists[list];
    return Trimmer::TermList{term_pool.data() + l.first, l.count, l.centre, l.upper};
  };
  std::vector<std::uint32_t> cell_list;  // per cell: its list in `lists`
  // Space radii of parameter blocks, conservative: a relative and an absolute margin.
  const double margin = 100.0 * ctx.tie + 1e-12;
  std::size_t current_cell = 0;  // the cell whose closed rectangle the next values lie on
  auto eval = [&](double u, double v) {
    if (cell_list.empty()) return g(u, v);
    return g(u, v, term_list(cell_list[current_cell]));
  };
  // Node values, evaluated lazily (the quadtree of large flat patches never visits most nodes).
  std::vector<double> value(static_cast<std::size_t>(su) * sv, std::numeric_limits<double>::quiet_NaN());
  auto val = [&](int i, int j) {
    double& v = value[static_cast<std::size_t>(wrap_u(i)) * sv + wrap_v(j)];
    if (std::isnan(v) && remembered) {
      const int oi = old_i[static_cast<std::size_t>(wrap_u(i))],
                oj = old_j[static_cast<std::size_t>(wrap_v(j))];
      if (oi >= 0 && oj >= 0) v = memory->value[static_cast<std::size_t>(oi) * old_sv + oj];
    }
    if (std::isnan(v)) v = eval(pu(wrap_u(i)), pv(wrap_v(j)));
    return v;
  };
  // Large flat stock faces: blocks of cells that the exact 1-Lipschitz g proves entirely kept or
  // removed are not subdivided (a kept block becomes one polygon whose edges carry the nodes of
  // finer neighbours, so no T-junctions arise).
  const bool quadtree =
      !patch.sweep && (patch.form == Form::Plane || patch.form == Form::Triangle) && nu * nv > 16;
  struct Block {
    int i0, i1, j0, j1;
  };
  // The block's halves across its longer side: {upper, lower} (pushed in that order, the lower
  // half is popped first).
  auto halves = [](const Block& b) {
    if (b.i1 - b.i0 >= b.j1 - b.j0) {
      const int im = (b.i0 + b.i1) / 2;
      return std::array<Block, 2>{{{im, b.i1, b.j0, b.j1}, {b.i0, im, b.j0, b.j1}}};
    }
    const int jm = (b.j0 + b.j1) / 2;
    return std::array<Block, 2>{{{b.i0, b.i1, jm, b.j1}, {b.i0, b.i1, b.j0, jm}}};
  };
  std::vector<Block> kept_blocks;
  std::vector<std::array<int, 2>> fine_cells;
  // Other patches: per cell, proven entirely kept or removed, or open (evaluated); empty: all open.
  constexpr std::uint8_t kRemoved = 0, kKept = 1, kOpen = 2;
  std::vector<GridMemory::Block> block_records;  // see GridMemory
  std::vector<std::uint8_t> cell_state;
  auto cell_state_at = [&](int i, int j) -> std::uint8_t {
    return cell_state.empty() ? kOpen : cell_state[static_cast<std::size_t>(i) * nv + j];
  };
  if (quadtree) {
    std::vector<Block> stack{{0, nu, 0, nv}};
    while (!stack.empty()) {
      const Block b = stack.back();
      stack.pop_back();
      if (b.i1 - b.i0 == 1 && b.j1 - b.j0 == 1) {
        fine_cells.push_back({b.i0, b.j0});
        continue;
      }
      const double uc = 0.5 * (pu(b.i0) + pu(b.i1)), vc = 0.5 * (pv(b.j0) + pv(b.j1));
      const Vector3d centre = evaluate(patch, uc, vc);
      double radius = 0.0;  // the block's image lies in the convex hull of its corners' images
      for (int ci : {b.i0, b.i1})
        for (int cj : {b.j0, b.j1})
          radius = std::max(radius, (evaluate(patch, pu(ci), pv(cj)) - centre).norm());
      const double gc = g(uc, vc);
      if (gc > 1.0001 * radius + 1e-12) {
        kept_blocks.push_back(b);
        continue;
      }
      if (gc < -1.0001 * radius - 1e-12) continue;
      for (const Block& half : halves(b)) stack.push_back(half);
    }
    if (kept_blocks.empty() && fine_cells.empty()) return out;
  } else {
    // Blocks that g's Lipschitz bound proves entirely kept or removed need no node values: g at
    // a block's centre is exact where it is positive and an upper bound of the exact minimum of
    // its terms where not (the early return), and within L times the block's radius (plus a
    // relative and a tie margin: the tie shift jumps by two ties, the distances are exact to far
    // less) of that minimum all over the block. Every other cell evaluates exactly as before.
    const double lipschitz = g.lipschitz();
    const bool proofs = std::isfinite(lipschitz);
    const std::size_t cells = static_cast<std::size_t>(nu) * nv;
    if (proofs) cell_state.assign(cells, kOpen);
    auto radius_of = [&](const Block& b) {
      return 1.001 * block_radius(patch, pu(b.i0), pu(b.i1), pv(b.j0), pv(b.j1)) + margin;
    };
    // A block's terms are those of its parent that can be the least one on it: within twice its
    // radius (and the tie jumps) of the least of them at its centre.
    const Block root{0, nu, 0, nv};
    // This round's blocks, for the next one (recorded only where there can be one).
    std::vector<GridMemory::Block>& records = block_records;
    auto rectangle_of = [&](const Block& b) {
      return std::array<double, 4>{pu(b.i0), pu(b.i1), pv(b.j0), pv(b.j1)};
    };
    auto remembered_block = [&](const Block& b) -> const GridMemory::Block* {
      if (memory->blocks.empty()) return nullptr;
      GridMemory::Block key;
      key.rectangle = rectangle_of(b);
      const auto it = std::lower_bound(memory->blocks.begin(), memory->blocks.end(), key);
      return it != memory->blocks.end() && it->rectangle == key.rectangle ? &*it : nullptr;
    };
    // A remembered open block's terms as a list of this round's.
    auto remembered_list = [&](const GridMemory::Block& r) {
      lists.push_back({static_cast<std::uint32_t>(term_pool.size()), r.count, r.centre, r.upper});
      term_pool.insert(term_pool.end(), memory->terms.begin() + r.first,
                       memory->terms.begin() + r.first + r.count);
      return static_cast<std::uint32_t>(lists.size() - 1);
    };
    auto set_state = [&](const Block& b, std::uint8_t state) {
      for (int i = b.i0; i < b.i1; ++i)
        for (int j = b.j0; j < b.j1; ++j) cell_state[static_cast<std::size_t>(i) * nv + j] = state;
    };
    // A block proven kept or removed, and recorded for the next round.
    auto prove = [&](const Block& b, std::uint8_t state) {
      set_state(b, state);
      if (extra_u) records.push_back({rectangle_of(b), state, 0u, 0u, Vector3d::Zero(), 0.0});
    };
    // A block's own terms from the tree (a list of its own, its parent having none).
    constexpr std::uint32_t kFromTree = UINT32_MAX;
    auto list_from_tree = [&](const Block& b) {
      const double uc = 0.5 * (pu(b.i0) + pu(b.i1)), vc = 0.5 * (pv(b.j0) + pv(b.j1));
      double upper = 0.0;
      std::vector<Trimmer::SweepTerm> terms = g.terms_within(uc, vc, radius_of(b), &upper);
      lists.push_back({static_cast<std::uint32_t>(term_pool.size()), static_cast<std::uint32_t>(terms.size()),
                       evaluate(patch, uc, vc), upper});
      term_pool.insert(term_pool.end(), terms.begin(), terms.end());
      return static_cast<std::uint32_t>(lists.size() - 1);
    };
    // Where the tree is searched, the terms within a large block's reach are many more than can
    // be the least on any small part of it (a short move's tube among dozens of neighbours in
    // its row: nearly a thousand terms for the whole half circle, a few dozen for a few cells),
    // and each level of blocks would sift them again: blocks of more cells than this take no
    // list, their halves get theirs from the tree.
    constexpr int kMostCellsFromTree = 8;
    std::uint32_t root_list = kFromTree;
    if (const GridMemory::Block* r = remembered_block(root); r && r->state == kOpen) {
      root_list = remembered_list(*r);
    } else if (!g.searches_tree() || cells <= static_cast<std::size_t>(kMostCellsFromTree)) {
      root_list = list_from_tree(root);
    }
    cell_list.assign(cells, 0);
    struct Task {
      Block b;
      std::uint32_t list;  // the block's terms (kFromTree: none yet)
    };
    std::vector<Task> stack{{root, root_list}};
    std::vector<Trimmer::SweepTerm> near;
    while (!stack.empty()) {
      Task task = stack.back();
      const Block& b = task.b;
      stack.pop_back();
      if (task.list == kFromTree && !remembered_block(b)) {
        if ((b.i1 - b.i0) * (b.j1 - b.j0) > kMostCellsFromTree) {
          // Proven as below from g at the centre: removed by an upper bound of it (inside another
          // move's tip), kept only by its exact value (the tree's search).
          if (proofs) {
            const double uc = 0.5 * (pu(b.i0) + pu(b.i1)), vc = 0.5 * (pv(b.j0) + pv(b.j1));
            const double reach = lipschitz * radius_of(b);
            double gc = g.upper_bound(uc, vc);
            if (gc > reach) gc = g(uc, vc);
            if (gc < -reach || gc > reach) {
              prove(b, gc > 0.0 ? kKept : kRemoved);
              continue;
            }
          }
          for (const Block& half : halves(b)) stack.push_back({half, kFromTree});
          continue;
        }
        task.list = list_from_tree(b);
      }
      if (b.i1 - b.i0 == 1 && b.j1 - b.j0 == 1) {
        // A single cell's centre costs about what its nodes do: it keeps its parent's terms.
        cell_list[static_cast<std::size_t>(b.i0) * nv + b.j0] = task.list;
        continue;
      }
      if (const GridMemory::Block* r = remembered_block(b)) {
        if (r->state != kOpen) {
          set_state(b, r->state);
        } else {
          const std::uint32_t list = remembered_list(*r);
          for (const Block& half : halves(b)) stack.push_back({half, list});
        }
        if (extra_u) {
          if (r->state == kOpen) {
            const ListAt& l = lists.back();
            records.push_back({r->rectangle, kOpen, l.first, l.count, l.centre, l.upper});
          } else {
            records.push_back({r->rectangle, r->state, 0u, 0u, Vector3d::Zero(), 0.0});
          }
        }
        continue;
      }
      const double uc = 0.5 * (pu(b.i0) + pu(b.i1)), vc = 0.5 * (pv(b.j0) + pv(b.j1));
      const double radius = radius_of(b);
      if (proofs) {
        const double reach = lipschitz * radius;
        const double gc = g(uc, vc, term_list(task.list));
        bool inside = false;
        if (gc < 0.0 && gc >= -reach) {
          // Inside one sweep at every corner: removed (a sweep is convex, g is not).
          const double gap = hull_gap(patch, pu(b.i0), pu(b.i1), pv(b.j0), pv(b.j1));
          if (std::isfinite(gap)) {
            const std::array<Vector3d, 4> corners{
                evaluate(patch, pu(b.i0), pv(b.j0)), evaluate(patch, pu(b.i1), pv(b.j0)),
                evaluate(patch, pu(b.i0), pv(b.j1)), evaluate(patch, pu(b.i1), pv(b.j1))};
            inside = g.inside_one_sweep(term_list(task.list), corners, 1.001 * gap + margin);
          }
        }
        if (gc < -reach || gc > reach || inside) {
          prove(b, gc > 0.0 ? kKept : kRemoved);
          continue;
        }
      }
      const bool fresh = (b.i1 - b.i0) * (b.j1 - b.j0) <= kFreshCells;
      const Vector3d centre = evaluate(patch, uc, vc);
      const double upper =
          g.near_terms(centre, term_list(task.list), 2.0 * radius + 4.0 * ctx.tie, near, fresh);
      const auto list = static_cast<std::uint32_t>(lists.size());
      lists.push_back({static_cast<std::uint32_t>(term_pool.size()), static_cast<std::uint32_t>(near.size()),
                       centre, upper});
      term_pool.insert(term_pool.end(), near.begin(), near.end());
      if (extra_u)
        records.push_back({rectangle_of(b), kOpen, lists[list].first, lists[list].count, centre, upper});
      for (const Block& half : halves(b)) stack.push_back({half, list});
    }
    // A kept cell has kept nodes; a node of removed cells only is removed.
    bool any_in = false;
    for (int i = 0; i < nu && !any_in; ++i)
      for (int j = 0; j < nv && !any_in; ++j) {
        if (cell_state_at(i, j) == kKept) any_in = true;
        if (cell_state_at(i, j) != kOpen) continue;
        current_cell = static_cast<std::size_t>(i) * nv + j;
        for (int k = 0; k < 4 && !any_in; ++k) any_in = val(i + (k & 1), j + (k >> 1)) > 0.0;
      }
    // Without a kept node the patch is gone, unless a strip hides between its nodes.
    if (!any_in && !extra_u) return out;
    for (int i = 0; i < nu; ++i)
      for (int j = 0; j < nv; ++j) fine_cells.push_back({i, j});
  }

  if (extra_u) {
    // Hidden strips: along a grid edge whose ends are both removed, g (L-Lipschitz in space) can
    // still rise above zero if (g0 + g1 + L length) / 2 > 0; bisect such edges down to a small
    // fraction of the tolerance budget and put a grid line through any kept point found. The
    // same for hidden cuts along edges whose ends are both kept.
    // The same bound as the block proofs (a ball end's sphere rule varies as 1/r, not 1/rule_radius).
    const double lipschitz = std::isfinite(g.lipschitz())
                                 ? g.lipschitz()
                                 : (patch.rule_count > 0 ? std::max(1.0, 1.0 / patch.rule_radius) : 1.0);
    const std::array<double, 2> speed = parameter_speeds(patch);
    const double shortest = 1e3 * ctx.tie + 0.02 * ctx.trim_tolerance;
    // Per grid edge (its lower node, its direction): scanned already.
    std::vector<bool> scanned(2 * value.size(), false);
    // Per grid edge: scanned and no strip found (handed to the next round, see GridMemory).
    std::vector<bool> clean(2 * value.size(), false);
    // Whether the previous round found the edge from node (i0, j0) along u or v clean.
    auto clean_before = [&](int i0, int j0, bool along_u) {
      if (!remembered) return false;
      const int oi0 = old_i[static_cast<std::size_t>(wrap_u(i0))],
                oj0 = old_j[static_cast<std::size_t>(wrap_v(j0))];
      const int i1 = along_u ? i0 + 1 : i0, j1 = along_u ? j0 : j0 + 1;
      const int oi1 = old_i[static_cast<std::size_t>(wrap_u(i1))],
                oj1 = old_j[static_cast<std::size_t>(wrap_v(j1))];
      if (oi0 < 0 || oj0 < 0 || oi1 < 0 || oj1 < 0) return false;
      // The same edge only if no line was added between its ends.
      if (along_u ? (oj1 != oj0 || oi1 != old_wrap_u(oi0 + 1)) : (oi1 != oi0 || oj1 != old_wrap_v(oj0 + 1)))
        return false;
      return static_cast<bool>(
          memory->clean[2 * (static_cast<std::size_t>(oi0) * old_sv + oj0) + (along_u ? 1 : 0)]);
    };
    struct Span {
      double a, b, ga, gb, bound;
      bool operator<(const Span& o) const { return bound < o.bound; }
    };
    std::vector<Span> heap;
    std::vector<Trimmer::SweepTerm> scan_terms;
    auto scan = [&](int i0, int j0, bool along_u) {
      const std::size_t key =
          2 * (static_cast<std::size_t>(wrap_u(i0)) * sv + wrap_v(j0)) + (along_u ? 1 : 0);
      if (scanned[key]) return;
      scanned[key] = true;
      clean[key] = true;  // until a strip is found
      if (clean_before(i0, j0, along_u)) return;
      const int i1 = along_u ? i0 + 1 : i0, j1 = along_u ? j0 : j0 + 1;
      // Both ends removed: look for a kept point; both kept: for a removed one (a cut narrower
      // than a cell, as where a sinking pass first touches a face). In terms of sign * g.
      const double sign = val(i0, j0) > 0.0 ? -1.0 : 1.0;
      const double g0 = sign * val(i0, j0), g1 = sign * val(i1, j1);
      if (g0 > 0.0 || g1 > 0.0) return;
      const double p0 = along_u ? pu(i0) : pv(j0), p1 = along_u ? pu(i1) : pv(j1);
      const double length = (p1 - p0) * speed[along_u ? 0 : 1];
      // Bisection, most promising span first (largest bound), a bounded number of samples: where
      // g hugs zero all along (a tangent contact, a tie) no strip worth a grid line is there.
      auto make_span = [&](double a, double b, double ga, double gb) {
        const double span_length = length * (b - a) / (p1 - p0);
        return Span{a, b, ga, gb, span_length < shortest ? -1.0 : 0.5 * (ga + gb + lipschitz * span_length)};
      };
      heap.assign(1, make_span(p0, p1, g0, g1));
      if (heap[0].bound <= 0.0) return;
      if (sign > 0.0 && !cell_list.empty()) {
        // Both ends inside one sweep, deeper than the edge's image strays from its chord: g < 0
        // all along it (the sweep is convex), no sample would find a kept point.
        const double gap = hull_gap(patch, pu(i0), pu(i1), pv(j0), pv(j1));
        if (std::isfinite(gap)) {
          const Vector3d x0 = evaluate(patch, pu(i0), pv(j0)), x1 = evaluate(patch, pu(i1), pv(j1));
          if (g.inside_one_sweep(term_list(cell_list[current_cell]), {x0, x1, x0, x1}, 1.001 * gap + margin))
            return;
        }
      }
      // The samples come from the terms that can be the least one on the edge (about its
      // midpoint, as for the edge roots): far fewer distances than from the cell's.
      Trimmer::TermList scan_list{nullptr, 0, Vector3d::Zero(), 0.0};
      if (!cell_list.empty()) {
        const double u0 = pu(i0), u1 = pu(i1), v0 = pv(j0), v1 = pv(j1);
        const double um = 0.5 * (u0 + u1), vm = 0.5 * (v0 + v1);
        const double radius = 1.001 * block_radius(patch, u0, u1, v0, v1) + margin;
        const Vector3d centre = evaluate(patch, um, vm);
        const double upper = g.near_terms(centre, term_list(cell_list[current_cell]),
                                          2.0 * radius + 4.0 * ctx.tie, scan_terms);
        scan_list = Trimmer::TermList{scan_terms.data(), scan_terms.size(), centre, upper};
      }
      if (!cell_list.empty()) {
        // The terms' own bounds along the edge's image may show its sign without samples: every
        // sweep term clear above zero and the patch's own terms too (L-Lipschitz), or one sweep
        // term below zero all along. (Where g hugs zero, at a cell's distance from a
        // neighbour's nearly coincident surface, the bisection would spend all its samples.)
        const EdgeCurve curve = edge_curve(patch, pu(i0), pv(j0), pu(i1), pv(j1));
        const double need = 4.0 * ctx.tie + 1e-12 * (1.0 + curve.a.cwiseAbs().maxCoeff());
        bool shown = false;
        if (sign < 0.0) {
          shown =
              0.5 * (g.own_value(pu(i0), pv(j0)) + g.own_value(pu(i1), pv(j1)) - lipschitz * length) > need;
          for (std::size_t k = 0; k < scan_terms.size() && shown; ++k) {
            const int j = scan_terms[k].segment;
            const Capsule& c = ctx.capsules[static_cast<std::size_t>(j)];
            const double lower = sweep_lower_along(c, scan_terms[k].plane, curve, -c.margin);
            // An adjacent move's sweep touching the edge (its end on the joint's profile) is
            // kept by the tie shift wherever it leans to keeping: never below zero, g stays
            // above it there.
            shown = lower > need + c.margin ||
                    (lower > -c.margin && g.tie_keeps(j, pu(i0), pv(j0)) && g.tie_keeps(j, pu(i1), pv(j1)));
          }
        } else {
          for (std::size_t k = 0; k < scan_terms.size() && !shown; ++k) {
            const Capsule& c = ctx.capsules[static_cast<std::size_t>(scan_terms[k].segment)];
            shown = sweep_holds_along(c, curve, need + c.margin);
          }
        }
        if (shown) return;
      }
      auto sample = [&](double u, double v) { return scan_list.terms ? g(u, v, scan_list) : eval(u, v); };
      for (int samples = 0; samples < 24 && !heap.empty(); ++samples) {
        std::pop_heap(heap.begin(), heap.end());
        const Span sp = heap.back();
        heap.pop_back();
        if (sp.bound <= 0.0) break;
        const double m = 0.5 * (sp.a + sp.b);
        const double gm = sign * (along_u ? sample(m, pv(j0)) : sample(pu(i0), m));
        if (gm > 0.0) {
          (along_u ? *extra_u : *extra_v).push_back(m);
          clean[key] = false;
          return;
        }
        heap.push_back(make_span(sp.a, m, sp.ga, gm));
        std::push_heap(heap.begin(), heap.end());
        heap.push_back(make_span(m, sp.b, gm, sp.gb));
        std::push_heap(heap.begin(), heap.end());
      }
    };
    for (const auto& [i, j] : fine_cells) {
      // A proven cell's edges need no scan: kept, one of their ends is kept; removed, g < 0 all
      // along them. Open cells scan their edges, shared ones too, from exact values.
      if (cell_state_at(i, j) != kOpen) continue;
      current_cell = static_cast<std::size_t>(i) * nv + j;
      scan(i, j, true);
      scan(i, j + 1, true);
      scan(i, j, false);
      scan(i + 1, j, false);
    }
    if (!extra_u->empty() || !extra_v->empty()) {
      memory->us = us;
      memory->vs = vs;
      memory->value = std::move(value);
      memory->clean = std::move(clean);
      std::sort(block_records.begin(), block_records.end());
      memory->blocks = std::move(block_records);
      memory->terms = std::move(term_pool);
      return out;
    }
  }

  std::vector<std::int32_t> node_id(value.size(), -1);
  auto node = [&](int i, int j) {
    std::int32_t& id = node_id[static_cast<std::size_t>(wrap_u(i)) * sv + wrap_v(j)];
    if (id < 0) {
      id = static_cast<std::int32_t>(out.vertices.size());
      out.vertices.push_back(evaluate(patch, pu(wrap_u(i)), pv(wrap_v(j))));
    }
    return static_cast<std::uint32_t>(id);
  };
  // Crossing vertices on grid edges, cached so neighbouring cells share them.
  std::unordered_map<std::uint64_t, std::uint32_t> crossing;
  std::vector<Trimmer::SweepTerm> edge_terms;
  struct CrossingInfo {
    double u, v;
    int term;
  };
  std::unordered_map<std::uint32_t, CrossingInfo> crossing_at;
  auto edge = [&](int i0, int j0, int i1, int j1) {
    // Canonical key: the lower node and the direction.
    const bool along_u = j0 == j1;
    const int ia = std::min(i0, i1), ja = std::min(j0, j1);
    const std::uint64_t key = (static_cast<std::uint64_t>(wrap_u(ia)) << 33) |
                              (static_cast<std::uint64_t>(wrap_v(ja)) << 1) | (along_u ? 1u : 0u);
    auto it = crossing.find(key);
    if (it != crossing.end()) return it->second;
    const int ib = along_u ? ia + 1 : ia, jb = along_u ? ja : ja + 1;
    auto at = [&](double s) {
      return std::array<double, 2>{pu(ia) + s * (pu(ib) - pu(ia)), pv(ja) + s * (pv(jb) - pv(ja))};
    };
    double t;
    Trimmer::TermList edge_list{nullptr, 0, Vector3d::Zero(), 0.0};
    if (cell_list.empty()) {
      t = edge_root(eval, val(ia, ja), val(ib, jb), at);
    } else {
      // The root search evaluates g many times along the edge: from the terms that can be the
      // least one on the edge, about its midpoint, far fewer distances than from the cell's.
      const double u0 = pu(ia), u1 = pu(ib), v0 = pv(ja), v1 = pv(jb);
      const double um = 0.5 * (u0 + u1), vm = 0.5 * (v0 + v1);
      const double radius = 1.001 * block_radius(patch, u0, u1, v0, v1) + margin;
      const Vector3d centre = evaluate(patch, um, vm);
      const double upper =
          g.near_terms(centre, term_list(cell_list[current_cell]), 2.0 * radius + 4.0 * ctx.tie, edge_terms);
      edge_list = Trimmer::TermList{edge_terms.data(), edge_terms.size(), centre, upper};
      t = edge_root([&](double u, double v) { return g(u, v, edge_list); }, val(ia, ja), val(ib, jb), at);
    }
    // A root at a grid node is that node (no sliver triangles between them). "At" means within
    // the weld distance (100 ties) in space: the tie-break shifts a trimming curve that runs
    // along a grid line (a pass exactly along a stock face) by one tie, which on a short edge is
    // far more than 1e-9 of it, and the sliver left would keep the seam from closing.
    const double edge_length = (evaluate(patch, pu(ib), pv(jb)) - evaluate(patch, pu(ia), pv(ja))).norm();
    const double snap = std::max(1e-9, 100.0 * ctx.tie / std::max(edge_length, 1e-300));
    std::uint32_t id;
    if (t <= snap) {
      id = node(ia, ja);
    } else if (t >= 1.0 - snap) {
      id = node(ib, jb);
    } else {
      id = static_cast<std::uint32_t>(out.vertices.size());
      const double u = pu(ia) + t * (pu(ib) - pu(ia)), v = pv(ja) + t * (pv(jb) - pv(ja));
      out.vertices.push_back(evaluate(patch, u, v));
      int term = Trimmer::kNoTerm;
      if (edge_list.terms)
        g.evaluate_with_term(u, v, edge_list, &term);
      else
        g.evaluate_with_term(u, v, &term);
      crossing_at.emplace(id, CrossingInfo{u, v, term});
    }
    crossing.emplace(key, id);
    return id;
  };
  // Where the contour leaves a cell through one term's curve and enters through another's, the
  // kept region has a corner inside the cell (two trimming curves meeting, e.g. two passes and
  // a stock face): marching squares would cut it off by a chord. The corner, found by Newton's
  // method on the two terms, is inserted; the patch on the other side finds the same point.
  auto corner_between = [&](std::uint32_t leave, std::uint32_t enter, int i, int j) -> std::int64_t {
    const auto a = crossing_at.find(leave), b = crossing_at.find(enter);
    if (a == crossing_at.end() || b == crossing_at.end()) return -1;
    const int ta = a->second.term, tb = b->second.term;
    if (ta == tb || ta == Trimmer::kNoTerm || tb == Trimmer::kNoTerm) return -1;
    const double du = pu(i + 1) - pu(i), dv = pv(j + 1) - pv(j);
    double u = 0.5 * (a->second.u + b->second.u), v = 0.5 * (a->second.v + b->second.v);
    const double hu = 1e-7 * du, hv = 1e-7 * dv;
    bool converged = false;
    for (int it = 0; it < 30 && !converged; ++it) {
      const double fa = g.term_value(ta, u, v), fb = g.term_value(tb, u, v);
      if (std::abs(fa) < 1e-3 * ctx.tie && std::abs(fb) < 1e-3 * ctx.tie) {
        converged = true;
        break;
      }
      const double a11 = (g.term_value(ta, u + hu, v) - g.term_value(ta, u - hu, v)) / (2 * hu);
      const double a12 = (g.term_value(ta, u, v + hv) - g.term_value(ta, u, v - hv)) / (2 * hv);
      const double a21 = (g.term_value(tb, u + hu, v) - g.term_value(tb, u - hu, v)) / (2 * hu);
      const double a22 = (g.term_value(tb, u, v + hv) - g.term_value(tb, u, v - hv)) / (2 * hv);
      const double det = a11 * a22 - a12 * a21;
      if (!(std::abs(det) > 0.0)) break;
      u -= (a22 * fa - a12 * fb) / det;
      v -= (a11 * fb - a21 * fa) / det;
      if (!(u > pu(i) - 0.25 * du && u < pu(i + 1) + 0.25 * du && v > pv(j) - 0.25 * dv &&
            v < pv(j + 1) + 0.25 * dv))
        break;
    }
    // Short of full precision, a point within the weld distance of both curves will do: the ball
    // end's body distance is itself a numerical minimisation.
    if (!converged && !(std::abs(g.term_value(ta, u, v)) < 100.0 * ctx.tie &&
                        std::abs(g.term_value(tb, u, v)) < 100.0 * ctx.tie && u > pu(i) - 0.25 * du &&
                        u < pu(i + 1) + 0.25 * du && v > pv(j) - 0.25 * dv && v < pv(j + 1) + 0.25 * dv))
      return -1;
    // No third term may cut the corner off (inside the cell its terms decide, as everywhere on it).
    const bool inside_cell = u >= pu(i) && u <= pu(i + 1) && v >= pv(j) && v <= pv(j + 1);
    if ((inside_cell ? eval(u, v) : g(u, v)) < -100.0 * ctx.tie) return -1;
    const auto id = static_cast<std::int64_t>(out.vertices.size());
    out.vertices.push_back(evaluate(patch, u, v));
    return id;
  };

  std::vector<std::uint32_t> poly;
  auto emit = [&](std::vector<std::uint32_t> p) {
    // Roots snapped to nodes repeat a vertex: drop the repeats.
    p.erase(std::unique(p.begin(), p.end()), p.end());
    while (p.size() > 1 && p.front() == p.back()) p.pop_back();
    for (std::size_t k = 1; k + 1 < p.size(); ++k) {
      Triangle t{p[0], p[k], p[k + 1]};
      if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
      if (patch.flip) std::swap(t[1], t[2]);
      out.triangles.push_back(t);
    }
  };
  for (const Block& b : kept_blocks)
    for (int ci : {b.i0, b.i1})
      for (int cj : {b.j0, b.j1}) node(ci, cj);
  for (const auto& [i, j] : fine_cells) {
    {
      const int ci[4] = {i, i + 1, i + 1, i};
      const int cj[4] = {j, j, j + 1, j + 1};
      bool in[4];
      int count = 0;
      // Proven cells: the node signs without their values (all kept or all removed).
      const auto proven = cell_state_at(i, j);
      current_cell = static_cast<std::size_t>(i) * nv + j;
      for (int k = 0; k < 4; ++k)
        count += (in[k] = proven == kOpen ? val(ci[k], cj[k]) > 0.0 : proven == kKept);
      if (count == 0) continue;
      if (count == 4) {
        emit({node(ci[0], cj[0]), node(ci[1], cj[1]), node(ci[2], cj[2]), node(ci[3], cj[3])});
        continue;
      }
      const bool saddle = count == 2 && in[0] == in[2];
      if (saddle && eval(0.5 * (pu(i) + pu(i + 1)), 0.5 * (pv(j) + pv(j + 1))) <= 0.0) {
        // Two separate corners.
        for (int k = 0; k < 4; ++k) {
          if (!in[k]) continue;
          const int kp = (k + 3) % 4, kn = (k + 1) % 4;
          emit({node(ci[k], cj[k]), edge(ci[k], cj[k], ci[kn], cj[kn]), edge(ci[kp], cj[kp], ci[k], cj[k])});
        }
        continue;
      }
      poly.clear();
      std::size_t leave_at = 0;
      for (int k = 0; k < 4; ++k) {
        const int kn = (k + 1) % 4;
        if (in[k]) poly.push_back(node(ci[k], cj[k]));
        if (in[k] != in[kn]) {
          poly.push_back(edge(ci[k], cj[k], ci[kn], cj[kn]));
          if (in[k]) leave_at = poly.size() - 1;
        }
      }
      const std::uint32_t leave = poly[leave_at], enter = poly[(leave_at + 1) % poly.size()];
      const std::int64_t corner = saddle ? -1 : corner_between(leave, enter, i, j);
      if (corner >= 0) {
        // Fanned from the corner, which sees the whole cell polygon.
        std::rotate(poly.begin(), poly.begin() + static_cast<std::ptrdiff_t>(leave_at + 1), poly.end());
        poly.insert(poly.begin(), static_cast<std::uint32_t>(corner));
      }
      emit(poly);
    }
  }
  // Kept blocks: their boundary with every node a neighbour created on it, fanned from the centre.
  for (const Block& b : kept_blocks) {
    poly.clear();
    for (int i = b.i0; i < b.i1; ++i)
      if (node_id[static_cast<std::size_t>(i) * sv + b.j0] >= 0) poly.push_back(node(i, b.j0));
    for (int j = b.j0; j < b.j1; ++j)
      if (node_id[static_cast<std::size_t>(b.i1) * sv + j] >= 0) poly.push_back(node(b.i1, j));
    for (int i = b.i1; i > b.i0; --i)
      if (node_id[static_cast<std::size_t>(i) * sv + b.j1] >= 0) poly.push_back(node(i, b.j1));
    for (int j = b.j1; j > b.j0; --j)
      if (node_id[static_cast<std::size_t>(b.i0) * sv + j] >= 0) poly.push_back(node(b.i0, j));
    if (poly.size() == 4) {
      emit(poly);
      continue;
    }
    const std::uint32_t centre = static_cast<std::uint32_t>(out.vertices.size());
    out.vertices.push_back(evaluate(patch, 0.5 * (pu(b.i0) + pu(b.i1)), 0.5 * (pv(b.j0) + pv(b.j1))));
    for (std::size_t k = 0; k < poly.size(); ++k) {
      Triangle t{centre, poly[k], poly[(k + 1) % poly.size()]};
      if (patch.flip) std::swap(t[1], t[2]);
      out.triangles.push_back(t);
    }
  }
  mark_border(out);
  return out;
}

// ---- patch construction --------------------------------------------------------------------

int steps_for_angle(double radius, double angle, double chord_tolerance, double max_cell) {
  double step = angle;
  if (radius > chord_tolerance) step = std::min(step, 2.0 * std::acos(1.0 - chord_tolerance / radius));
  if (max_cell > 0.0 && radius > 0.0) step = std::min(step, max_cell / radius);
  return std::max(1, static_cast<int>(std::ceil(std::abs(angle) / step - 1e-9)));
}

int steps_for_length(double length, double max_cell) {
  return std::max(1, static_cast<int>(std::ceil(length / max_cell - 1e-9)));
}

struct Budget {
  double tessellation;  // chord error of curved patches
  double cell;          // largest grid cell (trimming curve resolution)
};

void finish_patch(Patch& p) {
  // Bounds from a coarse sampling padded by the largest possible bulge between samples.
  Eigen::AlignedBox3d box;
  const int n = 8;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      box.extend(evaluate(p, static_cast<double>(i) / n, static_cast<double>(j) / n));
  double pad = 1e-9;
  if (p.form == Form::Tube || p.form == Form::Sphere || p.form == Form::Disc)
    pad += p.R * (1.0 - std::cos(M_PI / n));
  box.min().array() -= pad;
  box.max().array() += pad;
  p.box = box;
  // Orientation: compare the parameter normal with the result's outward normal.
  const double u = 0.37, v = 0.41, h = 1e-4;
  const Vector3d xu = evaluate(p, u + h, v) - evaluate(p, u - h, v);
  const Vector3d xv = evaluate(p, u, v + h) - evaluate(p, u, v - h);
  // Each patch bounds a convex solid (tool sweep, tool, box, cylinder) or is a mesh triangle.
  // A ball end's sphere patch spans its upper half too (trimmed away later), where the tool's
  // interior point does not see the sphere from inside: the sphere's own normal decides there.
  Vector3d outward = p.form == Form::Sphere ? solid_normal(p, u, v)
                     : p.has_interior       ? Vector3d(evaluate(p, u, v) - p.interior)
                                            : p.plane_normal;
  if (p.sweep) outward = -outward;
  p.flip = xu.cross(xv).dot(outward) < 0.0;
}

class PatchBuilder {
 public:
  PatchBuilder(const Context& ctx, Budget budget) : ctx_(ctx), budget_(budget) {}
  std::vector<Patch> patches;

  void plane(const Vector3d& o, const Vector3d& U, const Vector3d& V, const Vector3d& normal, Patch base) {
    base.form = Form::Plane;
    base.o = o;
    base.U = U;
    base.V = V;
    base.plane_normal = normal;
    base.nu = steps_for_length(U.norm(), budget_.cell);
    base.nv = steps_for_length(V.norm(), budget_.cell);
    add(base);
  }
  void tube(const Vector3d& o, const Vector3d& A, double R, const Vector3d& e1, const Vector3d& e2, double t0,
            double t1, Patch base) {
    base.form = Form::Tube;
    base.o = o;
    base.U = A;
    base.R = R;
    base.e1 = e1;
    base.e2 = e2;
    base.t0 = t0;
    base.t1 = t1;
    base.periodic_v = std::abs(std::abs(t1 - t0) - 2.0 * M_PI) < 1e-12;
    base.nu = steps_for_length(A.norm(), budget_.cell);
    base.nv = steps_for_angle(R, t1 - t0, budget_.tessellation, budget_.cell);
    if (base.periodic_v) base.nv = std::max(base.nv, 3);
    add(base);
  }
  // Sphere zone: azimuth f in [f0, f1] about w, polar angle t in [t0, t1] from w.
  void sphere(const Vector3d& c, double R, const Vector3d& w, const Vector3d& e1, double f0, double f1,
              double t0, double t1, Patch base) {
    base.form = Form::Sphere;
    base.o = c;
    base.R = R;
    base.w = w;
    base.e1 = e1;
    base.e2 = w.cross(e1);
    base.f0 = f0;
    base.f1 = f1;
    base.t0 = t0;
    base.t1 = t1;
    base.periodic_u = std::abs(std::abs(f1 - f0) - 2.0 * M_PI) < 1e-12;
    base.pole_v0 = t0 == 0.0;
    base.pole_v1 = t1 == M_PI;
    // Both directions curved: a cell's diagonal must keep the chord error, hence half the tolerance.
    base.nu = steps_for_angle(R, f1 - f0, 0.5 * budget_.tessellation, budget_.cell);
    base.nv = steps_for_angle(R, t1 - t0, 0.5 * budget_.tessellation, budget_.cell);
    if (base.periodic_u) base.nu = std::max(base.nu, 3);
    add(base);
  }
  void disc(const Vector3d& c, double R, const Vector3d& normal, Patch base) {
    base.form = Form::Disc;
    base.o = c;
    base.R = R;
    base.e1 = normal.unitOrthogonal();
    base.e2 = normal.cross(base.e1);
    base.plane_normal = normal;
    base.periodic_v = true;
    base.nu = steps_for_length(R, budget_.cell);
    base.nv = std::max(3, steps_for_angle(R, 2.0 * M_PI, budget_.tessellation, budget_.cell));
    add(base);
  }
  void triangle(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& normal, Patch base) {
    base.form = Form::Triangle;
    base.o = a;
    base.U = b - a;
    base.V = c - b;
    base.plane_normal = normal;
    base.nu = steps_for_length(std::max((b - a).norm(), (c - a).norm()), budget_.cell);
    base.nv = steps_for_length((c - b).norm(), budget_.cell);
    add(base);
  }

 private:
  void add(Patch& p) {
    finish_patch(p);
    if (!p.box.intersects(ctx_.stock_box)) return;
    // A tube one cell long (a short move) has grid lines only at its end profiles, which lie on
    // the neighbouring moves' sweeps. Near a stock face the part it keeps can be a strip bounded
    // by the face and another sweep that no grid edge meets (a raster's cusp within a cell of a
    // face parallel to the rows: the next row's tube keeps 0.04 wide between them, and no edge
    // scan can find it); a line through the middle profile meets it.
    if (p.sweep && p.form == Form::Tube && p.nu == 1 &&
        std::abs(ctx_.stock_distance(p.box.center())) <= 0.5 * p.box.diagonal().norm() + budget_.cell)
      p.nu = 2;
    patches.push_back(p);
  }
  const Context& ctx_;
  Budget budget_;
};

Vector3d horizontal_perpendicular(const Vector3d& d) {
  const Vector3d e = Vector3d::UnitZ().cross(d);
  return e.norm() > 1e-12 ? Vector3d(e.normalized()) : Vector3d::UnitX();
}

void add_stock_patches(const Job& job, PatchBuilder& builder) {
  Patch base;
  base.sweep = false;
  const Stock& stock = job.stock;
  base.has_interior = stock.type != StockType::Mesh;
  base.interior = stock.type == StockType::Cylinder
                      ? Vector3d(stock.base + 0.5 * stock.height * stock.axis.normalized())
                      : Vector3d(bounds(stock).center());
  switch (stock.type) {
    case StockType::Box: {
      const Vector3d lo = stock.box.min(), hi = stock.box.max(), s = hi - lo;
      const Vector3d X = Vector3d(s.x(), 0, 0), Y = Vector3d(0, s.y(), 0), Z = Vector3d(0, 0, s.z());
      const std::array<std::tuple<Vector3d, Vector3d, Vector3d, Vector3d>, 6> faces = {{
          {lo, Y, Z, -Vector3d::UnitX()},
          {lo + X, Y, Z, Vector3d::UnitX()},
          {lo, X, Z, -Vector3d::UnitY()},
          {lo + Y, X, Z, Vector3d::UnitY()},
          {lo, X, Y, -Vector3d::UnitZ()},
          {lo + Z, X, Y, Vector3d::UnitZ()},
      }};
      for (int f = 0; f < 6; ++f) {
        base.tag = {PatchKind::CutSurface, f, 0};
        builder.plane(std::get<0>(faces[f]), std::get<1>(faces[f]), std::get<2>(faces[f]),
                      std::get<3>(faces[f]), base);
      }
      break;
    }
    case StockType::Cylinder: {
      const Vector3d a = stock.axis.normalized();
      const Vector3d e1 = a.unitOrthogonal(), e2 = a.cross(e1);
      base.tag = {PatchKind::CutSurface, 0, 0};
      builder.tube(stock.base, stock.height * a, stock.radius, e1, e2, 0.0, 2.0 * M_PI, base);
      base.tag = {PatchKind::CutSurface, 1, 0};
      builder.disc(stock.base, stock.radius, -a, base);
      base.tag = {PatchKind::CutSurface, 2, 0};
      builder.disc(stock.base + stock.height * a, stock.radius, a, base);
      break;
    }
    case StockType::Mesh: {
      const TriangleMesh& m = stock.mesh;
      for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const Vector3d& p0 = m.vertices[m.triangles[t][0]];
        const Vector3d& p1 = m.vertices[m.triangles[t][1]];
        const Vector3d& p2 = m.vertices[m.triangles[t][2]];
        const Vector3d n = (p1 - p0).cross(p2 - p0);
        if (n.norm() <= 0.0) continue;
        base.tag = {PatchKind::CutSurface, static_cast<std::int32_t>(t), 0};
        builder.triangle(p0, p1, p2, n.normalized(), base);
      }
      break;
    }
  }
}

void add_side_sweep(const Context& ctx, int index, PatchBuilder& builder) {
  const Segment& s = ctx.segments[index];
  const Tool& tool = *s.tool;
  const Vector3d A = s.b - s.a;
  const double L = A.norm();
  const Vector3d d = A / L;
  const double r = tool.radius;
  Patch base;
  base.sweep = true;
  base.owner = index;
  base.segment = index;
  base.exclude[0] = index;
  base.adjacent[0] = s.prev;
  base.adjacent[1] = s.next;
  base.tag = {PatchKind::SideSweep, s.move, s.line};
  base.has_interior = true;
  base.interior = tool.type == ToolType::Sphere
                      ? Vector3d(s.a + 0.5 * A)
                      : Vector3d(s.a + 0.5 * A + (r + 0.5 * tool.length - 0.25 * r) * Vector3d::UnitZ());
  if (tool.type == ToolType::Sphere) {
    const Vector3d e1 = d.unitOrthogonal(), e2 = d.cross(e1);
    builder.tube(s.a, A, r, e1, e2, 0.0, 2.0 * M_PI, base);
    return;
  }
  // Ball end: tip sphere centre c = tip + r z, body up to c + length z.
  const Vector3d z = Vector3d::UnitZ();
  const Vector3d c0 = s.a + r * z;
  const double top_z = ctx.stock_box.max().z();
  const double lowest_centre = std::min(c0.z(), c0.z() + A.z());
  // Body height that can matter: above the stock's top nothing is kept.
  const double body = std::clamp(top_z - lowest_centre, 0.0, tool.length);
  const Vector3d horizontal(d.x(), d.y(), 0.0);
  if (horizontal.norm() < 1e-9) {
    // Plunge or retract: the contour generator is the whole body side.
    const Vector3d low = A.z() < 0 ? Vector3d(c0 + A) : c0;
    const double height = std::abs(A.z()) + tool.length;
    const double clipped = std::clamp(top_z - low.z(), 0.0, height);
    if (clipped > 100.0 * ctx.tie)
      builder.tube(low, clipped * z, r, Vector3d::UnitX(), Vector3d::UnitY(), 0.0, 2.0 * M_PI, base);
    return;
  }
  const Vector3d e1 = horizontal_perpendicular(d);
  const Vector3d e2 = d.cross(e1);  // e2.z = 1 - d.z^2 > 0
  // Lower half great circle perpendicular to d (normals with n.z <= 0).
  builder.tube(c0, A, r, e1, e2, M_PI, 2.0 * M_PI, base);
  if (body > 100.0 * ctx.tie) {
    // The two rulings of the body, swept.
    base.tag = {PatchKind::SideSweep, s.move, s.line};
    builder.plane(c0 + r * e1, A, body * z, e1, base);
    builder.plane(c0 - r * e1, A, body * z, -e1, base);
  }
  if (lowest_centre + tool.length < top_z) {
    const Vector3d top = c0 + tool.length * z;
    if (std::abs(d.z()) < 1e-12) {
      builder.plane(top - r * e1, A, 2.0 * r * e1, z, base);
    } else {
      // Half rim from e1 to -e1 through -sign(d.z) times the horizontal direction.
      const Vector3d g = -(d.z() > 0 ? 1.0 : -1.0) * horizontal.normalized();
      builder.tube(top, A, r, e1, g, 0.0, M_PI, base);
    }
  }
}

/// Front sweep: the tool's own surface at a chain vertex, kept outside the adjacent sweeps.
void add_front_sweep(const Context& ctx, int prev, int next, PatchBuilder& builder) {
  const Segment& s = ctx.segments[prev >= 0 ? prev : next];
  const Tool& tool = *s.tool;
  const Vector3d p = prev >= 0 ? s.b : s.a;
  const double r = tool.radius;
  Patch base;
  base.sweep = true;
  base.owner = prev >= 0 ? prev + 0.5 : next - 0.5;
  base.segment = prev >= 0 ? prev : next;
  base.at_vertex = true;
  base.tool_point = p;
  base.exclude[0] = base.adjacent[0] = prev;
  base.exclude[1] = base.adjacent[1] = next;
  const Segment& tag_seg = ctx.segments[next >= 0 ? next : prev];
  base.has_interior = true;
  base.interior = tool.type == ToolType::Sphere
                      ? p
                      : Vector3d(p + (r + 0.5 * tool.length - 0.25 * r) * Vector3d::UnitZ());
  base.tag = {PatchKind::FrontSweep, tag_seg.move, tag_seg.line};
  Vector3d dp = Vector3d::Zero(), dn = Vector3d::Zero();
  if (prev >= 0) dp = (ctx.segments[prev].b - ctx.segments[prev].a).normalized();
  if (next >= 0) dn = (ctx.segments[next].b - ctx.segments[next].a).normalized();
  auto set_rules = [&](Patch& patch, bool flat_top, const Vector3d& centre) {
    patch.rule_count = 0;
    patch.rule_centre = centre;
    patch.rule_radius = r;
    for (const auto& [dir, sign] : {std::make_pair(dp, 1.0), std::make_pair(dn, -1.0)}) {
      if (dir.squaredNorm() == 0.0) continue;
      OwnRule rule;
      rule.dir = sign * dir;
      rule.position = flat_top && std::abs(dir.z()) < 1e-12;
      if (flat_top && !rule.position) rule.dir = sign * (dir.z() > 0 ? 1.0 : -1.0) * Vector3d::UnitZ();
      patch.rules[patch.rule_count++] = rule;
    }
  };
  const Vector3d z = Vector3d::UnitZ();
  const bool ballend = tool.type == ToolType::BallEnd;
  const Vector3d c = ballend ? Vector3d(p + r * z) : p;
  // The tool's sphere outside both adjacent sweeps is exactly a lune between the great circles
  // normal to the two directions (a hemisphere at a path end): parametrised as such, its
  // borders are the side sweeps' end profiles. The ball end keeps its lower half (n.z <= 0).
  Patch ball = base;
  ball.rule_count = 0;
  if (ballend) ball.rules[ball.rule_count++] = OwnRule{-z, false};
  if (prev >= 0 && next >= 0) {
    Vector3d w = dp.cross(dn);
    const double turn = std::atan2(w.norm(), dp.dot(dn));
    w = w.norm() > 1e-12 ? Vector3d(w.normalized()) : dp.unitOrthogonal();
    builder.sphere(c, r, w, dp, -0.5 * M_PI, -0.5 * M_PI + turn, 0.0, M_PI, ball);
  } else {
    const Vector3d axis = prev >= 0 ? dp : Vector3d(-dn);
    builder.sphere(c, r, axis, axis.unitOrthogonal(), 0.0, 2.0 * M_PI, 0.0, 0.5 * M_PI, ball);
  }
  if (!ballend) return;
  // The body's side: the arc of horizontal normals n with n.dp >= 0 and n.dn <= 0.
  const double top_z = ctx.stock_box.max().z();
  const double body = std::clamp(top_z - c.z(), 0.0, tool.length);
  const Eigen::Vector2d a(dp.x(), dp.y()), b(dn.x(), dn.y());
  const bool level_prev = prev < 0 || a.norm() > 1e-9, level_next = next < 0 || b.norm() > 1e-9;
  if (body > 100.0 * ctx.tie && level_prev && level_next) {
    Eigen::Vector2d middle;
    double half_width = 0.5 * M_PI;
    if (prev >= 0 && next >= 0) {
      middle = a.normalized() - b.normalized();
      half_width = 0.5 * std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0));
    } else {
      middle = prev >= 0 ? Eigen::Vector2d(a.normalized()) : Eigen::Vector2d(-b.normalized());
    }
    if (half_width > 1e-12 && middle.norm() > 1e-12) {
      const double centre_angle = std::atan2(middle.y(), middle.x());
      Patch side = base;
      side.rule_count = 0;
      builder.tube(c, body * z, r, Vector3d::UnitX(), Vector3d::UnitY(), centre_angle - half_width,
                   centre_angle + half_width, side);
    }
  }
  if (c.z() + tool.length < top_z) {
    // The flat top: for a rising move the top disc leads (normal rule on +z); for a level move
    // the half ahead of the diameter belongs to this end (position rule).
    set_rules(base, true, c + tool.length * z);
    builder.disc(c + tool.length * z, r, z, base);
  }
}

/// Removes closed components that enclose no volume, and tiny open fragments: a band of a patch narrower than
/// the tie-break (a tool surface touching another sweep tangentially keeps a strip about sqrt(2 r tie) wide)
/// whose two sides the seam weld joined into a flat, doubly covered surface. No piece of a result is that
/// thin: its mean thickness 2 V / A is below `thickness`.
/// (`uses`: storage for the mesh's edge uses, reused.)
std::size_t remove_flat_components(TriangleMesh& mesh, std::vector<detail::TriangleOrigin>& patch_of,
                                   double thickness, double small_area, std::vector<detail::EdgeUse>& uses) {
  detail::sorted_edge_uses(mesh, uses);
  std::vector<std::uint32_t> component;
  const std::size_t count = detail::components_of_uses(mesh.triangles.size(), uses, component);
  if (count < 2) return 0;
  std::vector<double> volume(count, 0.0), area(count, 0.0);
  // Volumes about a point of each component: about the origin, rounding far from it would
  // swamp the volume of a small sliver.
  std::vector<Vector3d> origin(count, Vector3d::Zero());
  for (std::size_t i = mesh.triangles.size(); i-- > 0;)
    origin[component[i]] = mesh.vertices[mesh.triangles[i][0]];
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const Triangle& t = mesh.triangles[i];
    const Vector3d& o = origin[component[i]];
    const Vector3d a = mesh.vertices[t[0]] - o, b = mesh.vertices[t[1]] - o, c = mesh.vertices[t[2]] - o;
    volume[component[i]] += a.dot(b.cross(c)) / 6.0;
    area[component[i]] += 0.5 * (b - a).cross(c - a).norm();
  }
  // A component is open where the uses of one of its edges do not cancel (+1 for each use
  // min -> max, -1 for each max -> min). The uses, sorted by edge, lie together.
  std::vector<bool> open(count, false);
  for (std::size_t begin = 0; begin < uses.size();) {
    std::size_t end = begin;
    int sum = 0;
    for (; end < uses.size() && uses[end].key == uses[begin].key; ++end) sum += uses[end].forward ? 1 : -1;
    if (sum != 0)
      for (std::size_t i = begin; i < end; ++i) open[component[uses[i].triangle]] = true;
    begin = end;
  }
  std::vector<bool> drop(count, false);
  std::size_t dropped = 0;
  for (std::size_t c = 0; c < count; ++c) {
    // An open fragment smaller than a hundred tolerance squares is debris of the same kind
    // that did not close up: the piece of a solid it would bound is below the tolerance.
    // A closed one turned inside out that small is no void either: a void is the tool's size.
    const bool tiny = area[c] < small_area;
    drop[c] = !open[c] ? 2.0 * std::abs(volume[c]) < thickness * area[c] || (tiny && volume[c] < 0.0) : tiny;
    dropped += drop[c];
  }
  if (dropped == 0) return 0;
  std::vector<bool> remove(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) remove[i] = drop[component[i]];
  detail::remove_triangles(mesh, patch_of, remove);
  return dropped;
}

/// topology_report(mesh).boundary_edges alone: the edges with two distinct ends that exactly one
/// triangle with three distinct vertices uses.
std::size_t boundary_edge_count(const TriangleMesh& mesh, std::vector<detail::EdgeUse>& uses) {
  detail::sorted_edge_uses(mesh, uses);
  std::size_t count = 0;
  for (std::size_t begin = 0; begin < uses.size();) {
    std::size_t end = begin, proper = 0;
    for (; end < uses.size() && uses[end].key == uses[begin].key; ++end) {
      const Triangle& t = mesh.triangles[uses[end].triangle];
      proper += t[0] != t[1] && t[1] != t[2] && t[0] != t[2];
    }
    const bool loop = (uses[begin].key >> 32) == (uses[begin].key & 0xffffffffu);
    count += !loop && proper == 1;
    begin = end;
  }
  return count;
}

/// Signed distance to the surface a stock patch lies on (its face's plane, the cylinder's side):
/// zero on that face only, unlike the stock's distance, which vanishes on every face.
double stock_face_distance(const Patch& p, const Vector3d& x) {
  if (p.form == Form::Tube) {
    const Vector3d axis = p.U.normalized();
    const Vector3d radial = (x - p.o) - (x - p.o).dot(axis) * axis;
    return radial.norm() - p.R;
  }
  return (x - p.o).dot(p.plane_normal);
}

// The up-front memory estimate, fitted to the peak resident memory of the bundled jobs (see
// tests/morph/erode_estimate_test.cpp and docs/design/generator.md): a fixed part, the stock mesh, the
// segments with their capsules and bounds, the patches, and the tessellation cells of the patch
// grids (a cell is two triangles at most, with their share of vertices, edge uses and seams).
constexpr double kBytesFixed = 35.0 * (1 << 20);
// A mesh stock's triangle is also a patch of its own; 1000 + 400 bytes per triangle was measured on
// a 1M-triangle sphere stock (hostile reproducer sphere_5m_erode at a fifth of its size).
constexpr double kBytesPerStockTriangle = 1000.0;
constexpr double kBytesPerSegment = 600.0;
constexpr double kBytesPerPatch = 400.0;
constexpr double kBytesPerGridCell = 100.0;

void check_job(const Job& job, double tolerance) {
  if (!(tolerance > 0.0) || !std::isfinite(tolerance))
    throw InputError(job.file + ": tolerance must be positive, got " + std::to_string(tolerance));
  for (const Path& path : job.paths)
    for (const Move& move : path.moves) {
      const Tool& tool = job.tool_of(move);
      if (!tool.generator_builds())
        throw InputError(job.file + ": the move at line " + std::to_string(move.line) +
                         (path.source.empty() ? std::string() : " of " + path.source) + " uses tool " +
                         std::to_string(move.tool) + " (" + describe(tool) +
                         "), which generator 1 cannot build (sphere and ballend only); generator 2, the "
                         "default, builds every tool of revolution");
    }
  for (const auto& [number, tool] : job.tools) {
    if (!tool.generator_builds()) continue;
    if (!(tool.radius > 0.0))
      throw InputError(job.file + ": tool " + std::to_string(number) + " needs a positive radius");
    if (tool.type == ToolType::BallEnd && !(tool.length >= 0.0))
      throw InputError(job.file + ": tool " + std::to_string(number) + " needs a non-negative length");
  }
  check_tolerance_resolves(job, tolerance);
}

}  // namespace

ErodeResult erode(const Job& job, const ErodeOptions& options) {
  const auto t_start = Clock::now();
  const double tolerance = options.tolerance > 0.0 ? options.tolerance : job.tolerance;
  check_job(job, tolerance);
  Progress& progress = options.progress ? *options.progress : null_progress();
  ErodeResult result;
  ErodeStats& stats = result.stats;

  Context ctx;
  ctx.job = &job;
  ctx.stock_box = bounds(job.stock);
  const double scale = std::max(1.0, ctx.stock_box.sizes().maxCoeff());
  ctx.tie = 1e-11 * scale;
  ctx.trim_tolerance = tolerance;

  // Budget: arcs' chords 0.3, tessellation 0.35, trimming curves 0.35 of the tolerance.
  const double arc_chord = 0.3 * tolerance;
  double min_radius = std::numeric_limits<double>::infinity();
  for (const auto& [number, tool] : job.tools) min_radius = std::min(min_radius, tool.radius);
  if (!std::isfinite(min_radius)) min_radius = scale;
  for (const auto& [number, tool] : job.tools)
    ctx.max_depth = std::max(ctx.max_depth, tool.radius + 2.0 * ctx.tie);
  // A trimming curve is assumed to bend no tighter than the tool radius r; its chord over a cell
  // diagonal sqrt(2) h has sagitta 2 h^2 / (8 r) = h^2 / (4 r) <= 0.35 tol.
  Budget budget{0.35 * tolerance, std::sqrt(4.0 * min_radius * 0.35 * tolerance)};

  // What the job will cost, before anything large is built: arcs split into segments first,
  // straight runs joined (below).
  const int join_grid = grid_exponent_for(0.4 * tolerance);
  double segment_estimate = 0.0;
  for (const auto& [tool, count] : sweep_segment_counts(job, arc_chord, join_grid)) segment_estimate += count;
  const double stock_triangles =
      job.stock.type == StockType::Mesh ? double(job.stock.mesh.triangles.size()) : 0.0;
  const double stock_bytes = kBytesPerStockTriangle * stock_triangles;
  check_memory_cap(
      options, tolerance,
      kBytesFixed + stock_bytes + stock_triangles * kBytesPerPatch + segment_estimate * kBytesPerSegment,
      std::to_string(std::llround(segment_estimate)) + " segments (arcs as chords, straight runs joined), " +
          std::to_string(std::llround(stock_triangles)) + " stock triangles");
  // Only now the stock's own structures, the largest allocation for a big mesh stock.
  if (job.stock.type == StockType::Mesh) ctx.stock_mesh.emplace(job.stock.mesh);

  // Segments, chained.
  const std::vector<const Move*> moves = job.moves();
  stats.moves = moves.size();
  std::size_t global = 0;
  // A line going on straight along the line before it joins its segment, as in generator 2
  // (sweep_segments.h): the same swept solid, and CAM output at a fine step costs its lines.
  for (const Path& path : job.paths) {
    int last = -1;
    bool last_is_line = false;
    for (const Move& move : path.moves) {
      const int move_index = static_cast<int>(global++);
      const Tool& tool = job.tool_of(move);
      const std::vector<double> ts = chord_parameters(move, arc_chord);
      Eigen::AlignedBox3d move_box = swept_bounds(tool, move);
      if (move_box.intersects(ctx.stock_box)) ++stats.moves_touching_stock;
      for (std::size_t k = 0; k + 1 < ts.size(); ++k) {
        Segment seg;
        seg.a = point_at(move, ts[k]);
        seg.b = point_at(move, ts[k + 1]);
        if ((seg.b - seg.a).norm() <= 1e-12 * scale) continue;
        seg.tool = &tool;
        seg.move = move_index;
        seg.line = move.line;
        Move straight;
        straight.start = seg.a;
        straight.end = seg.b;
        seg.box = swept_bounds(tool, straight);
        if (last >= 0 && last_is_line && !move.is_arc() && ctx.segments[last].tool == &tool &&
            ctx.segments[last].b == seg.a &&
            goes_on_straight(ctx.segments[last].a, seg.a, seg.b, join_grid)) {
          Segment& joined = ctx.segments[last];
          joined.b = seg.b;
          straight.start = joined.a;
          joined.box = swept_bounds(tool, straight);
          continue;
        }
        last_is_line = !move.is_arc();
        const int index = static_cast<int>(ctx.segments.size());
        if (last >= 0 && ctx.segments[last].tool == &tool &&
            (ctx.segments[last].b - seg.a).norm() <= 1e-9 * scale) {
          seg.prev = last;
          ctx.segments[last].next = index;
        }
        ctx.segments.push_back(seg);
        last = index;
      }
    }
  }
  stats.segments = ctx.segments.size();
  ctx.capsules.reserve(ctx.segments.size());
  for (const Segment& s : ctx.segments) ctx.capsules.emplace_back(*s.tool, s.a, s.b);
  {
    std::vector<Eigen::AlignedBox3d> boxes;
    boxes.reserve(ctx.segments.size());
    for (const Segment& s : ctx.segments) boxes.push_back(s.box);
    ctx.tree = AabbTree(std::move(boxes));
  }

  PatchBuilder builder(ctx, budget);
  add_stock_patches(job, builder);
  for (int i = 0; i < static_cast<int>(ctx.segments.size()); ++i) {
    const Segment& s = ctx.segments[i];
    if (!s.box.intersects(ctx.stock_box)) continue;
    add_side_sweep(ctx, i, builder);
    if (s.prev < 0) add_front_sweep(ctx, -1, i, builder);
    if (s.next < 0) {
      add_front_sweep(ctx, i, -1, builder);
    } else {
      const Segment& n = ctx.segments[s.next];
      const Vector3d d0 = (s.b - s.a).normalized(), d1 = (n.b - n.a).normalized();
      if (d0.cross(d1).norm() > 1e-12 || d0.dot(d1) < 0.0) add_front_sweep(ctx, i, s.next, builder);
    }
  }
  const std::vector<Patch>& patches = builder.patches;
  stats.patches = patches.size();
  // A triangle's grid spans the parallelogram on two of its sides: half its cells lie inside.
  for (const Patch& p : patches)
    stats.grid_cells += (p.form == Form::Triangle ? 0.5 : 1.0) * double(p.nu) * double(p.nv);
  stats.estimated_bytes = kBytesFixed + stock_bytes + double(ctx.segments.size()) * kBytesPerSegment +
                          double(patches.size()) * kBytesPerPatch + stats.grid_cells * kBytesPerGridCell;
  check_memory_cap(options, tolerance, stats.estimated_bytes,
                   std::to_string(patches.size()) + " patches with " +
                       std::to_string(std::llround(stats.grid_cells)) + " tessellation cells");
  stats.seconds_setup = seconds_since(t_start);

  // Trim every patch independently.
  const auto t_trim = Clock::now();
  std::vector<PatchMesh> pieces(patches.size());
  progress.begin("erode: patches", patches.size());
  // The searches are counted patch by patch: their sum depends on the job alone, so whether it
  // passes the limit does too (the running sum only stops the work early once it has).
  std::atomic<std::uint64_t> searches{0};
  const std::uint64_t search_limit = options.search_limit;
  auto over_limit = [&] {
    return search_limit > 0 && searches.load(std::memory_order_relaxed) > search_limit;
  };
  for_each_index(options.policy, 0, patches.size(), [&](std::size_t i) {
    if (progress.interrupted() || over_limit()) return;
    pieces[i] = trim_patch(ctx, patches[i]);
    searches.fetch_add(pieces[i].searches, std::memory_order_relaxed);
    progress.advance(1);
  });
  progress.end();
  if (progress.interrupted()) throw Interrupted("erode: interrupted");
  if (over_limit())
    throw SearchLimitError(job.file + ": generator 1 ran more than " + std::to_string(search_limit) +
                           " distance searches (its search limit)");
  stats.searches = searches.load();
  stats.seconds_trim = seconds_since(t_trim);

  // Assemble in patch order, then join the patches along their trimming curves.
  const auto t_assemble = Clock::now();
  TriangleMesh& mesh = result.mesh;
  std::vector<detail::TriangleOrigin> patch_of_triangle;
  {
    // Where each kept piece's vertices and triangles go, then the copies in parallel.
    std::vector<std::size_t> first_vertex(pieces.size() + 1, 0), first_triangle(pieces.size() + 1, 0);
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      const bool kept = !pieces[i].triangles.empty();
      stats.patches_kept += kept;
      first_vertex[i + 1] = first_vertex[i] + (kept ? pieces[i].vertices.size() : 0);
      first_triangle[i + 1] = first_triangle[i] + pieces[i].triangles.size();
    }
    detail::reserve_large(mesh.vertices, first_vertex.back());
    // Room for the seams' splits, which grow the arrays in place (untouched room costs nothing).
    const std::size_t room = first_triangle.back() + first_triangle.back() / 8;
    detail::reserve_large(mesh.triangles, room);
    detail::reserve_large(mesh.tags, room);
    detail::reserve_large(patch_of_triangle, room);
    mesh.vertices.resize(first_vertex.back());
    mesh.triangles.resize(first_triangle.back());
    mesh.tags.resize(first_triangle.back());
    patch_of_triangle.resize(first_triangle.back());
    for_each_index(options.policy, 0, pieces.size(), [&](std::size_t i) {
      PatchMesh& piece = pieces[i];
      if (piece.triangles.empty()) return;
      const std::uint32_t offset = static_cast<std::uint32_t>(first_vertex[i]);
      std::copy(piece.vertices.begin(), piece.vertices.end(), mesh.vertices.begin() + first_vertex[i]);
      for (std::size_t k = 0; k < piece.triangles.size(); ++k) {
        const Triangle& t = piece.triangles[k];
        const std::size_t j = first_triangle[i] + k;
        mesh.triangles[j] = {t[0] + offset, t[1] + offset, t[2] + offset};
        mesh.tags[j] = patches[i].tag;
        patch_of_triangle[j] = {static_cast<std::uint32_t>(i), piece.border[k]};
      }
      piece = PatchMesh();
    });
  }
  detail::SeamOptions seam;
  seam.weld_distance = 1e-9 * scale;
  seam.snap_distance = 0.2 * tolerance;
  seam.match_distance = 0.5 * tolerance;
  seam.cell = budget.cell;
  seam.hole_diameter = 4.0 * budget.cell;
  // Far above the rounding of the distances.
  const double skip_margin = 1e3 * ctx.tie;
  auto least_sweep_distance = [&](const Vector3d& x) {
    // The least sweep distance at x: its exact value wherever a sweep holds x or comes nearer
    // than the least of those holding x; others only as far as they could lower it. Capped at
    // its running minimum, each distance is exact wherever that changes (the body's search
    // stops once it cannot); a sweep proven no nearer is skipped. The same minimum as the
    // tree's best-first search, without its queue.
    double least = std::numeric_limits<double>::infinity();
    auto visit = [&](std::size_t j) {
      if (sweep_at_least(ctx.capsules[j], x, least + skip_margin)) return;
      const Segment& s = ctx.segments[j];
      least = std::min(least, sweep_distance(*s.tool, s.a, s.b, x, least));
    };
    ctx.tree.for_each_overlapping(Eigen::AlignedBox3d(x, x), visit);
    double nearest = least;
    if (!std::isfinite(least)) {
      // No sweep's bounds hold x: the tree's search.
      ctx.tree.nearest(
          x,
          [&](std::size_t j) {
            const Segment& s = ctx.segments[j];
            const double d = sweep_distance(*s.tool, s.a, s.b, x, least);
            least = std::min(least, d);
            return d;
          },
          &nearest, ctx.max_depth);
    } else if (least > 0.0) {
      // Outside every sweep holding x: those whose bounds come nearer than that may be nearer.
      Eigen::AlignedBox3d query(x, x);
      query.min().array() -= least;
      query.max().array() += least;
      ctx.tree.for_each_overlapping(query, [&](std::size_t j) {
        const double outside = ctx.segments[j].box.exteriorDistance(x);
        if (outside > 0.0 && outside < least) visit(j);
      });
      nearest = least;
    }
    return nearest;
  };
  // The fills and repairs ask about many points close together (a hole, a repair's ball). Around
  // a point c where the search above ran, the sweeps that can be the nearest anywhere within
  // `near_reach` of it are kept (per thread), ordered by a lower bound of their distance at c:
  // a sweep whose distance at c exceeds the least there by more than twice the reach is farther
  // than that least sweep at every such point (distances are 1-Lipschitz). The value is the
  // same minimum, computed exactly as above; `generation` tells this call's sweeps from another's.
  static std::atomic<std::uint64_t> generations{0};
  const std::uint64_t generation = ++generations;
  const double near_reach = budget.cell;
  struct NearSweeps {
    std::uint64_t generation = 0;
    Vector3d centre = Vector3d::Zero();
    std::vector<std::pair<double, std::uint32_t>> sweeps;  // (lower bound at centre, segment)
  };
  const detail::FieldFunction field = [&](const Vector3d& x) {
    thread_local NearSweeps near;
    double least = std::numeric_limits<double>::infinity();
    const double moved = (x - near.centre).norm();
    if (near.generation == generation && moved <= near_reach) {
      for (const auto& [lower, j] : near.sweeps) {
        if (lower - moved >= least + skip_margin) break;  // and so are all after it
        if (sweep_at_least(ctx.capsules[j], x, least + skip_margin)) continue;
        const Segment& s = ctx.segments[j];
        least = std::min(least, sweep_distance(*s.tool, s.a, s.b, x, least));
      }
      return std::max(ctx.stock_distance(x), -least);
    }
    least = least_sweep_distance(x);
    near.generation = 0;
    if (std::isfinite(least)) {
      near.generation = generation;
      near.centre = x;
      near.sweeps.clear();
      const double reach = least + 2.0 * near_reach + skip_margin;
      Eigen::AlignedBox3d query(x, x);
      query.min().array() -= std::max(reach, 0.0);
      query.max().array() += std::max(reach, 0.0);
      ctx.tree.for_each_overlapping(query, [&](std::size_t j) {
        const Segment& s = ctx.segments[j];
        const double lower = sweep_distance_bounds(*s.tool, s.a, s.b, x).first;
        if (lower <= reach) near.sweeps.push_back({lower, static_cast<std::uint32_t>(j)});
      });
      std::sort(near.sweeps.begin(), near.sweeps.end());
    }
    return std::max(ctx.stock_distance(x), -least);
  };
  const detail::SeamStats seam_stats = detail::join_seams(
      mesh, patch_of_triangle, seam,
      [&](std::size_t patch, const Vector3d& x) {
        const Patch& p = patches[patch];
        if (!p.sweep) return stock_face_distance(p, x);
        const Segment& s = ctx.segments[p.segment];
        if (p.at_vertex) return tool_signed_distance(*s.tool, p.tool_point, x);
        return sweep_distance(*s.tool, s.a, s.b, x);
      },
      field);
  // Small defects left where several patches meet at a singular contact: replaced by a fan
  // whose every triangle is checked against the exact field. First the welds within a fifth of
  // the tolerance: where the joints of two raster rows line up across the cusp between them,
  // a joint's cap and the side patch meet the cusp 0.00104 apart at tolerance 0.01 and fold a
  // sliver over between them.
  std::vector<detail::EdgeUse> edge_uses;  // storage reused by the passes below
  detail::weld_near_defects(mesh, patch_of_triangle, 2e-1 * tolerance, edge_uses);
  detail::RepairOptions repair;
  repair.max_radius = 2.0 * budget.cell;
  repair.max_field_error = 0.5 * tolerance;
  // The second pass retries only the defects a repair of the first came near.
  detail::RepairMemory first_passes;
  // Each pass after the first looks for defects only where the one before left or made them.
  detail::DefectSuspects suspects;
  detail::RepairStats repair_stats =
      detail::repair_small_defects(mesh, patch_of_triangle, repair, field, &first_passes, &suspects);
  // Another pass over what is left: the defects it finds are those not yet repaired.
  auto repair_again = [&](detail::RepairMemory* memory) {
    const detail::RepairStats again =
        detail::repair_small_defects(mesh, patch_of_triangle, repair, field, memory, &suspects);
    repair_stats.repaired += again.repaired;
    repair_stats.defects = repair_stats.repaired + (again.defects - again.repaired);
  };
  // A second pass sees the spots whose ring was itself defective until a neighbour was mended.
  if (repair_stats.repaired > 0 && repair_stats.repaired < repair_stats.defects) repair_again(&first_passes);
  // Defects wider than the cell: where several sweeps lie within the tolerance of each other
  // (equal tools crossing at one depth) trimming cannot tell them apart and their pieces overlap;
  // a sliver gap along a seam is one loop only when grouped at a coarser spacing.
  for (int widen = 0; widen < 2 && repair_stats.defects > repair_stats.repaired; ++widen) {
    repair.max_radius *= 2.0;
    repair.max_field_error = 0.8 * tolerance;
    repair_again(nullptr);
  }
  // Two fans left meeting at one vertex: slivers a ten-thousandth of the tolerance wide meet at
  // the pinch (a joint's cap and the cusp between two rows), and no fan around it fits. Welded
  // into the pinch like the open spots above, they leave one fan the repair can replace. (Without
  // any defect found no repair ran, and the repair counts pinched vertices as defects.)
  // Pinches are defects of the repair too: the last pass's suspects hold them all.
  if (repair_stats.defects > 0 &&
      detail::weld_near_pinches(mesh, patch_of_triangle, 2e-1 * tolerance,
                                suspects.known ? &suspects.vertices : nullptr) > 0) {
    suspects.known = false;  // the weld renumbered and changed fans anywhere
    repair.max_radius = 2.0 * budget.cell;
    repair.max_field_error = 0.5 * tolerance;
    repair_again(nullptr);
  }
  stats.defects_repaired = repair_stats.repaired;
  stats.flat_components_removed = remove_flat_components(mesh, patch_of_triangle, 1e-3 * tolerance,
                                                         100.0 * tolerance * tolerance, edge_uses);
  stats.open_edges = repair_stats.defects == repair_stats.repaired ? 0 : boundary_edge_count(mesh, edge_uses);
  stats.seam_splits = seam_stats.splits;
  stats.corner_holes = seam_stats.holes_filled;
  stats.steps = {{"seam_splits", stats.seam_splits},
                 {"corner_holes", stats.corner_holes},
                 {"defects_repaired", stats.defects_repaired},
                 {"flat_components_removed", stats.flat_components_removed}};
  stats.triangles = mesh.triangles.size();
  stats.vertices = mesh.vertices.size();
  stats.seconds_assemble = seconds_since(t_assemble);
  stats.seconds_total = seconds_since(t_start);
  return result;
}

}  // namespace morph
