// SPDX-License-Identifier: Apache-2.0
// Local repair of the few defects the seam work leaves. A cluster of bad edges marks a place
// where several trimmed patches meet at a singular point (two equal tools crossing at the same
// depth touch tangentially at the bottom; a corner of one path lies on another pass) and the
// independent contours do not agree below the tie-break scale. Replacing a small disc of the
// surface there by a fan around the exact surface point is within the tolerance by construction
// (every replacement triangle is checked against the exact field) and restores the manifold.
#include "generator/erode_repair.h"

#include <morph/topology.h>

#include "mesh/edge_uses.h"
#include "mesh/huge_pages.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

namespace morph::detail {

namespace {

using Eigen::Vector3d;

/// The triangles around each vertex, a triangle listed once per corner it has there (twice at
/// the doubled corner of a collapsed one), in triangle order: compressed rows for the mesh as
/// given, which is large, and a list per vertex for the few fans added since.
class VertexTriangles {
 public:
  explicit VertexTriangles(const TriangleMesh& mesh) : row_start_(mesh.vertices.size() + 1, 0) {
    for (const Triangle& tri : mesh.triangles)
      for (std::uint32_t v : tri) ++row_start_[v + 1];
    std::partial_sum(row_start_.begin(), row_start_.end(), row_start_.begin());
    entries_.resize(row_start_.back());
    std::vector<std::uint32_t> fill(row_start_.begin(), row_start_.end() - 1);
    for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t)
      for (std::uint32_t v : mesh.triangles[t]) entries_[fill[v]++] = t;
  }

  void add(std::uint32_t v, std::uint32_t t) { added_[v].push_back(t); }

  bool empty(std::uint32_t v) const {
    if (reads_) reads_->push_back(v);
    return (v + 1 >= row_start_.size() || row_start_[v] == row_start_[v + 1]) && added_.count(v) == 0;
  }

  /// Vertices whose triangles are looked up are listed in `*reads` while it is set.
  void record_reads(std::vector<std::uint32_t>* reads) { reads_ = reads; }

  template <class F>
  void for_each(std::uint32_t v, F&& f) const {
    if (reads_) reads_->push_back(v);
    if (v + 1 < row_start_.size())
      for (std::uint32_t i = row_start_[v]; i < row_start_[v + 1]; ++i) f(entries_[i]);
    if (added_.empty()) return;
    auto it = added_.find(v);
    if (it != added_.end())
      for (std::uint32_t t : it->second) f(t);
  }

 private:
  std::vector<std::uint32_t> row_start_;
  std::vector<std::uint32_t> entries_;
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> added_;
  std::vector<std::uint32_t>* reads_ = nullptr;
};

class Repairer {
 public:
  Repairer(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of, const RepairOptions& options,
           const FieldFunction& field, RepairMemory* memory, DefectSuspects* suspects)
      : mesh_(mesh),
        patch_of_(patch_of),
        options_(options),
        field_(field),
        memory_(memory),
        suspects_(suspects),
        deleted_(mesh.triangles.size(), false),
        triangles_of_vertex_(mesh) {}

  RepairStats run() {
    RepairStats stats;
    const std::vector<std::vector<std::uint32_t>> clusters =
        defect_clusters(suspects_ && suspects_->known ? &suspects_->vertices : nullptr);
    stats.defects = clusters.size();
    // Every defect's vertices stay suspect (repaired or not), with those of the repairs' triangles.
    if (suspects_)
      for (const std::vector<std::uint32_t>& cluster : clusters)
        touched_.insert(touched_.end(), cluster.begin(), cluster.end());
    std::vector<std::uint32_t> reads;
    for (const std::vector<std::uint32_t>& cluster : clusters) {
      if (memory_ && fails_as_before(cluster)) continue;
      reads.clear();
      if (memory_) triangles_of_vertex_.record_reads(&reads);
      const std::size_t repaired = repair(cluster);
      triangles_of_vertex_.record_reads(nullptr);
      stats.repaired += repaired;
      if (memory_ && repaired == 0) {
        std::vector<RepairMemory::Point> read_points;
        for (std::uint32_t v : reads) read_points.push_back(point_key(v));
        std::sort(read_points.begin(), read_points.end());
        read_points.erase(std::unique(read_points.begin(), read_points.end()), read_points.end());
        memory_->failed[cluster_key(cluster)] = std::move(read_points);
      }
    }
    compact();
    return stats;
  }

  /// The touched vertices under the compaction's new indices (dropped ones left out).
  void leave_suspects(const std::vector<std::uint32_t>& new_index) {
    suspects_->known = true;
    suspects_->vertices.clear();
    for (std::uint32_t v : touched_)
      if (new_index[v] != kDropped) suspects_->vertices.push_back(new_index[v]);
    std::sort(suspects_->vertices.begin(), suspects_->vertices.end());
    suspects_->vertices.erase(std::unique(suspects_->vertices.begin(), suspects_->vertices.end()),
                              suspects_->vertices.end());
  }

 private:
  static constexpr int kMaxMerges = 4;
  static constexpr std::size_t kMaxTriangulatedLoop = 200;
  static constexpr std::size_t kMaxRefinedTriangles = 1000;
  // Its cubic number of candidate triangles each need the field.
  static constexpr std::size_t kMaxNearFieldTriangulatedLoop = 64;
  static constexpr std::size_t kInnerApexCandidates = 8;

  void add_triangle_to_maps(std::uint32_t t) {
    for (std::uint32_t v : mesh_.triangles[t]) triangles_of_vertex_.add(v, t);
  }

