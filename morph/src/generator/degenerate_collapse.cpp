// SPDX-License-Identifier: Apache-2.0
#include <morph/degenerate_collapse.h>
#include <morph/parallel.h>

#include "generator/limit_classes.h"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <unordered_map>
#include <utility>

namespace morph {
namespace {

using Triple = PlaneTriple;
using Edge = std::pair<std::uint32_t, std::uint32_t>;

// ---- step 0: each conformed polygon's support and the plane of each of its edges ----------------

const ExactPlane* plane_of(const Triple& t, std::uint64_t rank) {
  for (const ExactPlane* p : t.planes)
    if (p->rank == rank) return p;
  return nullptr;
}

// The planes two vertices share (at most three; no list is allocated for each of a job's
// millions of corners).
struct SharedPlanes {
  std::array<const ExactPlane*, 3> planes{};
  std::size_t count = 0;
  const ExactPlane* const* begin() const { return planes.data(); }
  const ExactPlane* const* end() const { return planes.data() + count; }
};
SharedPlanes shared(const Triple& u, const Triple& v) {
  SharedPlanes out;
  for (const ExactPlane* p : u.planes)
    if (plane_of(v, p->rank)) out.planes[out.count++] = p;
  return out;
}

// A conformed polygon's support and the plane of each of its edges (edge k: loop[k] to loop[k+1]),
// each named where a vertex holds it.
struct PlanarLoop {
  PlaneRef support = 0;
  bool support_turned = false;
  std::vector<PlaneRef> edge_planes;
};

PlanarLoop planar_loop(const ConformedSurface& surface, const ConformedPolygon& polygon) {
  const auto& loop = polygon.loop;
  const std::size_t n = loop.size();
  // The support is the one plane every vertex has; consecutive vertices share it and their edge's.
  SharedPlanes common = shared(surface.vertices[loop[0]], surface.vertices[loop[1]]);
  for (std::size_t k = 2; k < n && common.count > 1; ++k)
    common.count = static_cast<std::size_t>(
        std::remove_if(common.planes.begin(), common.planes.begin() + common.count,
                       [&](const ExactPlane* p) { return !plane_of(surface.vertices[loop[k]], p->rank); }) -
        common.planes.begin());
  PlanarLoop out;
  // A vertex may hold the support turned over (an edge of a piece outside it, flipped()): a
  // stock face's support contracts, a sweep facet's expands.
  const ExactPlane& support = *common.planes[0];
  out.support = surface.vertices.index_of(support);
  out.support_turned = support.direction != (polygon.move < 0 ? -1 : 1);
  out.edge_planes.reserve(n);
  for (std::size_t k = 0; k < n; ++k)
    for (const ExactPlane* p : shared(surface.vertices[loop[k]], surface.vertices[loop[(k + 1) % n]]))
      if (p->rank != support.rank) {
        out.edge_planes.push_back(surface.vertices.index_of(*p));
        break;
      }
  return out;
}

// ---- steps 2-4: the limit polygons ----------------------------------------------------------------

class Limit {
 public:
  Limit(const ConformedSurface& surface, const std::vector<Eigen::Vector3d>& points,
        const std::vector<PlanarLoop>& planar, const std::vector<std::uint32_t>& root,
        const std::set<std::uint32_t>& apart, ExecutionPolicy policy)
      : surface_(surface), points_(points), policy_(policy) {
    rep_.resize(root.size());
    apart_.resize(root.size());
    for (std::uint32_t v = 0; v < root.size(); ++v) {
      apart_[v] = apart.count(root[v]) > 0;
      rep_[v] = apart_[v] ? v : root[v];
    }
    const std::size_t n = surface.polygons.size();
    resize_faulted_in(polygons_, n, policy);
    removed_.assign(n, 0);
    zipped_.assign(n, 0);
    flat_.assign(n, kUnknown);
    for_each_index(policy_, 0, n, [&](std::size_t i) { add(i, surface.polygons[i], planar[i]); });
    // Each vertex's polygons, in polygon order (a counting sort).
    first_.assign(root.size() + 1, 0);
    for (std::size_t i = 0; i < n; ++i)
      if (!removed_[i])
        for (std::uint32_t v : polygons_[i].loop) ++first_[v + 1];
    for (std::size_t v = 0; v < root.size(); ++v) first_[v + 1] += first_[v];
    around_.resize(first_.back());
    std::vector<std::size_t> fill(first_.begin(), first_.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      if (!removed_[i])
        for (std::uint32_t v : polygons_[i].loop) around_[fill[v]++] = i;
  }

  // Step 3, until no sliver is left that can be zipped.
  // A polygon's flatness does not change as zips split its edges (the points put in lie on the
  // edges), so it is found once, in parallel.
  void zip_slivers(bool enabled) {
    if (!enabled) return;
    for_each_index(policy_, 0, polygons_.size(), [&](std::size_t i) {
      if (!removed_[i]) flat_[i] = flat(polygons_[i]) ? 1 : 0;
    });
    std::vector<std::size_t> slivers;
    for (std::size_t i = 0; i < polygons_.size(); ++i)
      if (!removed_[i] && flat_[i] == 1) slivers.push_back(i);
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t i : slivers)
        if (!removed_[i] && zip(i)) changed = true;
    }
  }

