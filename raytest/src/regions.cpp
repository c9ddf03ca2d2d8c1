// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/union_find.h>
#include <raytest/regions.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace raytest {

namespace {

std::size_t pieces_of(double length, double max_edge) {
  const double n = std::ceil(length / max_edge);
  return n >= 1 && std::isfinite(n) ? static_cast<std::size_t>(std::min(n, 4096.0)) : 1;
}

// A parent triangle seen from its longest edge ab, in the parent's winding (a, b, c), cut into
// `bands` strips parallel to ab, each at most max_edge high: strip j lies between the rows at
// heights j / bands and (j + 1) / bands of the apex c's.
struct Banded {
  std::uint32_t a = 0, b = 0, c = 0;
  std::size_t bands = 1;
};

Banded banded(const morph::TriangleMesh& mesh, const morph::Triangle& tri, double max_edge) {
  int longest = 0;
  double length = -1;
  for (int e = 0; e < 3; ++e) {
    const double l = (mesh.vertices[tri[e]] - mesh.vertices[tri[(e + 1) % 3]]).norm();
    if (l > length) length = l, longest = e;
  }
  Banded out{tri[longest], tri[(longest + 1) % 3], tri[(longest + 2) % 3], 1};
  const Eigen::Vector3d ab = mesh.vertices[out.b] - mesh.vertices[out.a];
  const Eigen::Vector3d ac = mesh.vertices[out.c] - mesh.vertices[out.a];
  const double height = length > 0 ? ab.cross(ac).norm() / length : 0.0;
  out.bands = pieces_of(height, max_edge);
  return out;
}

// Length of the row at height fraction s (from ab, length `base`, to the apex).
double row_length(double base, std::size_t j, std::size_t bands) {
  return base * (1.0 - static_cast<double>(j) / static_cast<double>(bands));
}

// About how many triangles a parent becomes: its rows' pieces twice, its sides' points, its strips.
std::size_t estimated_triangles(const morph::TriangleMesh& mesh, const morph::Triangle& tri,
                                double max_edge) {
  const Banded t = banded(mesh, tri, max_edge);
  const double base = (mesh.vertices[t.b] - mesh.vertices[t.a]).norm();
  std::size_t total = 2 * t.bands + pieces_of((mesh.vertices[t.c] - mesh.vertices[t.a]).norm(), max_edge) +
                      pieces_of((mesh.vertices[t.c] - mesh.vertices[t.b]).norm(), max_edge);
  for (std::size_t j = 0; j < t.bands; ++j) total += 2 * pieces_of(row_length(base, j, t.bands), max_edge);
  return total;
}

// A point of an edge at an exact fraction num / den of the way from its lower-numbered end.
struct EdgeFraction {
  std::uint64_t num = 0, den = 1;
  bool operator<(const EdgeFraction& o) const { return num * o.den < o.num * den; }
  bool operator==(const EdgeFraction& o) const { return num * o.den == o.num * den; }
};

// Every edge's points, shared by both its triangles: evenly spaced at most max_edge apart, plus
// every row end a triangle beside it asks for, so that each strip's corners are points of its sides.
class EdgePoints {
 public:
  using Key = std::pair<std::uint32_t, std::uint32_t>;
  struct Point {
    EdgeFraction at;  ///< from the lower-numbered end
    std::uint32_t vertex;
  };

  void ask(std::uint32_t from, std::uint32_t to, std::uint64_t num, std::uint64_t den) {
    if (from < to)
      asked_[{from, to}].push_back({num, den});
    else
      asked_[{to, from}].push_back({den - num, den});
  }

  // Turns every edge's fractions into vertices appended to `vertices` (the ends are the edge's own).
  void settle(std::vector<Eigen::Vector3d>& vertices) {
    for (auto& [key, fractions] : asked_) {
      std::sort(fractions.begin(), fractions.end());
      fractions.erase(std::unique(fractions.begin(), fractions.end()), fractions.end());
      std::vector<Point>& points = points_[key];
      for (const EdgeFraction& f : fractions) {
        std::uint32_t vertex = key.first;
        if (f.num == f.den) {
          vertex = key.second;
        } else if (f.num != 0) {
          vertex = static_cast<std::uint32_t>(vertices.size());
          const double t = static_cast<double>(f.num) / static_cast<double>(f.den);
          vertices.push_back((1 - t) * vertices[key.first] + t * vertices[key.second]);
        }
        points.push_back({f, vertex});
      }
    }
    asked_.clear();
  }

  // The points of edge from -> to in that order, with their fractions measured from `from`.
  std::vector<Point> along(std::uint32_t from, std::uint32_t to) const {
    std::vector<Point> out = points_.at({std::min(from, to), std::max(from, to)});
    if (from > to) {
      std::reverse(out.begin(), out.end());
      for (Point& p : out) p.at.num = p.at.den - p.at.num;
    }
    return out;
  }

 private:
  std::map<Key, std::vector<EdgeFraction>> asked_;
  std::map<Key, std::vector<Point>> points_;
};

}  // namespace

