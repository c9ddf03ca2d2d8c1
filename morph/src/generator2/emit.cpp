// SPDX-License-Identifier: Apache-2.0
#include <morph/emit.h>

#include <boost/multiprecision/cpp_int.hpp>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

namespace morph {
namespace {

using Exact = boost::multiprecision::cpp_int;

// The exponent of the least significant bit of v's mantissa (v != 0).
int lowest_bit(double v) {
  int e = 0;
  std::frexp(v, &e);
  return e - DBL_MANT_DIG;
}

// v · 2^-lowest as an integer (exact when lowest <= lowest_bit(v)).
Exact scaled(double v, int lowest) {
  if (v == 0) return 0;
  int e = 0;
  const double mantissa = std::frexp(v, &e);
  const auto m = static_cast<std::int64_t>(std::ldexp(mantissa, DBL_MANT_DIG));
  Exact out(m);
  out <<= (e - DBL_MANT_DIG - lowest);
  return out;
}

// The same sign in integers: the corners scaled by one power of two, the normal by another.
int exact_oriented_area_sign(const Eigen::Vector3d& n, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  int corner_low = INT32_MAX, normal_low = INT32_MAX;
  for (const Eigen::Vector3d* p : {&a, &b, &c})
    for (int i = 0; i < 3; ++i)
      if ((*p)[i] != 0) corner_low = std::min(corner_low, lowest_bit((*p)[i]));
  for (int i = 0; i < 3; ++i)
    if (n[i] != 0) normal_low = std::min(normal_low, lowest_bit(n[i]));
  if (corner_low == INT32_MAX || normal_low == INT32_MAX) return 0;
  Exact u[3], v[3], m[3];
  for (int i = 0; i < 3; ++i) {
    const Exact ai = scaled(a[i], corner_low);
    u[i] = scaled(b[i], corner_low) - ai;
    v[i] = scaled(c[i], corner_low) - ai;
    m[i] = scaled(n[i], normal_low);
  }
  const Exact value = m[0] * (u[1] * v[2] - u[2] * v[1]) + m[1] * (u[2] * v[0] - u[0] * v[2]) +
                      m[2] * (u[0] * v[1] - u[1] * v[0]);
  return value.sign();
}

// The triangles, their rounded corners and the way each must turn; re-rounds corners of those
// that do not.
class Rounding {
 public:
  Rounding(TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& facing) : mesh_(mesh), facing_(facing) {
    around_.resize(mesh.vertices.size());
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
      for (std::uint32_t v : mesh.triangles[t]) around_[v].push_back(t);
  }

  void run(EmitCounts& counts) {
    for (std::uint32_t t = 0; t < mesh_.triangles.size(); ++t) {
      if (turns_right(t)) continue;
      bool fixed = false;
      for (std::uint32_t v : mesh_.triangles[t])
        if (!fixed && reround(v)) fixed = true, ++counts.rerounded_vertices;
      if (!fixed) ++counts.misoriented_left;
    }
  }

 private:
  bool turns_right(std::uint32_t t) const {
    const Triangle& tri = mesh_.triangles[t];
    return oriented_area_sign(facing_[t], mesh_.vertices[tri[0]], mesh_.vertices[tri[1]],
                              mesh_.vertices[tri[2]]) > 0;
  }
  bool all_right(std::uint32_t v) const {
    for (std::uint32_t t : around_[v])
      if (!turns_right(t)) return false;
    return true;
  }
  // The nearest doubles first: one, then two units in the last place per coordinate.
  bool reround(std::uint32_t v) {
    const Eigen::Vector3d rounded = mesh_.vertices[v];
    for (int reach = 1; reach <= 2; ++reach)
      for (int dx = -reach; dx <= reach; ++dx)
        for (int dy = -reach; dy <= reach; ++dy)
          for (int dz = -reach; dz <= reach; ++dz) {
            if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != reach) continue;
            const int step[3] = {dx, dy, dz};
            Eigen::Vector3d moved = rounded;
            for (int i = 0; i < 3; ++i)
              for (int k = 0; k < std::abs(step[i]); ++k)
                moved[i] = std::nextafter(moved[i], step[i] > 0 ? DBL_MAX : -DBL_MAX);
            mesh_.vertices[v] = moved;
            if (all_right(v)) return true;
          }
    mesh_.vertices[v] = rounded;
    return false;
  }

