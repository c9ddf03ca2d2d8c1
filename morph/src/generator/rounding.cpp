// SPDX-License-Identifier: Apache-2.0
#include "generator/rounding.h"

#include <morph/parallel.h>

#include <boost/multiprecision/cpp_int.hpp>

#include <algorithm>
#include <atomic>
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

// A flat triangle's shortest edge is collapsed only when it is this much shorter than the
// triangle's longest: a needle far below what doubles can shape at that size. It only picks the
// candidates (moving a vertex by less than 1e-12 of the triangle's size); whether the collapse
// is made is exact (link condition, every incident triangle still turning the right way).
constexpr double kNeedle = 1e-12;
// Two rounded vertices closer than this fraction of their coordinates' size (about 500 ulps)
// are a cluster of exact points below anything the polytopes shape (the near-concurrent planes of
// a pole split one point into several ~1e-12 apart): their edge is a candidate too.
constexpr double kCluster = 1e-13;
constexpr std::uint32_t kGone = std::numeric_limits<std::uint32_t>::max();

// Closer than kCluster of the coordinates' size: a cluster of exact points far below any
// feature the tool polytope has (its pole's near-concurrent planes).
bool clustered(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const double size = std::max({1.0, a.cwiseAbs().maxCoeff(), b.cwiseAbs().maxCoeff()});
  return (a - b).norm() <= kCluster * size;
}

// True when none of the steps has anything to do: no triangle flat or turned the wrong way, no
// edge whose ends rounded alike or into a cluster, and every vertex used (so the compaction
// keeps the mesh as it is). Found in parallel: the settling's passes are serial, and on most
// surfaces (bear.nc at 0.01, 1.2 million triangles) they found nothing in 0.4 s.
bool settled_already(const TriangleMesh& mesh, const std::vector<Eigen::Vector3d>& facing) {
  std::atomic<bool> unsettled{false};
  for_each_index(ExecutionPolicy::Parallel, 0, mesh.triangles.size(), [&](std::size_t t) {
    if (unsettled.load(std::memory_order_relaxed)) return;
    const Triangle& tri = mesh.triangles[t];
    const Eigen::Vector3d &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
    if (zero_area(a, b, c) || oriented_area_sign(facing[t], a, b, c) <= 0 || a == b || b == c || c == a ||
        clustered(a, b) || clustered(b, c) || clustered(c, a))
      unsettled.store(true, std::memory_order_relaxed);
  });
  if (unsettled) return false;
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const Triangle& tri : mesh.triangles)
    for (std::uint32_t v : tri) used[v] = 1;
  return std::all_of(used.begin(), used.end(), [](char u) { return u != 0; });
}

// The mesh with each vertex's triangles, edited in place; dropped triangles are marked.
class Settler {
 public:
  Settler(TriangleMesh& mesh, std::vector<Eigen::Vector3d>& facing) : mesh_(mesh), facing_(facing) {
    around_.resize(mesh.vertices.size());
    alive_.assign(mesh.triangles.size(), true);
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
      for (std::uint32_t v : mesh.triangles[t]) around_[v].push_back(t);
  }

  void run(RoundingCounts& counts) {
    // First only collapses that leave every moved triangle good, then those that make none worse.
    for (int pass = 0; pass < 16; ++pass) {
      strict_ = pass < 8;
      const std::size_t before = counts.collapsed_edges + counts.flipped_edges + counts.rerounded_vertices;
      collapse_short_edges(counts);
      flip_flat(counts);
      reround(counts);
      if (counts.collapsed_edges + counts.flipped_edges + counts.rerounded_vertices == before)
        pass = std::max(pass, 7);
      if (pass > 8 && counts.collapsed_edges + counts.flipped_edges + counts.rerounded_vertices == before)
        break;
    }
    for (std::uint32_t t = 0; t < mesh_.triangles.size(); ++t)
      if (alive_[t] && !turns_right(t)) ++counts.misoriented_left;
    compact();
  }

 private:
  const Eigen::Vector3d& at(std::uint32_t v) const { return mesh_.vertices[v]; }
  bool turns_right(std::uint32_t t) const {
    const Triangle& tri = mesh_.triangles[t];
    return oriented_area_sign(facing_[t], at(tri[0]), at(tri[1]), at(tri[2])) > 0;
  }
  std::vector<std::uint32_t> neighbours(std::uint32_t v) const {
    std::vector<std::uint32_t> out;
    for (std::uint32_t t : around_[v])
      for (std::uint32_t w : mesh_.triangles[t])
        if (w != v) out.push_back(w);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }
  // The live triangles holding both u and v.
  std::vector<std::uint32_t> on_edge(std::uint32_t u, std::uint32_t v) const {
    std::vector<std::uint32_t> out;
    for (std::uint32_t t : around_[u]) {
      const Triangle& tri = mesh_.triangles[t];
      if (tri[0] == v || tri[1] == v || tri[2] == v) out.push_back(t);
    }
    return out;
  }
  static std::uint32_t third(const Triangle& tri, std::uint32_t u, std::uint32_t v) {
    for (std::uint32_t w : tri)
      if (w != u && w != v) return w;
    return kGone;
  }
  void drop(std::uint32_t t) {
    alive_[t] = false;
    for (std::uint32_t v : mesh_.triangles[t]) {
      auto& list = around_[v];
      list.erase(std::remove(list.begin(), list.end(), t), list.end());
    }
  }

