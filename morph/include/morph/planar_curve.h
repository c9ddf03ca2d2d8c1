// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file planar_curve.h
/// The boundary elements of the paper's two-dimensional model: line segments and circular arcs,
/// each with its provenance (a stock element, or a move of the trajectory and its G-code line).
/// All lengths in job units, angles in radians.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace morph::planar {

using Vec2 = Eigen::Vector2d;
using Box2 = Eigen::AlignedBox2d;

/// z component of the cross product.
inline double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}
/// `v` turned a quarter turn counter-clockwise.
inline Vec2 left_normal(const Vec2& v) {
  return Vec2(-v.y(), v.x());
}

/// What produced a boundary element.
enum class Origin : std::uint8_t {
  Stock = 0,   ///< an element of the stock's boundary (source = element index over all loops)
  Sweep = 1,   ///< the boundary of a move's dilation (source = move index)
  Offset = 2,  ///< the boundary of a stock element's dilation (classical erosion; source = element)
};

struct Provenance {
  Origin origin = Origin::Stock;
  std::int32_t source = -1;  ///< stock element index or global move index
  std::int32_t line = 0;     ///< G-code line of the move (or input element line), 0 if none
};

/// A line segment (sweep == 0) or a circular arc from `start` to `end`. An arc turns about
/// `center` by `sweep` radians (positive counter-clockwise, |sweep| <= 2*pi; a full circle has
/// start == end and |sweep| == 2*pi); `start` and `end` lie on its circle of `radius`.
struct Curve {
  Vec2 start = Vec2::Zero();
  Vec2 end = Vec2::Zero();
  Vec2 center = Vec2::Zero();
  double radius = 0.0;
  double sweep = 0.0;
  Provenance from;

  bool is_arc() const { return sweep != 0.0; }
};

/// A segment from a to b.
Curve make_segment(const Vec2& a, const Vec2& b, Provenance from = {});
/// The arc about `center` from angle `angle0` turning by `sweep` (radius r > 0).
Curve make_arc(const Vec2& center, double r, double angle0, double sweep, Provenance from = {});
/// The arc about `center` from `a` to `b`, counter-clockwise if ccw (b is put on the circle of a).
/// a == b gives a full circle.
Curve make_arc_between(const Vec2& center, const Vec2& a, const Vec2& b, bool ccw, Provenance from = {});
/// The arc from a to b with DXF/LWPOLYLINE `bulge` = tan(sweep / 4) (0 gives a segment).
Curve make_bulge(const Vec2& a, const Vec2& b, double bulge, Provenance from = {});

/// Angle of `start` about the centre (arcs).
double start_angle(const Curve& c);
/// Point at parameter t in [0, 1] (uniform in arc length).
Vec2 point_at(const Curve& c, double t);
/// Unit tangent at t, in the direction of travel.
Vec2 tangent_at(const Curve& c, double t);
/// Signed curvature: +1/r for counter-clockwise arcs, -1/r clockwise, 0 for segments.
double curvature(const Curve& c);
/// Length (exact).
double length(const Curve& c);
/// The curve's contribution to a closed loop's signed area: the shoelace term of its chord plus,
/// for an arc, the signed area of the circular segment between arc and chord (exact).
double area_term(const Curve& c);
/// Exact bounding box (arcs include their axis-extreme points).
Box2 bounds(const Curve& c);
/// The same curve travelled the other way.
Curve reversed(const Curve& c);
/// The piece between parameters t0 < t1 with the given end points (already on the curve).
Curve sub_curve(const Curve& c, double t0, double t1, const Vec2& p0, const Vec2& p1);

/// Closest point of the curve to p, with its parameter.
struct ClosestPoint {
  Vec2 point;
  double t = 0.0;
  double distance = 0.0;
};
ClosestPoint closest_point(const Curve& c, const Vec2& p);
/// Parameter of the point of the curve nearest to p (p is expected to lie on the curve).
double parameter_of(const Curve& c, const Vec2& p);

}  // namespace morph::planar
