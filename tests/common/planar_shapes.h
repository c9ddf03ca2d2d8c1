// SPDX-License-Identifier: Apache-2.0
#pragma once
// Planar stocks and trajectories as the tests build them (job units).
#include <morph/planar_dilation.h>
#include <morph/planar_region.h>

#include <vector>

namespace morphmill_test {

using morph::planar::Vec2;

/// The axis-aligned rectangle [x0, x1] x [y0, y1] as a one-piece region.
inline morph::planar::Region rectangle(double x0, double y0, double x1, double y1) {
  morph::planar::Loop loop;
  const Vec2 p[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  for (int i = 0; i < 4; ++i) loop.curves.push_back(morph::planar::make_segment(p[i], p[(i + 1) % 4]));
  return morph::planar::make_region({loop});
}

/// A closed polygon loop through the points.
inline morph::planar::Loop polygon(const std::vector<Vec2>& points) {
  morph::planar::Loop loop;
  for (std::size_t i = 0; i < points.size(); ++i)
    loop.curves.push_back(morph::planar::make_segment(points[i], points[(i + 1) % points.size()]));
  return loop;
}

/// The disc of `radius` about `center` (two half circles).
inline morph::planar::Loop circle(const Vec2& center, double radius) {
  morph::planar::Loop loop;
  loop.curves.push_back(morph::planar::make_arc(center, radius, 0.0, M_PI));
  loop.curves.push_back(morph::planar::make_arc(center, radius, M_PI, M_PI));
  loop.curves[1].start = loop.curves[0].end;
  loop.curves[1].end = loop.curves[0].start;
  return loop;
}

/// The moves of a polyline through the points (move i from points[i] to points[i + 1]).
inline morph::planar::Trajectory polyline(const std::vector<Vec2>& points, int first_index = 0) {
  morph::planar::Trajectory moves;
  for (std::size_t i = 0; i + 1 < points.size(); ++i)
    moves.push_back(morph::planar::make_segment(
        points[i], points[i + 1],
        {morph::planar::Origin::Sweep, static_cast<std::int32_t>(first_index + moves.size()),
         static_cast<std::int32_t>(i + 1)}));
  return moves;
}

/// A move of the tool centre along a circle of `radius` about `center` (full turn, counter-clockwise).
inline morph::planar::Curve circle_move(const Vec2& center, double radius, std::int32_t index) {
  return morph::planar::make_arc(center, radius, 0.0, 2.0 * M_PI, {morph::planar::Origin::Sweep, index, 0});
}

}  // namespace morphmill_test
