// SPDX-License-Identifier: Apache-2.0
#pragma once
// Intersections of two planar curves (segments and circular arcs), the arrangement's one
// numerical decision about where curves meet. Crossing, tangent and overlapping curves are all
// reported as points: an overlap by the ends of each curve that lie on the other.
#include <morph/planar_curve.h>

#include <vector>

namespace morph::planar {

struct CurveHit {
  Vec2 point;
  double ta = 0.0;  ///< parameter on the first curve
  double tb = 0.0;  ///< parameter on the second curve
};

/// Appends the points where a and b meet to `hits`. Points within `eps` (job units) of both
/// curves count: a tangency within eps is one point, collinear or co-circular overlaps give the
/// overlap's ends. Ends of a curve are reported too when they lie on the other curve.
void intersect(const Curve& a, const Curve& b, double eps, std::vector<CurveHit>& hits);

/// Distance from p to the curve's supporting line or circle restricted to the curve.
double distance(const Curve& c, const Vec2& p);

}  // namespace morph::planar