  // Step 4: the classes (roots) at edges or vertices where the limit is not a 2-manifold. Sorted
  // arrays, not maps: bear.nc at 0.01 has 5 million corners, and a map node for each was most of
  // this step's time.
  std::set<std::uint32_t> non_manifold(const std::vector<std::uint32_t>& root) const {
    std::set<std::uint32_t> bad;
    // Every corner as (vertex, next, previous), sorted: grouped by vertex, each directed edge
    // (vertex, next) once per use. Filled and sorted in parallel (one thread building these
    // lists for bear.nc's 5 million corners left the other idle).
    struct Corner {
      std::uint32_t at, next, previous;
      bool operator<(const Corner& o) const {
        return at < o.at || (at == o.at && (next < o.next || (next == o.next && previous < o.previous)));
      }
    };
    std::vector<std::size_t> first_corner(polygons_.size() + 1, 0);
    for (std::size_t i = 0; i < polygons_.size(); ++i)
      first_corner[i + 1] = first_corner[i] + (removed_[i] ? 0 : polygons_[i].loop.size());
    std::vector<Corner> corners;
    resize_faulted_in(corners, first_corner.back(), policy_);
    for_each_index(policy_, 0, polygons_.size(), [&](std::size_t i) {
      if (removed_[i]) return;
      const auto& loop = polygons_[i].loop;
      const std::size_t n = loop.size();
      for (std::size_t k = 0; k < n; ++k)
        corners[first_corner[i] + k] = {loop[k], loop[(k + 1) % n], loop[(k + n - 1) % n]};
    });
    sort_under(policy_, corners.begin(), corners.end(), std::less<Corner>());
    // Vertex v's corners are corners[first[v]] to corners[first[v + 1]].
    std::vector<std::size_t> first(root.size() + 1, 0);
    for_each_index(policy_, 0, root.size() + 1, [&](std::size_t v) {
      first[v] =
          static_cast<std::size_t>(std::lower_bound(corners.begin(), corners.end(), v,
                                                    [](const Corner& c, std::size_t x) { return c.at < x; }) -
                                   corners.begin());
    });
    std::vector<std::pair<Edge, std::size_t>> uses;
    reserve_faulted_in(uses, corners.size(), policy_);
    for (std::size_t k = 0, end; k < corners.size(); k = end) {
      for (end = k + 1;
           end < corners.size() && corners[end].at == corners[k].at && corners[end].next == corners[k].next;)
        ++end;
      uses.emplace_back(Edge{corners[k].at, corners[k].next}, end - k);
    }
    // Both checks in parallel, each use and each vertex flagging itself; the classes are
    // gathered after (a set: the same whatever the order).
    std::vector<char> bad_use(uses.size(), 0);
    for_each_index(policy_, 0, uses.size(), [&](std::size_t k) {
      const auto& [e, count] = uses[k];
      const Edge reverse{e.second, e.first};
      const auto back = std::lower_bound(uses.begin(), uses.end(), reverse,
                                         [](const auto& u, const Edge& x) { return u.first < x; });
      bad_use[k] = count != 1 || back == uses.end() || back->first != reverse || back->second != 1;
    });
    for (std::size_t k = 0; k < uses.size(); ++k)
      if (bad_use[k]) bad.insert(root[uses[k].first.first]), bad.insert(root[uses[k].first.second]);
    tbb::enumerable_thread_specific<std::vector<Edge>> scratch;
    std::vector<char> bad_fan(root.size(), 0);
    for_each_index(policy_, 0, root.size(), [&](std::size_t v) {
      if (first[v] == first[v + 1]) return;
      const auto around = corners.begin() + static_cast<std::ptrdiff_t>(first[v]);
      const std::size_t m = first[v + 1] - first[v];
      // One fan: from a corner, the corner whose next is this one's previous, around to the start.
      // next_of maps next to previous (the corners come sorted by next); a next used twice leaves
      // it shorter than m, so the vertex is flagged whichever entry is kept. Otherwise, where no
      // use is flagged above, the previous vertices are the next ones again, once each: the walk
      // goes round one cycle of that permutation, and finds m steps from any start iff one fan.
      auto& next_of = scratch.local();
      next_of.clear();
      for (std::size_t c = 0; c < m; ++c)
        if (c + 1 == m || around[c + 1].next != around[c].next)
          next_of.push_back({around[c].next, around[c].previous});
      std::size_t steps = 0;
      std::uint32_t at = around[0].next;
      do {
        const auto it = std::lower_bound(next_of.begin(), next_of.end(), at,
                                         [](const Edge& w, std::uint32_t x) { return w.first < x; });
        if (it == next_of.end() || it->first != at) break;
        at = it->second, ++steps;
      } while (at != around[0].next && steps <= m);
      bad_fan[v] = steps != m || next_of.size() != m;
    });
    for (std::size_t v = 0; v < root.size(); ++v)
      if (bad_fan[v]) bad.insert(root[v]);
    return bad;
  }

