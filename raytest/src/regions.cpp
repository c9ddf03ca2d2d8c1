// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <raytest/regions.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>

namespace raytest {

namespace {

std::size_t edge_divisions(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double max_edge) {
  const double n = std::ceil((a - b).norm() / max_edge);
  return n >= 1 && std::isfinite(n) ? static_cast<std::size_t>(std::min(n, 4096.0)) : 1;
}

// Divisions of a triangle's interior: those of its longest edge.
std::size_t divisions(const morph::TriangleMesh& mesh, const morph::Triangle& tri, double max_edge) {
  std::size_t n = 1;
  for (int e = 0; e < 3; ++e)
    n = std::max(n, edge_divisions(mesh.vertices[tri[e]], mesh.vertices[tri[(e + 1) % 3]], max_edge));
  return n;
}

// Union-find over vertex indices.
struct Components {
  std::vector<std::uint32_t> parent;
  explicit Components(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

}  // namespace

RefinedMesh refine_long_edges(const morph::TriangleMesh& mesh, double max_edge, std::size_t max_triangles) {
  if (!(max_edge > 0)) throw morph::InputError("refine_long_edges: max_edge must be positive");
  RefinedMesh out;
  // Grow the edge length until the triangle budget holds (n^2 triangles per parent).
  for (int attempt = 0; attempt < 64; ++attempt) {
    std::size_t total = 0;
    for (const auto& tri : mesh.triangles) {
      const std::size_t n = divisions(mesh, tri, max_edge);
      total += n * n;
    }
    if (total <= std::max(max_triangles, mesh.triangle_count())) break;
    max_edge *= std::sqrt(static_cast<double>(total) / static_cast<double>(max_triangles)) * 1.01;
  }
  out.max_edge = max_edge;
  morph::TriangleMesh& refined = out.mesh;
  refined.vertices = mesh.vertices;
  const bool tagged = mesh.tags.size() == mesh.triangles.size();
  // Each edge is split into its own number of pieces, the same seen from both of its triangles, so
  // the result stays conforming (no T-junctions): a triangle's lattice point at fraction i/n of an
  // edge snaps to the nearest of the edge's own points (monotone, so no triangle flips; the ones
  // that collapse are dropped).
  std::map<std::tuple<std::uint32_t, std::uint32_t, std::size_t>, std::uint32_t> points_on_edges;
  auto edge_point = [&](std::uint32_t a, std::uint32_t b, std::size_t i, std::size_t n) -> std::uint32_t {
    if (i == 0) return a;
    if (i == n) return b;
    if (a > b) std::swap(a, b), i = n - i;
    const std::size_t edge_n = edge_divisions(mesh.vertices[a], mesh.vertices[b], max_edge);
    const auto k = static_cast<std::size_t>(
        std::llround(static_cast<double>(i) * static_cast<double>(edge_n) / static_cast<double>(n)));
    if (k == 0) return a;
    if (k == edge_n) return b;
    const std::size_t n_ = edge_n;
    auto [it, inserted] = points_on_edges.try_emplace({a, b, k}, 0u);
    if (inserted) {
      it->second = static_cast<std::uint32_t>(refined.vertices.size());
      const double t = static_cast<double>(k) / static_cast<double>(n_);
      refined.vertices.push_back((1 - t) * mesh.vertices[a] + t * mesh.vertices[b]);
    }
    return it->second;
  };
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto [a, b, c] = mesh.triangles[t];
    const std::size_t n = divisions(mesh, mesh.triangles[t], max_edge);
    auto emit = [&](std::uint32_t x, std::uint32_t y, std::uint32_t z) {
      if (x == y || y == z || z == x) return;  // collapsed by snapping to a coarser edge
      refined.triangles.push_back({x, y, z});
      out.parent.push_back(static_cast<std::uint32_t>(t));
      if (tagged) refined.tags.push_back(mesh.tags[t]);
    };
    if (n == 1) {
      emit(a, b, c);
      continue;
    }
    // Lattice point (i, j): a + i/n (b - a) + j/n (c - a), i + j <= n.
    std::vector<std::uint32_t> lattice((n + 1) * (n + 2) / 2);
    auto at = [&](std::size_t i, std::size_t j) -> std::uint32_t& {
      return lattice[j * (2 * n + 3 - j) / 2 + i];
    };
    for (std::size_t j = 0; j <= n; ++j)
      for (std::size_t i = 0; i + j <= n; ++i) {
        if (j == 0) {
          at(i, j) = edge_point(a, b, i, n);
        } else if (i == 0) {
          at(i, j) = edge_point(a, c, j, n);
        } else if (i + j == n) {
          at(i, j) = edge_point(b, c, j, n);
        } else {
          at(i, j) = static_cast<std::uint32_t>(refined.vertices.size());
          const double u = static_cast<double>(i) / static_cast<double>(n);
          const double v = static_cast<double>(j) / static_cast<double>(n);
          refined.vertices.push_back(mesh.vertices[a] + u * (mesh.vertices[b] - mesh.vertices[a]) +
                                     v * (mesh.vertices[c] - mesh.vertices[a]));
        }
      }
    for (std::size_t j = 0; j < n; ++j)
      for (std::size_t i = 0; i + j < n; ++i) {
        emit(at(i, j), at(i + 1, j), at(i, j + 1));
        if (i + j + 1 < n) emit(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
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
  Components components(n);
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