RefinedMesh refine_long_edges(const morph::TriangleMesh& mesh, double max_edge, std::size_t max_triangles) {
  if (!(max_edge > 0)) throw morph::InputError("refine_long_edges: max_edge must be positive");
  RefinedMesh out;
  // Grow the edge length until the triangle budget holds.
  for (int attempt = 0; attempt < 64; ++attempt) {
    std::size_t total = 0;
    for (const auto& tri : mesh.triangles) total += estimated_triangles(mesh, tri, max_edge);
    if (total <= std::max(max_triangles, mesh.triangle_count())) break;
    max_edge *= std::sqrt(static_cast<double>(total) / static_cast<double>(max_triangles)) * 1.01;
  }
  out.max_edge = max_edge;
  morph::TriangleMesh& refined = out.mesh;
  refined.vertices = mesh.vertices;
  const bool tagged = mesh.tags.size() == mesh.triangles.size();

  // Strips, not a lattice: a long thin triangle (a sliver of a fan) becomes as many triangles as its
  // edges have points, not the square of its longest edge's. The edges' points are settled first,
  // so both triangles of an edge use the same ones and a closed mesh stays closed.
  std::vector<Banded> parents(mesh.triangles.size());
  EdgePoints edges;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const morph::Triangle& tri = mesh.triangles[t];
    const Banded p = parents[t] = banded(mesh, tri, max_edge);
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t from = tri[e], to = tri[(e + 1) % 3];
      const std::size_t n = pieces_of((mesh.vertices[to] - mesh.vertices[from]).norm(), max_edge);
      for (std::size_t k = 0; k <= n; ++k) edges.ask(from, to, k, n);
    }
    for (std::size_t j = 1; j < p.bands; ++j) {
      edges.ask(p.a, p.c, j, p.bands);
      edges.ask(p.b, p.c, j, p.bands);
    }
  }
  edges.settle(refined.vertices);

  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Banded& p = parents[t];
    const Eigen::Vector3d a = mesh.vertices[p.a], b = mesh.vertices[p.b], c = mesh.vertices[p.c];
    const Eigen::Vector3d ab = b - a;
    const double base = ab.norm();
    auto x_of = [&](std::uint32_t v) { return (refined.vertices[v] - a).dot(ab); };
    auto emit = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
      if (x == y || y == z || z == x) return;  // the zero-width start and end of a zip
      refined.triangles.push_back({x, y, z});
      out.parent.push_back(static_cast<std::uint32_t>(t));
      if (tagged) refined.tags.push_back(mesh.tags[t]);
    };
    const std::vector<EdgePoints::Point> bottom_edge = edges.along(p.a, p.b);
    const std::vector<EdgePoints::Point> left = edges.along(p.a, p.c), right = edges.along(p.b, p.c);
    // Row j from its end on ac to its end on bc (the sides' points at exactly j / bands).
    auto side_point = [&](const std::vector<EdgePoints::Point>& side, std::size_t j) {
      for (const EdgePoints::Point& q : side)
        if (q.at.num * p.bands == j * q.at.den) return q.vertex;
      throw std::logic_error("refine_long_edges: a row end is missing from its side");
    };
    auto row = [&](std::size_t j) {
      std::vector<std::uint32_t> points;
      if (j == 0) {
        for (const EdgePoints::Point& q : bottom_edge) points.push_back(q.vertex);
        return points;
      }
      if (j == p.bands) return std::vector<std::uint32_t>{p.c};
      const double s = static_cast<double>(j) / static_cast<double>(p.bands);
      const Eigen::Vector3d from = a + s * (c - a), to = b + s * (c - b);
      const std::size_t pieces = pieces_of(row_length(base, j, p.bands), max_edge);
      points.push_back(side_point(left, j));
      for (std::size_t i = 1; i < pieces; ++i) {
        points.push_back(static_cast<std::uint32_t>(refined.vertices.size()));
        refined.vertices.push_back(from +
                                   (static_cast<double>(i) / static_cast<double>(pieces)) * (to - from));
      }
      points.push_back(side_point(right, j));
      return points;
    };
    // Strictly between heights j and j + 1: the side's points there, by rising height.
    auto between = [&](const std::vector<EdgePoints::Point>& side, std::size_t j) {
      std::vector<std::uint32_t> points;
      for (const EdgePoints::Point& q : side)
        if (q.at.num * p.bands > j * q.at.den && q.at.num * p.bands < (j + 1) * q.at.den)
          points.push_back(q.vertex);
      return points;
    };
    std::vector<std::uint32_t> lower = row(0);
    for (std::size_t j = 0; j < p.bands; ++j) {
      // The strip is convex and every point of its boundary chain rises in x (ab's direction) along
      // both the lower row and the way round over the top: zip the two chains by x.
      const std::vector<std::uint32_t> upper_row = row(j + 1);
      std::vector<std::uint32_t> upper{lower.front()};
      for (std::uint32_t v : between(left, j)) upper.push_back(v);
      upper.insert(upper.end(), upper_row.begin(), upper_row.end());
      const std::vector<std::uint32_t> descending = between(right, j);
      upper.insert(upper.end(), descending.rbegin(), descending.rend());
      upper.push_back(lower.back());
      std::size_t i = 0, k = 0;
      while (i + 1 < lower.size() || k + 1 < upper.size()) {
        const bool advance_lower =
            k + 1 == upper.size() || (i + 1 < lower.size() && x_of(lower[i + 1]) <= x_of(upper[k + 1]));
        if (advance_lower) {
          emit(lower[i], lower[i + 1], upper[k]);
          ++i;
        } else {
          emit(lower[i], upper[k + 1], upper[k]);
          ++k;
        }
      }
      lower = upper_row;
    }
  }
  return out;
}