  // The limit surface, its polygons moved out (the last use of this).
  // `vertices`: the conformed surface's (this reads them until it moves them out at the end).
  LimitSurface result(LimitCounts counts, VertexPlanes&& vertices, std::vector<Eigen::Vector3d>&& points) {
    LimitSurface out;
    std::vector<char> still_flat(polygons_.size(), 0);
    for_each_index(policy_, 0, polygons_.size(), [&](std::size_t i) {
      if (removed_[i]) return;
      polygons_[i].straight_corners = straight_corners(polygons_[i]);
      // A zip only puts points on a polygon's edges: its flatness changes with it alone.
      still_flat[i] = flat_[i] == kUnknown ? flat(polygons_[i]) : flat_[i];
    });
    out.polygons.reserve(static_cast<std::size_t>(std::count(removed_.begin(), removed_.end(), 0)));
    for (std::size_t i = 0; i < polygons_.size(); ++i)
      if (!removed_[i]) {
        counts.flat_polygons_left += still_flat[i];
        out.polygons.push_back(std::move(polygons_[i]));
      } else if (zipped_[i]) {
        ++counts.zipped_slivers;
      } else {
        ++counts.removed_polygons;
      }
    for (std::uint32_t v = 0; v < rep_.size(); ++v) counts.merged_vertices += rep_[v] != v;
    out.counts = counts;
    out.vertices = std::move(vertices);  // a copy took half a second on bear.nc
    out.points = std::move(points);
    return out;
  }

 private:
  Triple at(std::uint32_t v) const { return surface_.vertices[v]; }
  const ExactPlane& plane(PlaneRef ref) const { return plane_at(surface_.vertices, ref); }
  // limit_side_at_vertex() at vertex v, by the integers where v is a grid point (most vertices
  // the limit step looks at are ties, which the filter cannot decide).
  int limit_side(std::uint32_t v, const ExactPlane& e) const {
    const Triple t = at(v);
    if (const std::optional<GridPoint> x = grid_vertex_near(t[0], t[1], t[2], points_[v]))
      return limit_side_at_grid_vertex(t[0], t[1], t[2], *x, e);
    return limit_side_at_vertex(t[0], t[1], t[2], e);
  }
  bool on(std::uint32_t v, const ExactPlane& e) const { return limit_side(v, e) == 0; }

  // Step 2: the polygon's edges between distinct points, as polygon i.
  void add(std::size_t i, const ConformedPolygon& polygon, const PlanarLoop& planar) {
    LimitPolygon& p = polygons_[i];
    p.support = planar.support;
    p.support_turned = planar.support_turned;
    p.faces_out = polygon.move < 0;
    p.move = polygon.move, p.face = polygon.face;
    const std::size_t n = polygon.loop.size();
    p.loop.reserve(n);
    p.edge_planes.reserve(n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t a = rep_[polygon.loop[k]], b = rep_[polygon.loop[(k + 1) % n]];
      if (a == b) continue;  // an ε-edge
      p.loop.push_back(a);
      p.edge_planes.push_back(planar.edge_planes[k]);
    }
    removed_[i] = p.loop.size() < 3;
  }

