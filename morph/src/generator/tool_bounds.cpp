// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/tool_bounds.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace morph {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kSlack = 1e-9;

// Radius of the largest ball about (0, 0, z) inside the tool: a minimum of affine functions of
// z, so concave, and maximised by ternary search.
double inscribed_radius(const ConvexPolytope& tool, double z) {
  double r = std::numeric_limits<double>::infinity();
  for (const PolytopeFacet& f : tool.facets) r = std::min(r, f.offset - f.normal.z() * z);
  return r;
}

// Radius of the largest axis cylinder over [z0, z1] inside the tool (0 if none).
double inscribed_cylinder(const ConvexPolytope& tool, double z0, double z1) {
  double r = std::numeric_limits<double>::infinity();
  for (const PolytopeFacet& f : tool.facets) {
    const double horizontal = std::hypot(f.normal.x(), f.normal.y());
    const double height = std::max(f.normal.z() * z0, f.normal.z() * z1);
    if (horizontal > 1e-12)
      r = std::min(r, (f.offset - height) / horizontal);
    else if (height > f.offset + kSlack)
      return 0.0;
  }
  return std::max(0.0, r);
}

// The parameters t in [0, 1] with lo <= z0 + t·dz <= hi, as [t0, t1]; false if none.
bool height_interval(double z0, double dz, double lo, double hi, double& t0, double& t1) {
  t0 = 0.0;
  t1 = 1.0;
  if (dz == 0.0) return lo <= z0 && z0 <= hi;
  double u = (lo - z0) / dz, v = (hi - z0) / dz;
  if (u > v) std::swap(u, v);
  t0 = std::max(t0, u);
  t1 = std::min(t1, v);
  return t0 <= t1;
}

double point_segment_distance(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
  const Vector3d d = b - a;
  const double dd = d.squaredNorm();
  const double t = dd > 0.0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

// Distance between the segments [p0, p1] and [q0, q1] (closest points by clamped parameters).
double segment_distance(const Vector3d& p0, const Vector3d& p1, const Vector3d& q0, const Vector3d& q1) {
  const Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  if (a <= 0.0) return point_segment_distance(p0, q0, q1);
  if (e <= 0.0) return point_segment_distance(q0, p0, p1);
  const double b = d1.dot(d2), c = d1.dot(r), denominator = a * e - b * b;
  double s = denominator > 0.0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1.0) {
    t = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  return (p0 + s * d1 - (q0 + t * d2)).norm();
}

// Distance in the xy plane from p to the segment a + t·(b - a), t in [t0, t1].
double xy_distance(const Vector3d& p, const Vector3d& a, const Vector3d& b, double t0, double t1) {
  const Vector2d q = p.head<2>(), from = a.head<2>(), d = (b - a).head<2>();
  const double dd = d.squaredNorm();
  const double t = dd > 0.0 ? std::clamp((q - from).dot(d) / dd, t0, t1) : t0;
  return (q - (from + t * d)).norm();
}

}  // namespace

double core_distance(const ToolBounds& bounds, const Vector3d& a, const Vector3d& b, const Vector3d& x) {
  const Vector3d c(0.0, 0.0, bounds.centre_height);
  return point_segment_distance(x, a + c, b + c);
}

ToolBounds tool_bounds(const ConvexPolytope& tool) {
  if (tool.facets.empty()) throw InputError("tool bounds: the tool polytope is empty");
  ToolBounds bounds;
  const Eigen::AlignedBox3d box = tool.bounds();
  bounds.bottom = box.min().z();
  bounds.top = box.max().z();
  double lo = bounds.bottom, hi = bounds.top;
  for (int i = 0; i < 200 && hi - lo > 1e-12 * (1.0 + bounds.top - bounds.bottom); ++i) {
    const double m1 = lo + (hi - lo) / 3.0, m2 = hi - (hi - lo) / 3.0;
    if (inscribed_radius(tool, m1) < inscribed_radius(tool, m2))
      lo = m1;
    else
      hi = m2;
  }
  // The lowest height of (nearly) that radius: a shank's plateau would otherwise leave the
  // centre anywhere along it, and the outer ball, which holds all below the centre, would grow.
  const double best = inscribed_radius(tool, 0.5 * (lo + hi)) - kSlack;
  double below = bounds.bottom, above = 0.5 * (lo + hi);
  for (int i = 0; i < 200 && above - below > 1e-12 * (1.0 + bounds.top - bounds.bottom); ++i) {
    const double middle = 0.5 * (below + above);
    (inscribed_radius(tool, middle) >= best ? above : below) = middle;
  }
  bounds.centre_height = above;
  bounds.inner_radius = std::max(0.0, inscribed_radius(tool, bounds.centre_height));
  bounds.cylinder_radius = inscribed_cylinder(tool, bounds.centre_height, bounds.top);
  const Vector3d c(0.0, 0.0, bounds.centre_height);
  for (const Vector3d& v : tool.vertices) {
    bounds.max_radius = std::max(bounds.max_radius, v.head<2>().norm());
    if (v.z() <= bounds.centre_height) bounds.outer_radius = std::max(bounds.outer_radius, (v - c).norm());
  }
  // The section at centre_height lies within max_radius of c.
  bounds.outer_radius = std::max(bounds.outer_radius, bounds.max_radius);
  return bounds;
}

