// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shared by generator 2's benches: bear's job as the spike defines it, this thread's CPU time,
// and the naive floating-point clipping of a convex polygon by a union of convex cutters.
#include <morph/erode.h>
#include <morph/gcode.h>

#include <Eigen/Core>
#include <ctime>
#include <string>
#include <vector>

namespace generator2_bench {

using Eigen::Vector3d;
using Polygon = std::vector<Vector3d>;

// Seconds of CPU time this thread has used: the machine is shared, so wall time would measure
// the neighbours too.
inline double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

constexpr double kOnPlane = 1e-9;  // mm: a vertex this near a plane is on it (float ties)

struct Plane {
  Vector3d normal;
  double offset;
  double value(const Vector3d& p) const { return normal.dot(p) - offset; }
};

// Splits a convex polygon by a plane into the part above it (value > 0) and the part below.
inline void split(const Polygon& polygon, const Plane& plane, Polygon& above, Polygon& below) {
  above.clear();
  below.clear();
  const std::size_t n = polygon.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Vector3d &p = polygon[i], &q = polygon[(i + 1) % n];
    const double vp = plane.value(p), vq = plane.value(q);
    if (vp >= -kOnPlane) above.push_back(p);
    if (vp <= kOnPlane) below.push_back(p);
    if ((vp > kOnPlane && vq < -kOnPlane) || (vp < -kOnPlane && vq > kOnPlane)) {
      const Vector3d x = p + (q - p) * (vp / (vp - vq));
      above.push_back(x);
      below.push_back(x);
    }
  }
  if (above.size() < 3) above.clear();
  if (below.size() < 3) below.clear();
}

inline double area(const Polygon& polygon) {
  Vector3d sum = Vector3d::Zero();
  for (std::size_t i = 1; i + 1 < polygon.size(); ++i)
    sum += (polygon[i] - polygon[0]).cross(polygon[i + 1] - polygon[0]);
  return 0.5 * sum.norm();
}

// The naive clipping: `polygon` minus the union of the cutters (each the intersection of the
// halfspaces below its planes), convex piece by convex piece. Adds the pieces and their area.
inline void clip(const Polygon& polygon, const std::vector<std::vector<Plane>>& cutters, double& pieces_out,
                 double& area_out) {
  std::vector<Polygon> pieces{polygon}, next;
  Polygon above, below, rest;
  for (const std::vector<Plane>& cutter : cutters) {
    next.clear();
    for (const Polygon& piece : pieces) {
      // A piece on or above one of the cutter's planes misses it: kept whole, not split.
      bool misses = false;
      for (const Plane& plane : cutter) {
        misses = true;
        for (const Vector3d& p : piece) misses = misses && plane.value(p) >= -kOnPlane;
        if (misses) break;
      }
      if (misses) {
        next.push_back(piece);
        continue;
      }
      rest = piece;
      for (const Plane& plane : cutter) {
        split(rest, plane, above, below);
        if (!above.empty()) next.push_back(above);
        rest.swap(below);
        if (rest.empty()) break;
      }
    }
    pieces.swap(next);
    if (pieces.empty()) break;
  }
  pieces_out += static_cast<double>(pieces.size());
  for (const Polygon& piece : pieces) area_out += area(piece);
}

// bear.nc with a ball end Ø3.175 (L 25.4) in the box (0,0,-20)-(80,80,0) at 0.01 mm.
inline morph::Job bear_job(const std::string& path) {
  morph::GcodeOptions options;
  options.initial_tool = 1;
  morph::GcodeResult program = morph::read_gcode(path, options);
  morph::Job job;
  job.name = "bear";
  job.stock.type = morph::StockType::Box;
  job.stock.box = Eigen::AlignedBox3d(Vector3d(0, 0, -20), Vector3d(80, 80, 0));
  morph::Tool tool = morph::ball_tool(1.5875, 25.4);
  tool.number = 1;
  job.tools[1] = tool;
  job.tolerance = 0.01;
  for (morph::Move& m : program.path.moves) m.tool = 1;
  job.paths.push_back(program.path);
  return job;
}

// Area of the generator's sweep faces (side and front sweeps), for comparison with the kept area.
inline double sweep_area(const morph::ErodeResult& generated) {
  double total = 0.0;
  for (std::size_t t = 0; t < generated.mesh.triangles.size(); ++t) {
    const morph::PatchKind kind = generated.mesh.tags[t].kind;
    if (kind != morph::PatchKind::SideSweep && kind != morph::PatchKind::FrontSweep) continue;
    const auto& tri = generated.mesh.triangles[t];
    const Vector3d &a = generated.mesh.vertices[tri[0]], &b = generated.mesh.vertices[tri[1]],
                   &c = generated.mesh.vertices[tri[2]];
    total += 0.5 * (b - a).cross(c - a).norm();
  }
  return total;
}

}  // namespace generator2_bench