  // The polygon that runs along the directed edge (the last in polygon order, should two).
  std::optional<std::size_t> owner(const Edge& edge) const {
    std::optional<std::size_t> found;
    const auto look = [&](std::size_t i) {
      if (removed_[i] || (found && *found >= i)) return;
      const std::vector<std::uint32_t>& loop = polygons_[i].loop;
      for (std::size_t k = 0; k < loop.size(); ++k)
        if (loop[k] == edge.first && loop[(k + 1) % loop.size()] == edge.second) {
          found = i;
          return;
        }
    };
    for (std::size_t k = first_[edge.first]; k < first_[edge.first + 1]; ++k) look(around_[k]);
    const auto more = inserted_around_.find(edge.first);
    if (more != inserted_around_.end())
      for (std::size_t i : more->second) look(i);
    return found;
  }

  // Every point on the line of the first edge: the limit is a segment. (The first edge's ends
  // lie on it by construction, and telling an exact zero costs the exact arithmetic.)
  bool flat(const LimitPolygon& p) const {
    return std::all_of(p.loop.begin() + 2, p.loop.end(),
                       [&](std::uint32_t v) { return on(v, plane(p.edge_planes[0])); });
  }
  std::vector<std::uint32_t> straight_corners(const LimitPolygon& p) const {
    std::vector<std::uint32_t> out;
    const std::size_t n = p.loop.size();
    for (std::size_t k = 0; k < n; ++k)
      if (on(p.loop[(k + 1) % n], plane(p.edge_planes[(k + n - 1) % n])))
        out.push_back(static_cast<std::uint32_t>(k));
    return out;
  }

  // Step 3 for polygon i (flat): its loop runs from one end of the segment to the other and back,
  // each way monotone. Order along the line's direction support × line plane: q comes after p iff
  // q is on the positive side of a plane of p's crossing the line, oriented by that direction.
  bool zip(std::size_t i) {
    const LimitPolygon& d = polygons_[i];
    // Points kept apart (step 4) are distinct vertices of one point: no order along the line.
    if (std::any_of(d.loop.begin(), d.loop.end(), [&](std::uint32_t v) { return apart_[v]; })) return false;
    const ExactPlane s = d.support_turned ? flipped(plane(d.support)) : plane(d.support);
    const ExactPlane& line = plane(d.edge_planes[0]);
    std::map<std::uint32_t, std::pair<const ExactPlane*, int>> crossing;  // point -> plane, its orientation
    for (std::uint32_t v : d.loop)
      for (const ExactPlane* c : at(v).planes)
        if (int o = normals_orientation(s, line, *c)) {
          crossing[v] = {c, o};
          break;
        }
    const auto after = [&](std::uint32_t q, std::uint32_t p) {
      const auto [c, o] = crossing.at(p);
      return limit_side(q, *c) * o > 0;
    };
    const std::size_t n = d.loop.size();
    std::size_t low = 0, high = 0;
    for (std::size_t k = 1; k < n; ++k) {
      if (after(d.loop[low], d.loop[k])) low = k;
      if (after(d.loop[k], d.loop[high])) high = k;
    }
    // Monotone up from low to high, then down back to low; distinct points strictly ordered.
    for (std::size_t k = low; k != high; k = (k + 1) % n)
      if (!after(d.loop[(k + 1) % n], d.loop[k])) return false;
    for (std::size_t k = high; k != low; k = (k + 1) % n)
      if (!after(d.loop[k], d.loop[(k + 1) % n])) return false;
    std::vector<std::uint32_t> sorted(d.loop);
    std::sort(sorted.begin(), sorted.end(), [&](std::uint32_t p, std::uint32_t q) { return after(q, p); });
    // Each neighbour across an edge x -> y of the sliver has y -> x: it takes the points strictly
    // between, from y to x.
    std::vector<std::pair<Edge, std::vector<std::uint32_t>>> inserts;
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t x = d.loop[k], y = d.loop[(k + 1) % n];
      const std::optional<std::size_t> across = owner({y, x});
      if (!across) return false;   // not a closed surface here: leave it
      if (*across == i) continue;  // the sliver's other chain: both edges vanish
      std::vector<std::uint32_t> between;
      for (std::uint32_t m : sorted)
        if ((after(m, x) && after(y, m)) || (after(m, y) && after(x, m))) between.push_back(m);
      if (after(y, x)) std::reverse(between.begin(), between.end());  // from y down to x
      inserts.push_back({{y, x}, between});
    }
    removed_[i] = zipped_[i] = 1;  // its edges are no one's before the neighbours take its points
    for (const auto& [edge, between] : inserts) split(edge, between);
    return true;
  }