  /// Calls f(t, +1) for every live triangle t using the edge as a->b and f(t, -1) for b->a, not
  /// counting those in `removed` (if given). A triangle is reported once per edge of it joining
  /// a and b, and that as often as such edges join them (which matters only for a collapsed
  /// triangle, whose doubled uses make the edge non-manifold).
  template <class F>
  void for_each_use(std::uint32_t a, std::uint32_t b, const std::unordered_set<std::uint32_t>* removed,
                    F&& f) const {
    const std::uint64_t key = edge_key(a, b);
    std::uint32_t previous = UINT32_MAX;
    triangles_of_vertex_.for_each(a, [&](std::uint32_t t) {
      if (t == previous) return;  // the same triangle at its other corner at a
      previous = t;
      const Triangle& tri = mesh_.triangles[t];
      int edges_joining = 0;
      for (int k = 0; k < 3; ++k) edges_joining += edge_key(tri[k], tri[(k + 1) % 3]) == key;
      if (edges_joining == 0 || deleted_[t] || (removed && removed->count(t))) return;
      for (int repeat = 0; repeat < edges_joining; ++repeat)
        for (int k = 0; k < 3; ++k)
          if (tri[k] == a && tri[(k + 1) % 3] == b)
            f(t, +1);
          else if (tri[k] == b && tri[(k + 1) % 3] == a)
            f(t, -1);
    });
  }

  /// Live triangles using the edge, with +1 for a->b and -1 for b->a.
  std::vector<std::pair<std::uint32_t, int>> uses(std::uint32_t a, std::uint32_t b,
                                                  const std::unordered_set<std::uint32_t>& removed) const {
    std::vector<std::pair<std::uint32_t, int>> result;
    for_each_use(a, b, &removed, [&](std::uint32_t t, int sign) { result.push_back({t, sign}); });
    return result;
  }

  bool manifold_edge(std::uint32_t a, std::uint32_t b) const {
    int count = 0, first_sign = 0;
    bool opposite = false;
    for_each_use(a, b, nullptr, [&](std::uint32_t, int sign) {
      if (count == 0) first_sign = sign;
      if (count == 1) opposite = sign != first_sign;
      ++count;
    });
    return count == 2 && opposite;
  }

  /// Scratch space of `manifold_vertex`, reused from vertex to vertex.
  struct FanScratch {
    std::vector<std::uint32_t> around, parent, link;
    std::vector<std::uint32_t> next, previous, follows;  // plainly_sound's, per triangle of `around`

    /// Disjoint sets over the triangles in `around`, each on its own.
    void separate_fans() {
      parent.resize(around.size());
      std::iota(parent.begin(), parent.end(), 0u);
    }
    std::uint32_t fan_of(std::uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    }
    void join_fans(std::uint32_t a, std::uint32_t b) { parent[fan_of(a)] = fan_of(b); }
    std::size_t fan_count() {
      std::size_t fans = 0;
      for (std::uint32_t i = 0; i < around.size(); ++i) fans += fan_of(i) == i;
      return fans;
    }
  };

  /// Whether the triangles around v form one fan (a disc or, at a border, a half disc): joined
  /// across the manifold edges at v, they form one piece.
  bool manifold_vertex(std::uint32_t v, FanScratch& scratch) const {
    std::vector<std::uint32_t>& around = scratch.around;
    around.clear();
    triangles_of_vertex_.for_each(v, [&](std::uint32_t t) {
      if (!deleted_[t]) around.push_back(t);
    });
    if (around.empty()) return true;
    scratch.separate_fans();
    std::vector<std::uint32_t>& link = scratch.link;
    link.clear();
    for (std::uint32_t t : around)
      for (std::uint32_t w : mesh_.triangles[t])
        if (w != v) link.push_back(w);
    std::sort(link.begin(), link.end());
    link.erase(std::unique(link.begin(), link.end()), link.end());
    for (std::uint32_t w : link) {
      if (!manifold_edge(v, w)) continue;
      // Every triangle with the edge v-w joins the first of them.
      std::uint32_t first = UINT32_MAX;
      for (std::uint32_t i = 0; i < around.size(); ++i) {
        const Triangle& tri = mesh_.triangles[around[i]];
        if (std::find(tri.begin(), tri.end(), w) == tri.end()) continue;
        if (first == UINT32_MAX)
          first = i;
        else
          scratch.join_fans(i, first);
      }
    }
    return scratch.fan_count() == 1;
  }

  /// Whether v is on a non-manifold or open edge or is a non-manifold vertex itself.
  bool defective_vertex(std::uint32_t v, FanScratch& scratch) const {
    if (triangles_of_vertex_.empty(v)) return false;
    bool bad_edge = false;
    triangles_of_vertex_.for_each(v, [&](std::uint32_t t) {
      if (bad_edge) return;
      const Triangle& tri = mesh_.triangles[t];
      for (int k = 0; k < 3 && !bad_edge; ++k) {
        const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
        if ((a == v || b == v) && !manifold_edge(a, b)) bad_edge = true;
      }
    });
    return bad_edge || !manifold_vertex(v, scratch);
  }

  /// Whether v is plainly sound: its triangles are live and proper, each edge at v is used once
  /// each way by them, and they form one fan. Then defective_vertex(v) is false; where this
  /// returns false, defective_vertex decides. Far cheaper, as it looks at v's own fan only.
  bool plainly_sound(std::uint32_t v, FanScratch& scratch) const {
    std::vector<std::uint32_t>& around = scratch.around;
    around.clear();
    bool plain = true;
    triangles_of_vertex_.for_each(v, [&](std::uint32_t t) {
      const Triangle& tri = mesh_.triangles[t];
      plain = plain && !deleted_[t] && tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2];
      around.push_back(t);
    });
    if (!plain || around.empty()) return false;
    // Each triangle (v, next, previous): sound when every next is one triangle's previous and
    // no other triangle's next (each edge at v used once each way), and following next -> the
    // triangle it is previous of visits every triangle once (one fan). Fans are small: pairs.
    const std::size_t k = around.size();
    std::vector<std::uint32_t>&next = scratch.next, &previous = scratch.previous, &follows = scratch.follows;
    next.resize(k);
    previous.resize(k);
    follows.resize(k);
    for (std::size_t i = 0; i < k; ++i) {
      const Triangle& tri = mesh_.triangles[around[i]];
      const int corner = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
      next[i] = tri[(corner + 1) % 3];
      previous[i] = tri[(corner + 2) % 3];
    }
    for (std::size_t i = 0; i < k; ++i) {
      int as_previous = 0, as_next = 0;
      for (std::size_t j = 0; j < k; ++j) {
        if (previous[j] == next[i]) {
          ++as_previous;
          follows[i] = static_cast<std::uint32_t>(j);
        }
        as_next += next[j] == next[i];
      }
      if (as_previous != 1 || as_next != 1) return false;
    }
    std::size_t steps = 0;
    std::size_t i = 0;
    do {
      i = follows[i];
      ++steps;
    } while (i != 0 && steps <= k);
    return steps == k;
  }