  TriangleMesh& mesh_;
  const std::vector<Eigen::Vector3d>& facing_;
  std::vector<std::vector<std::uint32_t>> around_;
};

}  // namespace

int oriented_area_sign(const Eigen::Vector3d& n, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                       const Eigen::Vector3d& c) {
  const Eigen::Vector3d u = b - a, v = c - a;
  const double value = n.dot(u.cross(v));
  // Differences, products and sums: within 16 units of roundoff of the permanent.
  const Eigen::Vector3d au = u.cwiseAbs(), av = v.cwiseAbs();
  const double permanent = std::fabs(n[0]) * (au[1] * av[2] + au[2] * av[1]) +
                           std::fabs(n[1]) * (au[2] * av[0] + au[0] * av[2]) +
                           std::fabs(n[2]) * (au[0] * av[1] + au[1] * av[0]);
  const double bound = 16 * (DBL_EPSILON / 2) * permanent;
  if (std::isfinite(value) && permanent > DBL_MIN * 1e20 && std::fabs(value) > bound)
    return value > 0 ? 1 : -1;
  return exact_oriented_area_sign(n, a, b, c);
}

TriangleMesh emit(const LimitSurface& surface, const std::vector<std::int32_t>& move_index,
                  const std::vector<std::int32_t>& move_line, EmitCounts* counts) {
  TriangleMesh mesh;
  std::vector<Eigen::Vector3d> facing;  // per triangle: the way its polygon faces out
  // Only the referenced vertices, in the order of their plane triples' indices.
  constexpr std::uint32_t kUnused = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> index(surface.vertices.size(), kUnused);
  for (const LimitPolygon& polygon : surface.polygons)
    for (std::uint32_t v : polygon.loop) index[v] = 0;
  for (std::uint32_t v = 0; v < surface.vertices.size(); ++v)
    if (index[v] != kUnused) {
      index[v] = static_cast<std::uint32_t>(mesh.vertices.size());
      const auto& t = surface.vertices[v];
      mesh.vertices.push_back(vertex_point(t[0], t[1], t[2]));
    }
  for (const LimitPolygon& polygon : surface.polygons) {
    const FaceTag tag = polygon.move < 0 ? FaceTag{PatchKind::StockFace, polygon.face, 0}
                                         : FaceTag{PatchKind::SideSweep, move_index.at(polygon.move),
                                                   move_line.at(polygon.move)};
    const Eigen::Vector3d out =
        polygon.faces_out ? polygon.support.normal : Eigen::Vector3d(-polygon.support.normal);
    const auto add = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
      mesh.triangles.push_back({a, b, c});
      mesh.tags.push_back(tag);
      facing.push_back(out);
    };
    const std::size_t n = polygon.loop.size();
    if (polygon.strictly_convex) {
      for (std::size_t k = 1; k + 1 < n; ++k)
        add(index[polygon.loop[0]], index[polygon.loop[k]], index[polygon.loop[k + 1]]);
      continue;
    }
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (std::uint32_t v : polygon.loop) centroid += mesh.vertices[index[v]];
    const auto centre = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(centroid / static_cast<double>(n));
    for (std::size_t k = 0; k < n; ++k) add(centre, index[polygon.loop[k]], index[polygon.loop[(k + 1) % n]]);
  }
  EmitCounts local;
  Rounding(mesh, facing).run(local);
  if (counts) *counts = local;
  return mesh;
}

}  // namespace morph