  // Inserts `between` into the edge (owned by a polygon) from edge.first to edge.second.
  void split(const Edge& edge, const std::vector<std::uint32_t>& between) {
    const std::optional<std::size_t> owner_of = owner(edge);
    if (!owner_of) return;  // not a 2-manifold here: step 4 keeps its classes apart
    const std::size_t j = *owner_of;
    LimitPolygon& p = polygons_[j];
    const std::size_t n = p.loop.size();
    std::size_t k = 0;
    while (k < n && !(p.loop[k] == edge.first && p.loop[(k + 1) % n] == edge.second)) ++k;
    if (k == n) return;
    const PlaneRef line = p.edge_planes[k];
    p.loop.insert(p.loop.begin() + static_cast<std::ptrdiff_t>(k + 1), between.begin(), between.end());
    p.edge_planes.insert(p.edge_planes.begin() + static_cast<std::ptrdiff_t>(k + 1), between.size(), line);
    for (std::uint32_t m : between) inserted_around_[m].push_back(j);
    flat_[j] = kUnknown;
  }

  const ConformedSurface& surface_;
  const std::vector<Eigen::Vector3d>& points_;  // vertex_point() of each vertex
  ExecutionPolicy policy_;
  std::vector<std::uint32_t> rep_;
  std::vector<LimitPolygon> polygons_;
  std::vector<bool> apart_;             // per vertex: its class is kept apart
  std::vector<char> removed_, zipped_;  // per polygon (written in parallel: not vector<bool>)
  static constexpr char kUnknown = -1;
  std::vector<char> flat_;  // per polygon: 1 flat, 0 not, kUnknown not looked at since it changed
  // Each vertex's polygons (around_[first_[v]] to around_[first_[v + 1]]), and the polygons that
  // took it since (zips): where the owner of an edge is looked for. A job has millions of
  // corners and a few thousand zips: a table of every directed edge took a second to build.
  std::vector<std::size_t> first_, around_;
  std::unordered_map<std::uint32_t, std::vector<std::size_t>> inserted_around_;
};

}  // namespace

Eigen::Vector3d LimitSurface::outward_normal(const LimitPolygon& polygon) const {
  const Eigen::Vector3d& normal = plane_at(vertices, polygon.support).normal;
  return polygon.faces_out != polygon.support_turned ? normal : Eigen::Vector3d(-normal);
}

LimitSurface collapse_degenerates(ConformedSurface surface, ExecutionPolicy policy) {
  std::vector<PlanarLoop> planar;
  resize_faulted_in(planar, surface.polygons.size(), policy);
  for_each_index(policy, 0, planar.size(),
                 [&](std::size_t i) { planar[i] = planar_loop(surface, surface.polygons[i]); });
  std::vector<Eigen::Vector3d> points;
  const std::vector<std::uint32_t> root = limit_classes(surface.vertices, policy, &points);
  std::vector<std::size_t> class_size(root.size(), 0);
  for (std::uint32_t r : root) ++class_size[r];
  // Merge every class, then keep apart those where the limit is not a 2-manifold, until none is.
  std::set<std::uint32_t> apart;
  for (;;) {
    Limit limit(surface, points, planar, root, apart, policy);
    limit.zip_slivers(true);
    const std::set<std::uint32_t> bad = limit.non_manifold(root);
    if (bad.empty()) {
      LimitCounts counts;
      counts.kept_apart = apart.size();
      return limit.result(counts, std::move(surface.vertices), std::move(points));
    }
    const std::size_t before = apart.size();
    for (std::uint32_t c : bad)
      if (class_size[c] > 1) apart.insert(c);
    if (apart.size() == before) break;
  }
  // Not settled (not seen so far): every class apart and nothing zipped is the conformed
  // surface itself, a 2-manifold by construction.
  for (std::uint32_t v = 0; v < root.size(); ++v)
    if (class_size[root[v]] > 1) apart.insert(root[v]);
  Limit limit(surface, points, planar, root, apart, policy);
  limit.zip_slivers(false);
  LimitCounts counts;
  counts.kept_apart = apart.size();
  counts.unsettled = 1;
  return limit.result(counts, std::move(surface.vertices), std::move(points));
}

}  // namespace morph