  /// Vertices of bad edges and non-manifold vertices, grouped by proximity (max_radius); only
  /// among `scan` (sorted) if given.
  std::vector<std::vector<std::uint32_t>> defect_clusters(const std::vector<std::uint32_t>* scan) const {
    // Each vertex is judged by its own fan alone, so the vertices are scanned in parallel.
    std::vector<char> defective(mesh_.vertices.size(), 0);
    const std::uint32_t count = static_cast<std::uint32_t>(scan ? scan->size() : mesh_.vertices.size());
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, count),
                      [&](const tbb::blocked_range<std::uint32_t>& range) {
                        FanScratch scratch;
                        for (std::uint32_t i = range.begin(); i != range.end(); ++i) {
                          const std::uint32_t v = scan ? (*scan)[i] : i;
                          defective[v] = !plainly_sound(v, scratch) && defective_vertex(v, scratch);
                        }
                      });
    std::vector<std::uint32_t> bad;
    for (std::uint32_t v = 0; v < mesh_.vertices.size(); ++v)
      if (defective[v]) bad.push_back(v);
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

  std::size_t repair(const std::vector<std::uint32_t>& cluster) {
    refined_ = false;
    if (repair_with_balls(cluster)) return 1;
    return fill_open_loop(cluster) ? 1 : 0;
  }

  /// Closes a defect that is nothing but one simple loop of open edges with the loop's own
  /// triangulation, removing nothing: a sliver of surface narrower than the sampling (the end of
  /// a pass 0.001 short of a coincident one) leaves a long thin gap no ball can cover.
  bool fill_open_loop(const std::vector<std::uint32_t>& cluster) {
    std::unordered_map<std::uint32_t, std::uint32_t> loop_next, loop_triangle;
    const std::unordered_set<std::uint32_t> nothing;
    std::unordered_map<std::uint32_t, int> incoming;
    for (std::uint32_t v : cluster) {
      bool failed = false;
      triangles_of_vertex_.for_each(v, [&](std::uint32_t t) {
        if (deleted_[t] || failed) return;
        const Triangle& tri = mesh_.triangles[t];
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
          if (a != v) continue;
          const auto edge_uses = uses(a, b, nothing);
          if (edge_uses.size() == 2 && edge_uses[0].second != edge_uses[1].second) continue;
          if (edge_uses.size() != 1 || !loop_next.emplace(a, b).second || ++incoming[b] > 1) {
            failed = true;
            return;
          }
          loop_triangle.emplace(a, t);
        }
      });
      if (failed) return false;
    }
    if (loop_next.size() != cluster.size() || loop_next.size() > kMaxTriangulatedLoop) return false;
    std::vector<std::uint32_t> loop;
    if (!single_loop(loop_next, loop)) return false;
    Fan fan = least_area_triangulation(loop, loop_triangle, nothing);
    if (fan.triangles.empty()) return false;
    if (fits(fan, nothing)) return emit(fan, {});
    // A ridge where three cuts meet under the loop: its own triangles sag below the ridge, the
    // refined ones follow it.
    double reach = 0.0;
    for (std::uint32_t v : loop)
      reach = std::max(reach, (mesh_.vertices[v] - mesh_.vertices[loop[0]]).norm());
    return refine(fan, reach) && fits(fan, nothing) && emit(fan, {});
  }

  /// The cycle of `next` (a -> b for each open edge) from its least vertex into `loop`; false
  /// unless it is one cycle through all of them, at least three.
  static bool single_loop(const std::unordered_map<std::uint32_t, std::uint32_t>& next,
                          std::vector<std::uint32_t>& loop) {
    if (next.size() < 3) return false;
    const std::uint32_t first = std::min_element(next.begin(), next.end())->first;
    for (std::uint32_t v = first;;) {
      loop.push_back(v);
      auto it = next.find(v);
      if (it == next.end() || loop.size() > next.size()) return false;
      v = it->second;
      if (v == first) break;
    }
    return loop.size() == next.size();
  }

  bool repair_with_balls(std::vector<std::uint32_t> cluster) {
    // Defects closer than a ball apart are one defect: a ball whose ring meets another defect
    // takes that defect's vertices into the cluster, and the balls grow again from its centre.
    for (int merge = 0; merge <= kMaxMerges; ++merge) {
      Vector3d centre = Vector3d::Zero();
      for (std::uint32_t v : cluster) centre += mesh_.vertices[v];
      centre /= static_cast<double>(cluster.size());
      double spread = 0.0;
      for (std::uint32_t v : cluster) spread = std::max(spread, (mesh_.vertices[v] - centre).norm());
      if (spread > options_.max_radius) return 0;
      std::vector<std::uint32_t> met;
      for (double radius = std::max(1.5 * spread, 0.05 * options_.max_radius); radius <= options_.max_radius;
           radius *= 1.5) {
        if (try_ball(cluster, centre, radius, met)) return 1;
        if (!met.empty()) break;
      }
      if (met.empty()) return 0;
      const std::size_t before = cluster.size();
      cluster.insert(cluster.end(), met.begin(), met.end());
      std::sort(cluster.begin(), cluster.end());
      cluster.erase(std::unique(cluster.begin(), cluster.end()), cluster.end());
      if (cluster.size() == before) return 0;
    }
    return 0;
  }

  /// `met` receives the vertices of a defect the ball's ring runs into (then the ball fails).
  bool try_ball(const std::vector<std::uint32_t>& cluster, const Vector3d& centre, double radius,
                std::vector<std::uint32_t>& met) {
    // Triangles with a vertex in the ball, reached over the surface from the defect: a ball
    // reaching through a thin wall must not take the other side's triangles with it.
    std::unordered_set<std::uint32_t> removed;
    std::vector<std::uint32_t> removed_order;
    std::vector<std::uint32_t> stack;
    {
      std::unordered_set<std::uint32_t> reached;
      std::vector<std::uint32_t> front;
      for (std::uint32_t v : cluster)
        if ((mesh_.vertices[v] - centre).norm() <= radius && reached.insert(v).second) front.push_back(v);
      while (!front.empty()) {
        const std::uint32_t v = front.back();
        front.pop_back();
        bool live = false;
        triangles_of_vertex_.for_each(v, [&](std::uint32_t t) {
          if (deleted_[t]) return;
          live = true;
          for (std::uint32_t w : mesh_.triangles[t])
            if ((mesh_.vertices[w] - centre).norm() <= radius && reached.insert(w).second) front.push_back(w);
        });
        if (live) stack.push_back(v);
      }
    }
    std::sort(stack.begin(), stack.end());
    for (std::uint32_t v : stack)
      triangles_of_vertex_.for_each(v, [&](std::uint32_t t) {
        if (!deleted_[t] && removed.insert(t).second) removed_order.push_back(t);
      });
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
            triangles_of_vertex_.for_each(v, [&](std::uint32_t s) {
              if (!deleted_[s] && !removed.count(s) && in_ring.insert(s).second) ring.push_back(s);
            });
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
          if (after.size() != 1) {
            met = {a, b};
            return false;
          }
          // Open only because its partner went with the ball, not a defect outside it.
          const auto before = uses(a, b, {});
          if (before.size() != 2 || before[0].second == before[1].second) {
            met = {a, b};
            return false;
          }
          if (!loop_next.emplace(a, b).second) pinched.push_back(a);
          loop_triangle.try_emplace(a, t);
          if (++incoming[b] > 1) pinched.push_back(b);
        }
      }
      if (pinched.empty()) break;
      if (attempt == 2) return false;
      std::sort(pinched.begin(), pinched.end());
      for (std::uint32_t v : pinched)
        triangles_of_vertex_.for_each(v, [&](std::uint32_t t) {
          if (!deleted_[t] && removed.insert(t).second) removed_order.push_back(t);
        });
    }
    std::vector<std::uint32_t> loop;
    if (!single_loop(loop_next, loop)) return false;
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
    // Where creases cross inside the hole (two equal tools crossing at one depth touch at a
    // point, and four seams leave it) the crossing is no point Newton's method finds from the
    // centroid, but the patches' own corner there is: a vertex of what was removed.
    {
      std::vector<std::pair<double, std::uint32_t>> inner;
      for (std::uint32_t t : removed_order)
        for (std::uint32_t v : mesh_.triangles[t])
          if (!loop_next.count(v)) inner.push_back({(mesh_.vertices[v] - centroid).norm(), v});
      std::sort(inner.begin(), inner.end());
      inner.erase(std::unique(inner.begin(), inner.end()), inner.end());
      for (std::size_t i = 0; i < std::min<std::size_t>(inner.size(), kInnerApexCandidates); ++i)
        for (int levels = 1; levels <= 2; ++levels) {
          const Fan fan = ringed_fan(loop, loop_triangle, mesh_.vertices[inner[i].second], levels, radius);
          if (fits(fan, removed)) return emit(fan, removed_order);
        }
    }
    // A long narrow hole (a gap along a seam) has no centre a fan could use without needles.
    if (loop.size() <= kMaxTriangulatedLoop) {
      const Fan fan = least_area_triangulation(loop, loop_triangle, removed);
      if (!fan.triangles.empty() && fits(fan, removed)) return emit(fan, removed_order);
    }
    if (loop.size() <= kMaxNearFieldTriangulatedLoop) {
      const Fan fan = near_field_triangulation(loop, loop_triangle, removed);
      if (!fan.triangles.empty() && fits(fan, removed)) return emit(fan, removed_order);
    }
    // A crease across a curved hole: the fan refined where it leaves the surface, each new point
    // on the exact surface, until every triangle fits (the triangles across the crease shrink
    // towards it). Costly (up to kMaxRefinedTriangles triangles, each checked): once per
    // defect, on the smallest hole its balls leave.
    if (!refined_) {
      refined_ = true;
      for (Fan fan : {ringed_fan(loop, loop_triangle, apex, 1, radius),
                      least_area_triangulation(loop, loop_triangle, removed)})
        if (refine(fan, radius) && fits(fan, removed)) return emit(fan, removed_order);
      // The stock's edge across the hole: each side triangulated and refined on its own.
      if (Fan fan = stock_edge_split(loop, loop_triangle, removed); refine(fan, radius) && fits(fan, removed))
        return emit(fan, removed_order);
    }
    return false;
  }

  /// Replacement triangles: index >= 0 an existing vertex, -1 - k the fan's k-th new point.
  struct Fan {
    std::vector<Vector3d> points;
    std::vector<std::array<std::int64_t, 3>> triangles;
    std::vector<std::uint32_t> ring_triangle;  // per triangle: the ring triangle it continues
    /// Per triangle (if not empty): the normal it must not fold back against, instead of its ring
    /// triangle's (which may be a sliver turned any way).
    std::vector<Vector3d> fold_normal;
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

  /// The loop's triangulation of least total area, over its own vertices only.
  Fan least_area_triangulation(const std::vector<std::uint32_t>& loop,
                               const std::unordered_map<std::uint32_t, std::uint32_t>& loop_triangle,
                               const std::unordered_set<std::uint32_t>& removed) const {
    return best_triangulation(loop, loop_triangle, removed, false);
  }

  /// The loop's triangulation of least total area, over its own vertices only, among those whose
  /// every triangle is near the exact surface: where a crease crosses the hole, the one that
  /// follows it.
  Fan near_field_triangulation(const std::vector<std::uint32_t>& loop,
                               const std::unordered_map<std::uint32_t, std::uint32_t>& loop_triangle,
                               const std::unordered_set<std::uint32_t>& removed) const {
    return best_triangulation(loop, loop_triangle, removed, true);
  }

  /// Where the stock's edge crosses the hole (the cuts of a raster's rows reaching the stock's
  /// side face), the loop is a run of the stock face's vertices and a run of the cuts', and the
  /// two vertices where the runs meet lie on that edge: each run closed by the chord between
  /// them and triangulated on its own, so that refining the chord moves its points onto the edge
  /// (a triangulation of the whole loop crosses the edge everywhere). Empty unless the loop is
  /// two such runs.
  Fan stock_edge_split(const std::vector<std::uint32_t>& loop,
                       const std::unordered_map<std::uint32_t, std::uint32_t>& loop_triangle,
                       const std::unordered_set<std::uint32_t>& removed) const {
    const std::size_t n = loop.size();
    auto on_stock = [&](std::size_t i) {
      const PatchKind kind = mesh_.tags[loop_triangle.at(loop[i % n])].kind;
      return kind == PatchKind::StockFace || kind == PatchKind::CutSurface;
    };
    std::vector<std::size_t> changes;
    for (std::size_t i = 0; i < n; ++i)
      if (on_stock(i) != on_stock(i + n - 1)) changes.push_back(i);
    if (changes.size() != 2) return {};
    Fan fan;
    for (const auto& [from, to] :
         {std::pair{changes[0], changes[1]}, std::pair{changes[1], changes[0] + n}}) {
      std::vector<std::uint32_t> run;
      for (std::size_t i = from; i <= to; ++i) run.push_back(loop[i % n]);
      if (run.size() < 3) return {};
      // Without needles: a side's vertices along the stock's edges lie on straight lines.
      const Fan half = best_triangulation(run, loop_triangle, removed, false, true);
      if (half.triangles.empty()) return {};
      fan.triangles.insert(fan.triangles.end(), half.triangles.begin(), half.triangles.end());
      fan.ring_triangle.insert(fan.ring_triangle.end(), half.ring_triangle.begin(), half.ring_triangle.end());
      // Each side folds against its ring as a whole: the sum of its ring triangles' area vectors.
      Vector3d side = Vector3d::Zero();
      for (std::size_t i = 0; i + 1 < run.size(); ++i) {
        const Triangle& ring = mesh_.triangles[loop_triangle.at(run[i])];
        side += (mesh_.vertices[ring[1]] - mesh_.vertices[ring[0]])
                    .cross(mesh_.vertices[ring[2]] - mesh_.vertices[ring[0]]);
      }
      fan.fold_normal.resize(fan.triangles.size(), side);
    }
    return fan;
  }

  /// Dynamic programming over the loop's sub-polygons for the least total area. No diagonal may
  /// be an edge the mesh keeps outside the hole (two loop vertices joined around it; `fits`
  /// rejects such a fill as non-manifold); with `only_near_field`, triangles off the exact
  /// surface (or needles, which `fits` rejects too) are not candidates either; with
  /// `no_needles`, needles are not.
  Fan best_triangulation(const std::vector<std::uint32_t>& loop,
                         const std::unordered_map<std::uint32_t, std::uint32_t>& loop_triangle,
                         const std::unordered_set<std::uint32_t>& removed, bool only_near_field,
                         bool no_needles = false) const {
    const double infinity = std::numeric_limits<double>::infinity();
    const std::size_t n = loop.size();
    // kept[i * n + j], i < j, diagonals only: 1 if the mesh keeps the edge, 0 if not, -1 unknown.
    std::vector<signed char> kept(n * n, -1);
    auto diagonal_kept = [&](std::size_t i, std::size_t j) {
      if (j == i + 1 || (i == 0 && j == n - 1)) return false;
      signed char& known = kept[i * n + j];
      if (known < 0) known = uses(loop[i], loop[j], removed).empty() ? 0 : 1;
      return known == 1;
    };
    auto cost = [&](std::size_t i, std::size_t k, std::size_t j) {
      if (diagonal_kept(i, k) || diagonal_kept(k, j) || diagonal_kept(i, j)) return infinity;
      const Vector3d &a = mesh_.vertices[loop[i]], &b = mesh_.vertices[loop[k]], &c = mesh_.vertices[loop[j]];
      const double area = (b - a).cross(c - a).norm();
      if (!only_near_field && !no_needles) return area;
      const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
      if (area < 1e-3 * longest) return infinity;
      if (only_near_field && !triangle_near_field(a, b, c, field_, options_.max_field_error)) return infinity;
      return area;
    };
    // best[i * n + j]: the least area of the polygon loop[i..j]; split[i * n + j]: its apex.
    std::vector<double> best(n * n, 0.0);
    std::vector<std::size_t> split(n * n, 0);
    for (std::size_t gap = 2; gap < n; ++gap)
      for (std::size_t i = 0; i + gap < n; ++i) {
        const std::size_t j = i + gap;
        double least = infinity;
        for (std::size_t k = i + 1; k < j; ++k) {
          if (best[i * n + k] == infinity || best[k * n + j] == infinity) continue;
          const double total = best[i * n + k] + best[k * n + j] + cost(i, k, j);
          if (total < least) {
            least = total;
            split[i * n + j] = k;
          }
        }
        best[i * n + j] = least;
      }
    Fan fan;
    if (best[n - 1] == infinity) return fan;
    std::vector<std::pair<std::size_t, std::size_t>> pending{{0, n - 1}};
    while (!pending.empty()) {
      const auto [i, j] = pending.back();
      pending.pop_back();
      if (j < i + 2) continue;
      const std::size_t k = split[i * n + j];
      // Against the loop's direction, as the fans are: the loop runs along the ring's open edges.
      fan.triangles.push_back({loop[j], loop[k], loop[i]});
      fan.ring_triangle.push_back(loop_triangle.at(loop[i]));
      pending.push_back({i, k});
      pending.push_back({k, j});
    }
    return fan;
  }

  /// Splits the fan's inner edges at their midpoints moved onto the exact surface, the longest
  /// edge of the worst triangle first, until every triangle is within the field error or the fan
  /// has kMaxRefinedTriangles. The fan's border (its edges used once) is never split: the ring
  /// shares it.
  bool refine(Fan& fan, double reach) const {
    auto error = [&](const std::array<std::int64_t, 3>& t) {
      const Vector3d a = point_of(fan, t[0]), b = point_of(fan, t[1]), c = point_of(fan, t[2]);
      return triangle_near_field(a, b, c, field_, options_.max_field_error) ? 0.0 : 1.0;
    };
    auto key = [](std::int64_t a, std::int64_t b) { return std::pair{std::min(a, b), std::max(a, b)}; };
    std::vector<double> errors;
    for (const auto& t : fan.triangles) errors.push_back(error(t));
    while (true) {
      const auto worst = std::max_element(errors.begin(), errors.end());
      if (worst == errors.end() || *worst == 0.0) return true;
      if (fan.triangles.size() + 2 > kMaxRefinedTriangles) return false;
      const std::size_t t = static_cast<std::size_t>(worst - errors.begin());
      // The triangle's inner edge whose midpoint is furthest off the surface (an edge across a
      // crease), of equals the longest.
      int best_edge = -1;
      std::pair<double, double> farthest{-1.0, 0.0};
      for (int k = 0; k < 3; ++k) {
        const std::int64_t a = fan.triangles[t][k], b = fan.triangles[t][(k + 1) % 3];
        int shared = 0;
        for (const auto& other : fan.triangles)
          for (int m = 0; m < 3; ++m) shared += key(other[m], other[(m + 1) % 3]) == key(a, b);
        if (shared != 2) continue;
        const Vector3d pa = point_of(fan, a), pb = point_of(fan, b);
        const std::pair<double, double> measure{std::abs(field_(0.5 * (pa + pb))), (pa - pb).norm()};
        if (measure > farthest) {
          farthest = measure;
          best_edge = k;
        }
      }
      if (best_edge < 0) return false;
      const std::int64_t a = fan.triangles[t][best_edge], b = fan.triangles[t][(best_edge + 1) % 3];
      const Vector3d middle = 0.5 * (point_of(fan, a) + point_of(fan, b));
      // A midpoint inside the part, under a convex crease, would go to the nearer face; lifted
      // off the part along the triangles' normals, Newton's method takes it to the crease.
      Vector3d normal = Vector3d::Zero();
      for (const auto& u : fan.triangles)
        for (int k = 0; k < 3; ++k)
          if (key(u[k], u[(k + 1) % 3]) == key(a, b)) {
            const Vector3d p = point_of(fan, u[0]);
            normal += (point_of(fan, u[1]) - p).cross(point_of(fan, u[2]) - p).normalized();
          }
      const double inside = field_(middle);
      const Vector3d start = inside < 0.0 && normal.norm() > 0.0
                                 ? Vector3d(middle - 2.0 * inside * normal.normalized())
                                 : middle;
      Vector3d onto = onto_surface(start, reach);
      if (!(std::abs(field_(onto)) <= options_.max_field_error)) onto = onto_surface(middle, reach);
      if (!(std::abs(field_(onto)) <= options_.max_field_error)) return false;
      fan.points.push_back(onto);
      const std::int64_t m = -static_cast<std::int64_t>(fan.points.size());
      // Both triangles with the edge become two each.
      const std::size_t count = fan.triangles.size();
      for (std::size_t u = 0; u < count; ++u)
        for (int k = 0; k < 3; ++k) {
          const std::int64_t p = fan.triangles[u][k], q = fan.triangles[u][(k + 1) % 3];
          if (key(p, q) != key(a, b)) continue;
          const std::int64_t r = fan.triangles[u][(k + 2) % 3];
          fan.triangles[u] = {p, m, r};
          fan.triangles.push_back({m, q, r});
          fan.ring_triangle.push_back(fan.ring_triangle[u]);
          if (!fan.fold_normal.empty()) fan.fold_normal.push_back(fan.fold_normal[u]);
          errors[u] = error(fan.triangles[u]);
          errors.push_back(error(fan.triangles.back()));
          break;
        }
    }
  }

  Vector3d point_of(const Fan& fan, std::int64_t index) const {
    return index >= 0 ? mesh_.vertices[static_cast<std::size_t>(index)]
                      : fan.points[static_cast<std::size_t>(-1 - index)];
  }

  bool fits(const Fan& fan, const std::unordered_set<std::uint32_t>& removed) const {
    if (fan.triangles.empty()) return false;  // no triangulation was found
    // A fan between existing vertices must not repeat an edge the ring already has.
    std::unordered_map<std::uint64_t, int> fan_uses;
    for (const auto& tri : fan.triangles)
      for (int k = 0; k < 3; ++k)
        if (tri[k] >= 0 && tri[(k + 1) % 3] >= 0)
          ++fan_uses[edge_key(static_cast<std::uint32_t>(tri[k]),
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
      if (!triangle_near_field(a, b, c, field_, options_.max_field_error)) return false;
      const Triangle& owner = mesh_.triangles[fan.ring_triangle[t]];
      const Vector3d ring_normal = (mesh_.vertices[owner[1]] - mesh_.vertices[owner[0]])
                                       .cross(mesh_.vertices[owner[2]] - mesh_.vertices[owner[0]]);
      const Vector3d normal = (b - a).cross(c - a);
      if (normal.norm() <= 1e-12 * std::max(1.0, ring_normal.norm())) return false;
      // Not a needle (a loop along a sliver would be closed by the sliver turned over).
      const double longest = std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
      if (normal.norm() < 1e-3 * longest) return false;
      // Folded back against the ring (a crease inside the hole may turn it by up to a right angle).
      const Vector3d& fold = fan.fold_normal.empty() ? ring_normal : fan.fold_normal[t];
      if (normal.dot(fold) < -0.5 * normal.norm() * fold.norm()) return false;
    }
    return true;
  }

  RepairMemory::Point point_key(std::uint32_t v) const {
    return {mesh_.vertices[v].x(), mesh_.vertices[v].y(), mesh_.vertices[v].z()};
  }

  std::vector<RepairMemory::Point> cluster_key(const std::vector<std::uint32_t>& cluster) const {
    std::vector<RepairMemory::Point> key;
    for (std::uint32_t v : cluster) key.push_back(point_key(v));
    std::sort(key.begin(), key.end());
    return key;
  }

  /// Whether the cluster failed before, with the same options, and no repair since changed the
  /// triangles around any vertex it looked at: then it fails the same way again (what it did
  /// depended on nothing else, the vertices' order included, which compaction keeps).
  bool fails_as_before(const std::vector<std::uint32_t>& cluster) const {
    const auto it = memory_->failed.find(cluster_key(cluster));
    if (it == memory_->failed.end()) return false;
    for (const RepairMemory::Point& p : it->second)
      if (memory_->changed.count(p)) return false;
    return true;
  }

  bool emit(const Fan& fan, const std::vector<std::uint32_t>& removed_order) {
    if (memory_) {
      for (std::uint32_t t : removed_order)
        for (std::uint32_t v : mesh_.triangles[t]) memory_->changed.insert(point_key(v));
      for (const auto& tri : fan.triangles)
        for (std::int64_t index : tri)
          if (index >= 0) memory_->changed.insert(point_key(static_cast<std::uint32_t>(index)));
    }
    for (std::uint32_t t : removed_order) {
      deleted_[t] = true;
      if (suspects_) touched_.insert(touched_.end(), mesh_.triangles[t].begin(), mesh_.triangles[t].end());
    }
    const auto first_new = static_cast<std::int64_t>(mesh_.vertices.size());
    for (const Vector3d& p : fan.points) {
      mesh_.vertices.push_back(p);
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
      if (suspects_) touched_.insert(touched_.end(), tri.begin(), tri.end());
    }
    return true;
  }

  void compact() {
    std::vector<std::uint32_t> new_index;
    remove_triangles(mesh_, patch_of_, deleted_, suspects_ ? &new_index : nullptr);
    if (suspects_) leave_suspects(new_index);
  }

  TriangleMesh& mesh_;
  std::vector<TriangleOrigin>& patch_of_;
  const RepairOptions& options_;
  const FieldFunction& field_;
  RepairMemory* memory_;
  DefectSuspects* suspects_;
  std::vector<std::uint32_t> touched_;  // vertices of defects and of removed or added triangles
  std::vector<bool> deleted_;
  bool refined_ = false;  // whether the current defect's fans were refined already
  VertexTriangles triangles_of_vertex_;
};

}  // namespace

