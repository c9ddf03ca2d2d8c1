// Local repair of the few defects the seam work leaves. A cluster of bad edges marks a place
// where several trimmed patches meet at a singular point (two equal tools crossing at the same
// depth touch tangentially at the bottom; a corner of one path lies on another pass) and the
// independent contours do not agree below the tie-break scale. Replacing a small disc of the
// surface there by a fan around the exact surface point is within the tolerance by construction
// (every replacement triangle is checked against the exact field) and restores the manifold.
#include "erode_repair.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace morph::detail {

namespace {

using Eigen::Vector3d;

std::uint64_t undirected(std::uint32_t a, std::uint32_t b) {
  return (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
}

class Repairer {
 public:
  Repairer(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of, const RepairOptions& options,
           const FieldFunction& field)
      : mesh_(mesh), patch_of_(patch_of), options_(options), field_(field) {
    deleted_.assign(mesh_.triangles.size(), false);
    triangles_of_vertex_.resize(mesh_.vertices.size());
    for (std::uint32_t t = 0; t < mesh_.triangles.size(); ++t) add_triangle_to_maps(t);
    for (std::uint32_t v = 0; v < mesh_.vertices.size(); ++v)
      vertex_grid_[cell_key(mesh_.vertices[v])].push_back(v);
  }

  RepairStats run() {
    RepairStats stats;
    const std::vector<std::vector<std::uint32_t>> clusters = defect_clusters();
    stats.defects = clusters.size();
    for (const std::vector<std::uint32_t>& cluster : clusters) stats.repaired += repair(cluster);
    compact();
    return stats;
  }

 private:
  std::int64_t cell_index(double x) const {
    return static_cast<std::int64_t>(std::floor(x / options_.max_radius));
  }
  static std::uint64_t pack(std::int64_t x, std::int64_t y, std::int64_t z) {
    return (static_cast<std::uint64_t>(x & 0x1fffff) << 42) |
           (static_cast<std::uint64_t>(y & 0x1fffff) << 21) | static_cast<std::uint64_t>(z & 0x1fffff);
  }
  std::uint64_t cell_key(const Vector3d& p) const {
    return pack(cell_index(p.x()), cell_index(p.y()), cell_index(p.z()));
  }

  void add_triangle_to_maps(std::uint32_t t) {
    const Triangle& tri = mesh_.triangles[t];
    for (int k = 0; k < 3; ++k) {
      triangles_of_vertex_[tri[k]].push_back(t);
      triangles_of_edge_[undirected(tri[k], tri[(k + 1) % 3])].push_back(t);
    }
  }

  /// Live triangles using the edge, with +1 for a->b and -1 for b->a.
  std::vector<std::pair<std::uint32_t, int>> uses(std::uint32_t a, std::uint32_t b,
                                                  const std::unordered_set<std::uint32_t>& removed) const {
    std::vector<std::pair<std::uint32_t, int>> result;
    auto it = triangles_of_edge_.find(undirected(a, b));
    if (it == triangles_of_edge_.end()) return result;
    for (std::uint32_t t : it->second) {
      if (deleted_[t] || removed.count(t)) continue;
      const Triangle& tri = mesh_.triangles[t];
      for (int k = 0; k < 3; ++k)
        if (tri[k] == a && tri[(k + 1) % 3] == b)
          result.push_back({t, +1});
        else if (tri[k] == b && tri[(k + 1) % 3] == a)
          result.push_back({t, -1});
    }
    return result;
  }

  bool manifold_edge(std::uint32_t a, std::uint32_t b) const {
    const auto u = uses(a, b, {});
    return u.size() == 2 && u[0].second != u[1].second;
  }

  /// Whether the triangles around v form one fan (a disc or, at a border, a half disc).
  bool manifold_vertex(std::uint32_t v) const {
    std::vector<std::uint32_t> around;
    for (std::uint32_t t : triangles_of_vertex_[v])
      if (!deleted_[t]) around.push_back(t);
    if (around.empty()) return true;
    std::vector<std::uint32_t> parent(around.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    for (std::size_t i = 0; i < around.size(); ++i)
      for (std::size_t j = i + 1; j < around.size(); ++j) {
        const Triangle &p = mesh_.triangles[around[i]], &q = mesh_.triangles[around[j]];
        for (std::uint32_t w : p) {
          if (w == v || std::find(q.begin(), q.end(), w) == q.end()) continue;
          if (manifold_edge(v, w))
            parent[find(static_cast<std::uint32_t>(i))] = find(static_cast<std::uint32_t>(j));
        }
      }
    std::size_t fans = 0;
    for (std::size_t i = 0; i < around.size(); ++i) fans += find(static_cast<std::uint32_t>(i)) == i;
    return fans == 1;
  }

  /// Vertices of bad edges and non-manifold vertices, grouped by proximity (max_radius).
  std::vector<std::vector<std::uint32_t>> defect_clusters() const {
    std::vector<std::uint32_t> bad;
    for (const auto& [key, list] : triangles_of_edge_) {
      const auto a = static_cast<std::uint32_t>(key >> 32), b = static_cast<std::uint32_t>(key & 0xffffffffu);
      if (!manifold_edge(a, b)) {
        bad.push_back(a);
        bad.push_back(b);
      }
    }
    for (std::uint32_t v = 0; v < mesh_.vertices.size(); ++v)
      if (!triangles_of_vertex_[v].empty() && !manifold_vertex(v)) bad.push_back(v);
    std::sort(bad.begin(), bad.end());
    bad.erase(std::unique(bad.begin(), bad.end()), bad.end());
    std::vector<std::uint32_t> parent(bad.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto find = [&](std::uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    // Bad spots closer than this are one defect (the hole between them goes with them).
    const double cell = 0.25 * options_.max_radius;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid;
    auto key_of = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
      return (static_cast<std::uint64_t>(x & 0x1fffff) << 42) |
             (static_cast<std::uint64_t>(y & 0x1fffff) << 21) | static_cast<std::uint64_t>(z & 0x1fffff);
    };
    for (std::uint32_t i = 0; i < bad.size(); ++i) {
      const Vector3d& p = mesh_.vertices[bad[i]];
      const std::int64_t cx = static_cast<std::int64_t>(std::floor(p.x() / cell)),
                         cy = static_cast<std::int64_t>(std::floor(p.y() / cell)),
                         cz = static_cast<std::int64_t>(std::floor(p.z() / cell));
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            auto it = grid.find(key_of(cx + dx, cy + dy, cz + dz));
            if (it == grid.end()) continue;
            for (std::uint32_t j : it->second)
              if ((mesh_.vertices[bad[j]] - p).norm() <= cell) parent[find(i)] = find(j);
          }
      grid[key_of(cx, cy, cz)].push_back(i);
    }
    std::unordered_map<std::uint32_t, std::size_t> index_of_root;
    std::vector<std::vector<std::uint32_t>> clusters;
    for (std::uint32_t i = 0; i < bad.size(); ++i) {
      const std::uint32_t root = find(i);
      auto [it, inserted] = index_of_root.try_emplace(root, clusters.size());
      if (inserted) clusters.emplace_back();
      clusters[it->second].push_back(bad[i]);
    }
    return clusters;
  }

  /// Newton steps on the exact field from `start`; `start` itself if they do not settle nearby.
  Vector3d onto_surface(const Vector3d& start, double reach) const {
    Vector3d x = start;
    for (int it = 0; it < 20; ++it) {
      const double f = field_(x);
      if (std::abs(f) < 1e-12) break;
      Vector3d gradient;
      const double h = 1e-7 * std::max(1.0, reach);
      for (int k = 0; k < 3; ++k)
        gradient[k] = (field_(x + h * Vector3d::Unit(k)) - field_(x - h * Vector3d::Unit(k))) / (2.0 * h);
      if (gradient.squaredNorm() < 1e-12) return start;
      x -= f * gradient / gradient.squaredNorm();
    }
    return (x - start).norm() <= reach && std::abs(field_(x)) <= options_.max_field_error ? x : start;
  }

  bool within_field(const Vector3d& p) const { return std::abs(field_(p)) <= options_.max_field_error; }

  std::size_t repair(const std::vector<std::uint32_t>& cluster) {
    Vector3d centre = Vector3d::Zero();
    for (std::uint32_t v : cluster) centre += mesh_.vertices[v];
    centre /= static_cast<double>(cluster.size());
    double spread = 0.0;
    for (std::uint32_t v : cluster) spread = std::max(spread, (mesh_.vertices[v] - centre).norm());
    if (spread > options_.max_radius) return 0;
    for (double radius = std::max(1.5 * spread, 0.05 * options_.max_radius); radius <= options_.max_radius;
         radius *= 1.5)
      if (try_ball(centre, radius)) return 1;
    return 0;
  }

  bool try_ball(const Vector3d& centre, double radius) {
    // Triangles with a vertex in the ball, found from the triangles around nearby vertices.
    std::unordered_set<std::uint32_t> removed;
    std::vector<std::uint32_t> removed_order;
    std::vector<std::uint32_t> stack;
    const std::int64_t cx = cell_index(centre.x()), cy = cell_index(centre.y()), cz = cell_index(centre.z());
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = vertex_grid_.find(pack(cx + dx, cy + dy, cz + dz));
          if (it == vertex_grid_.end()) continue;
          for (std::uint32_t v : it->second)
            if ((mesh_.vertices[v] - centre).norm() <= radius && !triangles_of_vertex_[v].empty())
              stack.push_back(v);
        }
    std::sort(stack.begin(), stack.end());
    for (std::uint32_t v : stack)
      for (std::uint32_t t : triangles_of_vertex_[v])
        if (!deleted_[t] && removed.insert(t).second) removed_order.push_back(t);
    if (removed.empty()) return false;
    // The ring around what is removed must be manifold and open towards it along one loop. Where
    // the loop would pass a vertex twice (two kept corners touching at a point), the triangles
    // around that vertex go too, and the ring is taken again.
    std::unordered_map<std::uint32_t, std::uint32_t> loop_next;  // a -> b for open edges a -> b
    std::unordered_map<std::uint32_t, std::uint32_t> loop_triangle;
    for (int attempt = 0;; ++attempt) {
      std::sort(removed_order.begin(), removed_order.end());
      std::vector<std::uint32_t> ring;
      {
        std::unordered_set<std::uint32_t> in_ring;
        for (std::uint32_t t : removed_order)
          for (std::uint32_t v : mesh_.triangles[t])
            for (std::uint32_t s : triangles_of_vertex_[v])
              if (!deleted_[s] && !removed.count(s) && in_ring.insert(s).second) ring.push_back(s);
        std::sort(ring.begin(), ring.end());
      }
      if (ring.empty()) return false;
      loop_next.clear();
      loop_triangle.clear();
      std::unordered_map<std::uint32_t, int> incoming;
      std::vector<std::uint32_t> pinched;
      for (std::uint32_t t : ring) {
        const Triangle& tri = mesh_.triangles[t];
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
          const auto after = uses(a, b, removed);
          if (after.size() == 2 && after[0].second != after[1].second) continue;
          if (after.size() != 1) return false;
          // Open only because its partner went with the ball, not a defect outside it.
          const auto before = uses(a, b, {});
          if (before.size() != 2 || before[0].second == before[1].second) return false;
          if (!loop_next.emplace(a, b).second) pinched.push_back(a);
          loop_triangle.try_emplace(a, t);
          if (++incoming[b] > 1) pinched.push_back(b);
        }
      }
      if (pinched.empty()) break;
      if (attempt == 2) return false;
      std::sort(pinched.begin(), pinched.end());
      for (std::uint32_t v : pinched)
        for (std::uint32_t t : triangles_of_vertex_[v])
          if (!deleted_[t] && removed.insert(t).second) removed_order.push_back(t);
    }
    if (loop_next.size() < 3) return false;
    std::vector<std::uint32_t> loop;
    const std::uint32_t first = std::min_element(loop_next.begin(), loop_next.end())->first;
    for (std::uint32_t v = first;;) {
      loop.push_back(v);
      auto it = loop_next.find(v);
      if (it == loop_next.end()) return false;
      v = it->second;
      if (v == first) break;
      if (loop.size() > loop_next.size()) return false;
    }
    if (loop.size() != loop_next.size()) return false;
    // The fan's centre: the nearest point of the exact surface to the hole's centroid, with rings
    // of points of the exact surface between it and the loop where one fan would cut too deep
    // into a curved surface; or, where the hole straddles a crease that a new point would
    // flatten, one of the loop's own vertices (those on the crease fan across it exactly).
    Vector3d centroid = Vector3d::Zero();
    for (std::uint32_t v : loop) centroid += mesh_.vertices[v];
    centroid /= static_cast<double>(loop.size());
    const Vector3d apex = onto_surface(centroid, radius);
    for (int levels = 1; levels <= 4; ++levels) {
      const Fan fan = ringed_fan(loop, loop_triangle, apex, levels, radius);
      if (fits(fan, removed)) return emit(fan, removed_order);
    }
    for (std::size_t k = 0; k < loop.size(); ++k) {
      const Fan fan = vertex_fan(loop, loop_triangle, k);
      if (fits(fan, removed)) return emit(fan, removed_order);
    }
    return false;
  }

  /// Replacement triangles: index >= 0 an existing vertex, -1 - k the fan's k-th new point.
  struct Fan {
    std::vector<Vector3d> points;
    std::vector<std::array<std::int64_t, 3>> triangles;
    std::vector<std::uint32_t> ring_triangle;  // per triangle: the ring triangle it continues
  };

  Fan ringed_fan(const std::vector<std::uint32_t>& loop,
                 const std::unordered_map<std::uint32_t, std::uint32_t>& loop_triangle, const Vector3d& apex,
                 int levels, double radius) const {
    Fan fan;
    const std::size_t n = loop.size();
    // ring[k][i]: k = 0 the loop, k = levels the apex (one point).
    std::vector<std::vector<std::int64_t>> ring(levels + 1, std::vector<std::int64_t>(n));
    for (std::size_t i = 0; i < n; ++i) ring[0][i] = loop[i];
    for (int k = 1; k < levels; ++k)
      for (std::size_t i = 0; i < n; ++i) {
        const double s = static_cast<double>(k) / levels;
        fan.points.push_back(
            onto_surface(mesh_.vertices[loop[i]] + s * (apex - mesh_.vertices[loop[i]]), radius));
        ring[k][i] = -static_cast<std::int64_t>(fan.points.size());
      }
    fan.points.push_back(apex);
    for (std::size_t i = 0; i < n; ++i) ring[levels][i] = -static_cast<std::int64_t>(fan.points.size());
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      const std::uint32_t owner = loop_triangle.at(loop[i]);
      for (int k = 0; k < levels; ++k) {
        fan.triangles.push_back({ring[k][j], ring[k][i], ring[k + 1][i]});
        fan.ring_triangle.push_back(owner);
        if (k + 1 < levels) {
          fan.triangles.push_back({ring[k][j], ring[k + 1][i], ring[k + 1][j]});
          fan.ring_triangle.push_back(owner);
        }
      }
    }
    return fan;
  }