namespace {

bool in_capsule(const ToolBounds& bounds, double core, double radius) {
  return core + radius <= bounds.inner_radius - kSlack;
}

bool in_capsule(const ToolBounds& bounds, const Vector3d& a, const Vector3d& b, const Vector3d& centre,
                double radius) {
  return in_capsule(bounds, core_distance(bounds, a, b, centre), radius);
}

// Inside the inner cylinder at one position a + t(b - a): its [z + centre_height, z + top]
// holds the ball's heights, and its axis is near enough in xy.
bool in_swept_cylinder(const ToolBounds& bounds, const Vector3d& a, const Vector3d& b, const Vector3d& centre,
                       double radius) {
  if (bounds.cylinder_radius <= radius + kSlack) return false;
  double t0, t1;
  if (!height_interval(a.z(), b.z() - a.z(), centre.z() + radius - bounds.top,
                       centre.z() - radius - bounds.centre_height, t0, t1))
    return false;
  return xy_distance(centre, a, b, t0, t1) + radius <= bounds.cylinder_radius - kSlack;
}

}  // namespace

bool ball_inside_sweep(const ToolBounds& bounds, const Vector3d& a, const Vector3d& b, const Vector3d& centre,
                       double radius) {
  return in_capsule(bounds, a, b, centre, radius) || in_swept_cylinder(bounds, a, b, centre, radius);
}

namespace {

// ball_misses_sweep(), given the ball's centre's core_distance().
bool misses(const ToolBounds& bounds, const Vector3d& a, const Vector3d& b, const Vector3d& centre,
            double radius, double core) {
  if (core <= bounds.outer_radius + radius + kSlack) return false;
  // Positions whose upper cylinder [z + centre_height, z + top] meets the ball's heights.
  double t0, t1;
  if (!height_interval(a.z(), b.z() - a.z(), centre.z() - radius - bounds.top,
                       centre.z() + radius - bounds.centre_height, t0, t1))
    return true;
  return xy_distance(centre, a, b, t0, t1) > bounds.max_radius + radius + kSlack;
}

}  // namespace

BallVerdict ball_against_sweep(const ToolBounds& bounds, const Vector3d& a, const Vector3d& b,
                               const Vector3d& centre, double radius, double* core_out) {
  const double core = core_distance(bounds, a, b, centre);
  if (core_out) *core_out = core;
  if (in_capsule(bounds, core, radius) || in_swept_cylinder(bounds, a, b, centre, radius))
    return BallVerdict::Inside;
  return misses(bounds, a, b, centre, radius, core) ? BallVerdict::Misses : BallVerdict::Unknown;
}

Eigen::AlignedBox3d inner_box(const ToolBounds& bounds, const Vector3d& a, const Vector3d& b) {
  Eigen::AlignedBox3d box;
  const Vector3d low = a.cwiseMin(b), high = a.cwiseMax(b);
  if (bounds.inner_radius > kSlack) {
    const Vector3d c(0.0, 0.0, bounds.centre_height);
    box.extend(Eigen::AlignedBox3d(low + c, high + c));
    box.min().array() -= bounds.inner_radius;
    box.max().array() += bounds.inner_radius;
  }
  if (bounds.cylinder_radius > kSlack) {
    const double r = bounds.cylinder_radius;
    box.extend(Eigen::AlignedBox3d(Vector3d(low.x() - r, low.y() - r, low.z() + bounds.centre_height),
                                   Vector3d(high.x() + r, high.y() + r, high.z() + bounds.top)));
  }
  if (box.isEmpty()) return box;
  const double margin =
      kSlack + 1e-9 * (1.0 + box.min().cwiseAbs().cwiseMax(box.max().cwiseAbs()).maxCoeff());
  box.min().array() -= margin;
  box.max().array() += margin;
  return box;
}