void remove_triangles(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                      const std::vector<bool>& remove, std::vector<std::uint32_t>* new_index_out) {
  std::vector<bool> used(mesh.vertices.size(), false);
  keep_triangles(mesh, patch_of_triangle, [&](std::size_t t, const Triangle& tri) {
    if (remove[t]) return false;
    for (std::uint32_t v : tri) used[v] = true;
    return true;
  });
  // In place: a vertex's new index is never above its old one.
  std::vector<std::uint32_t> new_index(mesh.vertices.size(), kDropped);
  std::uint32_t count = 0;
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    if (!used[v]) continue;
    new_index[v] = count;
    mesh.vertices[count++] = mesh.vertices[v];
  }
  mesh.vertices.resize(count);
  for (Triangle& tri : mesh.triangles)
    for (std::uint32_t& v : tri) v = new_index[v];
  if (new_index_out) *new_index_out = std::move(new_index);
}

std::size_t weld_near_defects(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                              double distance, std::vector<EdgeUse>& uses) {
  // An undirected edge is sound when used once each way.
  sorted_edge_uses(mesh, uses);
  std::vector<std::uint32_t> defect;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    if (j - i != 2 || uses[i].forward == uses[i + 1].forward) {
      defect.push_back(static_cast<std::uint32_t>(uses[i].key >> 32));
      defect.push_back(static_cast<std::uint32_t>(uses[i].key & 0xffffffffu));
    }
    i = j;
  }
  std::sort(defect.begin(), defect.end());
  defect.erase(std::unique(defect.begin(), defect.end()), defect.end());
  return weld_near(mesh, patch_of_triangle, defect, distance, false);
}