std::vector<DeviationRegion> find_regions(const morph::TriangleMesh& mesh, const std::vector<double>& values,
                                          const ToleranceBand& band, std::size_t max_sources) {
  if (values.size() != mesh.vertex_count())
    throw morph::InputError("find_regions: one value per vertex expected");
  const std::size_t n = values.size();
  std::vector<signed char> kind(n, 0);  // -1 gouge, +1 excess, 0 within or unknown
  for (std::size_t v = 0; v < n; ++v) {
    if (std::isnan(values[v])) continue;
    const DeviationClass c = classify(values[v], band);
    kind[v] = c == DeviationClass::Gouge ? -1 : c == DeviationClass::Excess ? 1 : 0;
  }
  morph::UnionFind components(n);
  std::vector<double> vertex_area(n, 0.0);
  for (const auto& tri : mesh.triangles) {
    const double area = 0.5 * (mesh.vertices[tri[1]] - mesh.vertices[tri[0]])
                                  .cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]])
                                  .norm();
    for (int e = 0; e < 3; ++e) {
      vertex_area[tri[e]] += area / 3.0;
      const std::uint32_t x = tri[e], y = tri[(e + 1) % 3];
      if (kind[x] != 0 && kind[x] == kind[y]) components.unite(x, y);
    }
  }
  std::map<std::uint32_t, std::size_t> index_of_root;  // root -> region, in vertex order
  std::vector<DeviationRegion> regions;
  std::vector<std::uint32_t> region_of(n, 0xffffffffu);
  for (std::size_t v = 0; v < n; ++v) {
    if (kind[v] == 0) continue;
    const std::uint32_t root = components.find(static_cast<std::uint32_t>(v));
    auto [it, inserted] = index_of_root.try_emplace(root, regions.size());
    if (inserted) {
      DeviationRegion r;
      r.kind = kind[v] < 0 ? DeviationClass::Gouge : DeviationClass::Excess;
      regions.push_back(r);
    }
    DeviationRegion& r = regions[it->second];
    region_of[v] = static_cast<std::uint32_t>(it->second);
    r.area += vertex_area[v];
    r.bounds.extend(mesh.vertices[v]);
    ++r.vertices;
    if (std::abs(values[v]) > std::abs(r.worst)) {
      r.worst = values[v];
      r.location = mesh.vertices[v];
    }
  }
  // Provenance: the tags of faces touching each region, with the worst value seen on them.
  if (mesh.tags.size() == mesh.triangles.size()) {
    using Key = std::tuple<int, std::int32_t, std::int32_t>;
    std::vector<std::map<Key, double>> seen(regions.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const morph::FaceTag& tag = mesh.tags[t];
      for (std::uint32_t v : mesh.triangles[t]) {
        if (region_of[v] == 0xffffffffu) continue;
        auto [it, inserted] =
            seen[region_of[v]].try_emplace(Key{static_cast<int>(tag.kind), tag.source, tag.line}, values[v]);
        if (!inserted && std::abs(values[v]) > std::abs(it->second)) it->second = values[v];
      }
    }
    for (std::size_t r = 0; r < regions.size(); ++r) {
      for (const auto& [key, worst] : seen[r]) {
        RegionSource s;
        s.tag.kind = static_cast<morph::PatchKind>(std::get<0>(key));
        s.tag.source = std::get<1>(key);
        s.tag.line = std::get<2>(key);
        s.worst = worst;
        regions[r].sources.push_back(s);
      }
      std::stable_sort(
          regions[r].sources.begin(), regions[r].sources.end(),
          [](const RegionSource& x, const RegionSource& y) { return std::abs(x.worst) > std::abs(y.worst); });
      if (regions[r].sources.size() > max_sources) regions[r].sources.resize(max_sources);
    }
  }
  std::stable_sort(regions.begin(), regions.end(), [](const DeviationRegion& x, const DeviationRegion& y) {
    if (std::abs(x.worst) != std::abs(y.worst)) return std::abs(x.worst) > std::abs(y.worst);
    return std::lexicographical_compare(x.location.data(), x.location.data() + 3, y.location.data(),
                                        y.location.data() + 3);
  });
  return regions;
}

}  // namespace raytest