namespace {

// The inner bounds' tests of points (radius 0) against one sweep, with what depends on the sweep
// alone worked out once: the same arithmetic as in_capsule() and in_swept_cylinder(), bit for bit.
class InnerTests {
 public:
  InnerTests(const ToolBounds& bounds, const Vector3d& a, const Vector3d& b)
      : bounds_(bounds),
        a_(a),
        b_(b),
        core_from_(a + Vector3d(0.0, 0.0, bounds.centre_height)),
        core_(b + Vector3d(0.0, 0.0, bounds.centre_height) - core_from_),
        core_length2_(core_.squaredNorm()),
        xy_(a.head<2>()),
        xy_motion_((b - a).head<2>()),
        xy_length2_(xy_motion_.squaredNorm()) {}

  bool in_capsule(const Vector3d& x) const {
    const double t =
        core_length2_ > 0.0 ? std::clamp((x - core_from_).dot(core_) / core_length2_, 0.0, 1.0) : 0.0;
    return (x - (core_from_ + t * core_)).norm() <= bounds_.inner_radius - kSlack;
  }

  bool in_cylinder(const Vector3d& x) const {
    if (bounds_.cylinder_radius <= kSlack) return false;
    double t0, t1;
    if (!height_interval(a_.z(), b_.z() - a_.z(), x.z() - bounds_.top, x.z() - bounds_.centre_height, t0, t1))
      return false;
    const Vector2d q = x.head<2>();
    const double t = xy_length2_ > 0.0 ? std::clamp((q - xy_).dot(xy_motion_) / xy_length2_, t0, t1) : t0;
    return (q - (xy_ + t * xy_motion_)).norm() <= bounds_.cylinder_radius - kSlack;
  }

 private:
  const ToolBounds& bounds_;
  const Vector3d &a_, &b_;
  const Vector3d core_from_, core_;
  const double core_length2_;
  const Vector2d xy_, xy_motion_;
  const double xy_length2_;
};

}  // namespace

bool points_inside_sweep(const ToolBounds& bounds, const Vector3d& a, const Vector3d& b,
                         const std::vector<Vector3d>& points) {
  const InnerTests inner(bounds, a, b);
  return std::all_of(points.begin(), points.end(), [&](const Vector3d& x) { return inner.in_capsule(x); }) ||
         std::all_of(points.begin(), points.end(), [&](const Vector3d& x) { return inner.in_cylinder(x); });
}

bool any_point_inside_sweep(const ToolBounds& bounds, const Vector3d& a, const Vector3d& b,
                            const std::vector<Vector3d>& points) {
  const InnerTests inner(bounds, a, b);
  return std::any_of(points.begin(), points.end(),
                     [&](const Vector3d& x) { return inner.in_capsule(x) || inner.in_cylinder(x); });
}

bool ball_misses_sweep(const ToolBounds& bounds, const Vector3d& a, const Vector3d& b, const Vector3d& centre,
                       double radius, double* core_out) {
  const double core = core_distance(bounds, a, b, centre);
  if (core_out) *core_out = core;
  return misses(bounds, a, b, centre, radius, core);
}

}  // namespace morph

namespace morph {

bool capsule_misses_sweep(const ToolBounds& bounds, const Vector3d& a, const Vector3d& b,
                          const Vector3d& from, const Vector3d& to, double radius) {
  const Vector3d c(0.0, 0.0, bounds.centre_height);
  if (segment_distance(from, to, a + c, b + c) <= bounds.outer_radius + radius + kSlack) return false;
  // The upper cylinder against the ball holding the capsule.
  const double half = 0.5 * (to - from).norm() + radius;
  const Vector3d centre = 0.5 * (from + to);
  double t0, t1;
  if (!height_interval(a.z(), b.z() - a.z(), centre.z() - half - bounds.top,
                       centre.z() + half - bounds.centre_height, t0, t1))
    return true;
  return xy_distance(centre, a, b, t0, t1) > bounds.max_radius + half + kSlack;
}

}  // namespace morph