std::size_t weld_near_pinches(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                              double distance, const std::vector<std::uint32_t>* among) {
  return weld_near(mesh, patch_of_triangle,
                   among ? non_manifold_vertices(mesh, *among) : non_manifold_vertices(mesh), distance, true);
}

std::size_t weld_near(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                      const std::vector<std::uint32_t>& defect, double distance, bool whole_reach) {
  if (defect.empty()) return 0;
  // Every vertex within `distance` of a defect's vertex becomes that vertex (the lowest index of
  // a group keeps its position).
  auto cell_of = [&](const Vector3d& p) {
    return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(p.x() / distance)),
                                       static_cast<std::int64_t>(std::floor(p.y() / distance)),
                                       static_cast<std::int64_t>(std::floor(p.z() / distance))};
  };
  auto pack = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    return (static_cast<std::uint64_t>(x & 0x1fffff) << 42) |
           (static_cast<std::uint64_t>(y & 0x1fffff) << 21) | static_cast<std::uint64_t>(z & 0x1fffff);
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> near_defects;
  // The cells searched: those holding a defect's vertex, and with `whole_reach` the 26 around
  // each too (every vertex within `distance`).
  const int reach = whole_reach ? 1 : 0;
  for (std::uint32_t v : defect) {
    const auto c = cell_of(mesh.vertices[v]);
    for (int dx = -reach; dx <= reach; ++dx)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dz = -reach; dz <= reach; ++dz) near_defects[pack(c[0] + dx, c[1] + dy, c[2] + dz)];
  }
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    const auto c = cell_of(mesh.vertices[v]);
    auto it = near_defects.find(pack(c[0], c[1], c[2]));
    if (it != near_defects.end()) it->second.push_back(v);
  }
  std::vector<std::uint32_t> parent(mesh.vertices.size());
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  std::size_t merged = 0;
  for (std::uint32_t v : defect) {
    const auto c = cell_of(mesh.vertices[v]);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = near_defects.find(pack(c[0] + dx, c[1] + dy, c[2] + dz));
          if (it == near_defects.end()) continue;
          for (std::uint32_t w : it->second) {
            if ((mesh.vertices[w] - mesh.vertices[v]).norm() > distance) continue;
            const std::uint32_t rv = find(v), rw = find(w);
            if (rv == rw) continue;
            parent[std::max(rv, rw)] = std::min(rv, rw);
            ++merged;
          }
        }
  }
  if (merged == 0) return 0;
  // Every root is its own root now (path halving left chains), so the relabelling below can
  // run in parallel.
  for (std::uint32_t v = 0; v < parent.size(); ++v) parent[v] = parent[parent[v]];
  // Triangles the welds made degenerate go, and so do pairs of one triangle and its reverse (a
  // sliver folded flat); of equal triangles one stays.
  // Only the triangles with a vertex of a weld or of a defect can collapse or come to equal
  // another: the others keep their vertices, and two equal triangles before the weld are a
  // defect themselves (their edges used twice the same way, or four times).
  std::vector<char> involved(mesh.vertices.size(), 0);
  for (std::uint32_t v : defect) involved[v] = 1;
  for (std::uint32_t v = 0; v < parent.size(); ++v)
    if (parent[v] != v) involved[v] = involved[parent[v]] = 1;
  std::vector<std::uint32_t> candidates;
  for (std::uint32_t i = 0; i < mesh.triangles.size(); ++i) {
    const Triangle& t = mesh.triangles[i];
    if (involved[t[0]] || involved[t[1]] || involved[t[2]]) candidates.push_back(i);
  }
  std::vector<bool> remove(mesh.triangles.size(), false);
  const Triangle degenerate{UINT32_MAX, UINT32_MAX, UINT32_MAX};  // sorts last
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(mesh.triangles.size())),
                    [&](const tbb::blocked_range<std::uint32_t>& range) {
                      for (std::uint32_t i = range.begin(); i != range.end(); ++i)
                        for (std::uint32_t& v : mesh.triangles[i]) v = parent[v];
                    });
  std::vector<std::pair<Triangle, std::uint32_t>> sorted(candidates.size());
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    Triangle key = mesh.triangles[candidates[k]];
    std::sort(key.begin(), key.end());
    const bool collapsed = key[0] == key[1] || key[1] == key[2];
    sorted[k] = {collapsed ? degenerate : key, candidates[k]};
  }
  tbb::parallel_sort(sorted.begin(), sorted.end());  // (triangle, index) pairs are unique
  while (!sorted.empty() && sorted.back().first == degenerate) {
    remove[sorted.back().second] = true;
    sorted.pop_back();
  }
  auto orientation = [&](std::uint32_t i) {
    const Triangle& t = mesh.triangles[i];
    // Even rotations of the sorted order are one orientation.
    const std::size_t first = static_cast<std::size_t>(std::min_element(t.begin(), t.end()) - t.begin());
    return t[(first + 1) % 3] < t[(first + 2) % 3];
  };
  for (std::size_t i = 0; i < sorted.size();) {
    std::size_t j = i;
    while (j < sorted.size() && sorted[j].first == sorted[i].first) ++j;
    int forward = 0, backward = 0;
    for (std::size_t k = i; k < j; ++k) (orientation(sorted[k].second) ? forward : backward)++;
    // Keep the surplus of one orientation over the other, the first ones of it.
    int keep_forward = std::max(0, forward - backward), keep_backward = std::max(0, backward - forward);
    keep_forward = std::min(keep_forward, 1);
    keep_backward = std::min(keep_backward, 1);
    for (std::size_t k = i; k < j; ++k) {
      int& budget = orientation(sorted[k].second) ? keep_forward : keep_backward;
      if (budget > 0)
        --budget;
      else
        remove[sorted[k].second] = true;
    }
    i = j;
  }
  remove_triangles(mesh, patch_of_triangle, remove);
  return merged;
}

RepairStats repair_small_defects(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                                 const RepairOptions& options, const FieldFunction& field,
                                 RepairMemory* memory, DefectSuspects* suspects) {
  if (mesh.triangles.empty()) return {};
  return Repairer(mesh, patch_of_triangle, options, field, memory, suspects).run();
}

}  // namespace morph::detail