  Fan vertex_fan(const std::vector<std::uint32_t>& loop,
                 const std::unordered_map<std::uint32_t, std::uint32_t>& loop_triangle,
                 std::size_t centre) const {
    Fan fan;
    const std::size_t n = loop.size();
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = (i + 1) % n;
      if (i == centre || j == centre) continue;
      fan.triangles.push_back({loop[j], loop[i], loop[centre]});
      fan.ring_triangle.push_back(loop_triangle.at(loop[i]));
    }
    return fan;
  }

  Vector3d point_of(const Fan& fan, std::int64_t index) const {
    return index >= 0 ? mesh_.vertices[static_cast<std::size_t>(index)]
                      : fan.points[static_cast<std::size_t>(-1 - index)];
  }

  bool fits(const Fan& fan, const std::unordered_set<std::uint32_t>& removed) const {
    // A fan between existing vertices must not repeat an edge the ring already has.
    std::unordered_map<std::uint64_t, int> fan_uses;
    for (const auto& tri : fan.triangles)
      for (int k = 0; k < 3; ++k)
        if (tri[k] >= 0 && tri[(k + 1) % 3] >= 0)
          ++fan_uses[undirected(static_cast<std::uint32_t>(tri[k]),
                                static_cast<std::uint32_t>(tri[(k + 1) % 3]))];
    for (const auto& [key, count] : fan_uses)
      if (count + uses(static_cast<std::uint32_t>(key >> 32), static_cast<std::uint32_t>(key & 0xffffffffu),
                       removed)
                      .size() !=
          2)
        return false;
    for (std::size_t t = 0; t < fan.triangles.size(); ++t) {
      const Vector3d a = point_of(fan, fan.triangles[t][0]), b = point_of(fan, fan.triangles[t][1]),
                     c = point_of(fan, fan.triangles[t][2]);
      if (!within_field((a + b + c) / 3.0) || !within_field(0.5 * (a + b)) || !within_field(0.5 * (b + c)) ||
          !within_field(0.5 * (c + a)))
        return false;
      const Triangle& owner = mesh_.triangles[fan.ring_triangle[t]];
      const Vector3d ring_normal = (mesh_.vertices[owner[1]] - mesh_.vertices[owner[0]])
                                       .cross(mesh_.vertices[owner[2]] - mesh_.vertices[owner[0]]);
      const Vector3d normal = (b - a).cross(c - a);
      if (normal.norm() <= 1e-12 * std::max(1.0, ring_normal.norm())) return false;
      // Not a needle (a loop along a sliver would be closed by the sliver turned over).
      const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
      if (normal.norm() < 1e-3 * longest) return false;
      // Folded back against the ring (a crease inside the hole may turn it by up to a right angle).
      if (normal.dot(ring_normal) < -0.5 * normal.norm() * ring_normal.norm()) return false;
    }
    return true;
  }

  bool emit(const Fan& fan, const std::vector<std::uint32_t>& removed_order) {
    for (std::uint32_t t : removed_order) deleted_[t] = true;
    const auto first_new = static_cast<std::int64_t>(mesh_.vertices.size());
    for (const Vector3d& p : fan.points) {
      vertex_grid_[cell_key(p)].push_back(static_cast<std::uint32_t>(mesh_.vertices.size()));
      mesh_.vertices.push_back(p);
      triangles_of_vertex_.emplace_back();
    }
    for (std::size_t t = 0; t < fan.triangles.size(); ++t) {
      Triangle tri;
      for (int k = 0; k < 3; ++k) {
        const std::int64_t index = fan.triangles[t][k];
        tri[k] = static_cast<std::uint32_t>(index >= 0 ? index : first_new + (-1 - index));
      }
      const std::uint32_t owner = fan.ring_triangle[t];
      mesh_.triangles.push_back(tri);
      mesh_.tags.push_back(mesh_.tags[owner]);
      patch_of_.push_back({patch_of_[owner].patch, 7});
      deleted_.push_back(false);
      add_triangle_to_maps(static_cast<std::uint32_t>(mesh_.triangles.size() - 1));
    }
    return true;
  }

  void compact() { remove_triangles(mesh_, patch_of_, deleted_); }

  TriangleMesh& mesh_;
  std::vector<TriangleOrigin>& patch_of_;
  const RepairOptions& options_;
  const FieldFunction& field_;
  std::vector<bool> deleted_;
  std::vector<std::vector<std::uint32_t>> triangles_of_vertex_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> triangles_of_edge_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> vertex_grid_;
};

}  // namespace

void remove_triangles(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                      const std::vector<bool>& remove) {
  std::vector<bool> used(mesh.vertices.size(), false);
  std::size_t kept = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (remove[t]) continue;
    for (std::uint32_t v : mesh.triangles[t]) used[v] = true;
    mesh.triangles[kept] = mesh.triangles[t];
    mesh.tags[kept] = mesh.tags[t];
    patch_of_triangle[kept] = patch_of_triangle[t];
    ++kept;
  }
  mesh.triangles.resize(kept);
  mesh.tags.resize(kept);
  patch_of_triangle.resize(kept);
  std::vector<std::uint32_t> new_index(mesh.vertices.size(), 0);
  std::vector<Vector3d> vertices;
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!used[v]) continue;
    new_index[v] = static_cast<std::uint32_t>(vertices.size());
    vertices.push_back(mesh.vertices[v]);
  }
  for (Triangle& tri : mesh.triangles)
    for (std::uint32_t& v : tri) v = new_index[v];
  mesh.vertices = std::move(vertices);
}

RepairStats repair_small_defects(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                                 const RepairOptions& options, const FieldFunction& field) {
  if (mesh.triangles.empty()) return {};
  return Repairer(mesh, patch_of_triangle, options, field).run();
}

}  // namespace morph::detail
