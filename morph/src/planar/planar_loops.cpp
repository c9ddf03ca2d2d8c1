// SPDX-License-Identifier: Apache-2.0
#include "planar/planar_loops.h"

#include <morph/exceptions.h>

#include <cmath>
#include <sstream>

namespace morph::planar {

namespace {

Vec2 rotated(const Vec2& v, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return Vec2(c * v.x() - s * v.y(), s * v.x() + c * v.y());
}

/// Direction of the chord over the first `probe` of a curve leaving a vertex with this tangent and
/// signed curvature: tangent pieces that part are told apart by how they bend.
Vec2 leaving_direction(const Vec2& tangent, double signed_curvature, double probe) {
  return rotated(tangent, 0.5 * signed_curvature * probe);
}

/// Counter-clockwise angle from `reference` to `v`, in [0, 2 pi).
double ccw_angle(const Vec2& reference, const Vec2& v) {
  double a = std::atan2(cross(reference, v), reference.dot(v));
  if (a < 0.0) a += 2.0 * M_PI;
  return a;
}

}  // namespace

std::vector<Loop> link_loops(const std::vector<Curve>& pieces, const std::vector<std::uint32_t>& from,
                             const std::vector<std::uint32_t>& to, std::size_t vertex_count, double probe) {
  const std::size_t n = pieces.size();
  std::vector<std::size_t> first(vertex_count + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++first[from[i] + 1];
  for (std::size_t v = 0; v < vertex_count; ++v) first[v + 1] += first[v];
  std::vector<std::uint32_t> leaving(n);
  {
    std::vector<std::size_t> fill(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < n; ++i) leaving[fill[from[i]]++] = static_cast<std::uint32_t>(i);
  }
  std::vector<char> used(n, 0);
  std::vector<Loop> loops;
  for (std::size_t s = 0; s < n; ++s) {
    if (used[s]) continue;
    Loop loop;
    std::size_t current = s;
    used[s] = 1;
    while (true) {
      loop.curves.push_back(pieces[current]);
      const std::uint32_t v = to[current];
      const Curve& in = pieces[current];
      const double in_probe = std::min(probe, length(in));
      const Vec2 reference = leaving_direction(-tangent_at(in, 1.0), -curvature(in), in_probe);
      std::size_t best = n;
      double best_angle = -1.0;
      for (std::size_t k = first[v]; k < first[v + 1]; ++k) {
        const std::uint32_t e = leaving[k];
        if (used[e] && e != s) continue;
        const Curve& out = pieces[e];
        const double angle = ccw_angle(
            reference, leaving_direction(tangent_at(out, 0.0), curvature(out), std::min(probe, length(out))));
        if (angle > best_angle) {
          best_angle = angle;
          best = e;
        }
      }
      if (best == n) {
        std::ostringstream message;
        message << "planar erosion: the boundary is open at (" << in.end.x() << ", " << in.end.y()
                << "): no piece leaves the end of a piece from "
                << (in.from.origin == Origin::Stock ? "stock element " : "move ") << in.from.source;
        throw GeometryError(message.str());
      }
      if (best == s) break;
      used[best] = 1;
      current = best;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

}  // namespace morph::planar