  bool flat(std::uint32_t t) const {
    const Triangle& tri = mesh_.triangles[t];
    return zero_area(at(tri[0]), at(tri[1]), at(tri[2]));
  }

  // Step 1: an edge whose ends rounded alike, and the shortest edge of a flat needle (kNeedle),
  // collapsed when the link condition holds and every other triangle about the moved end keeps
  // turning the right way (exact).
  void collapse_short_edges(RoundingCounts& counts) {
    for (std::uint32_t t = 0; t < mesh_.triangles.size(); ++t) {
      if (!alive_[t]) continue;
      const bool is_flat = flat(t);
      int shortest = 0;
      double longest = 0;
      for (int k = 0; k < 3; ++k) {
        if (length(t, k) < length(t, shortest)) shortest = k;
        longest = std::max(longest, length(t, k));
      }
      for (int k = 0; k < 3 && alive_[t]; ++k) {
        const std::uint32_t a = mesh_.triangles[t][k], b = mesh_.triangles[t][(k + 1) % 3];
        const bool candidate = at(a) == at(b) || clustered(at(a), at(b)) ||
                               (is_flat && k == shortest && length(t, k) <= kNeedle * kNeedle * longest);
        if (!candidate) continue;
        if (collapse(std::min(a, b), std::max(a, b))) ++counts.collapsed_edges;
      }
    }
  }
  double length(std::uint32_t t, int k) const {
    return (at(mesh_.triangles[t][(k + 1) % 3]) - at(mesh_.triangles[t][k])).squaredNorm();
  }
  // v into u (v's triangles take u; the edge's two triangles go), u placed at its own point,
  // v's, or their midpoint: the first where no remaining triangle about them gets worse (turns
  // the wrong way or becomes flat where it was not).
  bool collapse(std::uint32_t u, std::uint32_t v) {
    const std::vector<std::uint32_t> pair = on_edge(u, v);
    if (pair.size() != 2) return false;
    const std::uint32_t o1 = third(mesh_.triangles[pair[0]], u, v),
                        o2 = third(mesh_.triangles[pair[1]], u, v);
    if (o1 == o2) return false;
    const std::vector<std::uint32_t> nu = neighbours(u), nv = neighbours(v);
    std::vector<std::uint32_t> common;
    std::set_intersection(nu.begin(), nu.end(), nv.begin(), nv.end(), std::back_inserter(common));
    if (common.size() != 2) return false;  // the link condition: only o1 and o2
    const Eigen::Vector3d pu = at(u), pv = at(v);
    // The triangles that move, and whether each turned the right way and was not flat.
    std::vector<std::pair<std::uint32_t, std::pair<bool, bool>>> moved;
    for (std::uint32_t w : {u, v})
      for (std::uint32_t t : around_[w])
        if (t != pair[0] && t != pair[1]) moved.push_back({t, {turns_right(t), !flat(t)}});
    bool placed = pu == pv;
    std::vector<Eigen::Vector3d> places{pu, pv, 0.5 * (pu + pv)};
    for (int step = 1; step < 27; ++step)  // and the doubles next to u's
      places.push_back(next_double(pu, step % 3 - 1, step / 3 % 3 - 1, step / 9 - 1));
    for (const Eigen::Vector3d& p : places) {
      if (placed) break;
      mesh_.vertices[u] = mesh_.vertices[v] = p;
      placed = std::all_of(moved.begin(), moved.end(), [&](const auto& m) {
        return ((!strict_ && !m.second.first) || turns_right(m.first)) &&
               ((!strict_ && !m.second.second) || !flat(m.first));
      });
    }
    if (!placed) {
      mesh_.vertices[u] = pu, mesh_.vertices[v] = pv;
      return false;
    }
    drop(pair[0]);
    drop(pair[1]);
    for (std::uint32_t t : around_[v]) {
      for (std::uint32_t& w : mesh_.triangles[t])
        if (w == v) w = u;
      around_[u].push_back(t);
    }
    around_[v].clear();
    return true;
  }

  static Eigen::Vector3d next_double(Eigen::Vector3d p, int dx, int dy, int dz) {
    const int step[3] = {dx, dy, dz};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < std::abs(step[i]); ++k)
        p[i] = std::nextafter(p[i], step[i] > 0 ? DBL_MAX : -DBL_MAX);
    return p;
  }

  // Step 2: a flat triangle's longest edge flipped, when both new triangles turn the right way
  // (exact) and are not flat.
  void flip_flat(RoundingCounts& counts) {
    for (std::uint32_t t = 0; t < mesh_.triangles.size(); ++t) {
      if (!alive_[t] || !flat(t)) continue;
      const Triangle tri = mesh_.triangles[t];
      int longest = 0;
      for (int k = 1; k < 3; ++k)
        if (length(t, k) > length(t, longest)) longest = k;
      if (flip(t, tri[longest], tri[(longest + 1) % 3], tri[(longest + 2) % 3])) ++counts.flipped_edges;
    }
  }
  // t runs p -> q -> m with m (nearly) on the segment pq; its neighbour s runs q -> p -> d. They
  // become (p, d, m) and (d, q, m), with s's facing and provenance.
  bool flip(std::uint32_t t, std::uint32_t p, std::uint32_t q, std::uint32_t m) {
    const std::vector<std::uint32_t> pair = on_edge(p, q);
    if (pair.size() != 2) return false;
    const std::uint32_t s = pair[0] == t ? pair[1] : pair[0];
    const std::uint32_t d = third(mesh_.triangles[s], p, q);
    if (d == m || !on_edge(d, m).empty()) return false;
    const Eigen::Vector3d facing = facing_[s];
    if (oriented_area_sign(facing, at(p), at(d), at(m)) <= 0 ||
        oriented_area_sign(facing, at(d), at(q), at(m)) <= 0)
      return false;
    if (zero_area(at(p), at(d), at(m)) || zero_area(at(d), at(q), at(m))) return false;
    const FaceTag tag = mesh_.tags.empty() ? FaceTag{} : mesh_.tags[s];
    drop(t);
    drop(s);
    revive(t, {p, d, m}, facing, tag);
    revive(s, {d, q, m}, facing, tag);
    return true;
  }
  void revive(std::uint32_t t, const Triangle& tri, const Eigen::Vector3d& facing, const FaceTag& tag) {
    mesh_.triangles[t] = tri;
    facing_[t] = facing;
    if (!mesh_.tags.empty()) mesh_.tags[t] = tag;
    alive_[t] = true;
    for (std::uint32_t v : tri) around_[v].push_back(t);
  }

  // Step 3.
  void reround(RoundingCounts& counts) {
    for (std::uint32_t t = 0; t < mesh_.triangles.size(); ++t) {
      if (!alive_[t] || turns_right(t)) continue;
      for (std::uint32_t v : mesh_.triangles[t])
        if (move_to_neighbouring_double(v)) {
          ++counts.rerounded_vertices;
          break;
        }
    }
  }
  bool all_right(std::uint32_t v) const {
    return std::all_of(around_[v].begin(), around_[v].end(), [&](std::uint32_t t) { return turns_right(t); });
  }
  // The nearest doubles first: one, then two units in the last place per coordinate.
  bool move_to_neighbouring_double(std::uint32_t v) {
    const Eigen::Vector3d rounded = mesh_.vertices[v];
    for (int reach = 1; reach <= 2; ++reach)
      for (int dx = -reach; dx <= reach; ++dx)
        for (int dy = -reach; dy <= reach; ++dy)
          for (int dz = -reach; dz <= reach; ++dz) {
            if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != reach) continue;
            mesh_.vertices[v] = next_double(rounded, dx, dy, dz);
            if (all_right(v)) return true;
          }
    mesh_.vertices[v] = rounded;
    return false;
  }

  // Drops the dead triangles and the vertices no triangle uses, keeping the order of the rest.
  void compact() {
    std::vector<std::uint32_t> index(mesh_.vertices.size(), kGone);
    std::size_t kept = 0;
    for (std::uint32_t t = 0; t < mesh_.triangles.size(); ++t)
      if (alive_[t]) {
        mesh_.triangles[kept] = mesh_.triangles[t];
        if (!mesh_.tags.empty()) mesh_.tags[kept] = mesh_.tags[t];
        ++kept;
        for (std::uint32_t v : mesh_.triangles[t]) index[v] = 0;
      }
    mesh_.triangles.resize(kept);
    if (!mesh_.tags.empty()) mesh_.tags.resize(kept);
    std::uint32_t next = 0;
    for (std::uint32_t v = 0; v < mesh_.vertices.size(); ++v)
      if (index[v] != kGone) mesh_.vertices[next] = mesh_.vertices[v], index[v] = next++;
    mesh_.vertices.resize(next);
    for (Triangle& tri : mesh_.triangles)
      for (std::uint32_t& v : tri) v = index[v];
  }

  TriangleMesh& mesh_;
  std::vector<Eigen::Vector3d>& facing_;
  std::vector<std::vector<std::uint32_t>> around_;
  std::vector<bool> alive_;
  bool strict_ = true;
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

RoundingCounts settle_rounding(TriangleMesh& mesh, std::vector<Eigen::Vector3d> facing) {
  RoundingCounts counts;
  if (settled_already(mesh, facing)) return counts;
  Settler(mesh, facing).run(counts);
  return counts;
}

}  // namespace morph
