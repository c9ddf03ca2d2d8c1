// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/parallel.h>
#include <raytest/sampling.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <string>

namespace raytest {

std::vector<Eigen::Vector3d> angle_weighted_vertex_normals(const morph::TriangleMesh& mesh) {
  // The weighted face normals (the atan2 calls are most of the cost) in parallel; the sums in
  // triangle order, so the result does not depend on the threads.
  std::vector<std::array<Eigen::Vector3d, 3>> weighted(mesh.triangles.size());
  morph::for_each_index(morph::ExecutionPolicy::Parallel, 0, mesh.triangles.size(), [&](std::size_t t) {
    const morph::Triangle& tri = mesh.triangles[t];
    const Eigen::Vector3d n = morph::face_normal(mesh, t);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d& v0 = mesh.vertices[tri[k]];
      const Eigen::Vector3d e1 = mesh.vertices[tri[(k + 1) % 3]] - v0;
      const Eigen::Vector3d e2 = mesh.vertices[tri[(k + 2) % 3]] - v0;
      // atan2 of |cross| and dot is accurate for tiny and near-flat angles alike.
      weighted[t][k] = std::atan2(e1.cross(e2).norm(), e1.dot(e2)) * n;
    }
  });
  std::vector<Eigen::Vector3d> normals(mesh.vertices.size(), Eigen::Vector3d::Zero());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) normals[mesh.triangles[t][k]] += weighted[t][k];
  for (Eigen::Vector3d& n : normals) {
    const double length = n.norm();
    if (length > 0) n /= length;
  }
  return normals;
}

namespace {

// Uniform double in [0, 1) from the full 53-bit mantissa: std::uniform_real_distribution is
// not specified identically across standard libraries, this is.
double unit_uniform(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

// Index of the bin of `x` in the increasing cumulative sums `cumulative` (x < cumulative.back()).
std::size_t pick(const std::vector<double>& cumulative, double x) {
  const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), x);
  return std::min<std::size_t>(static_cast<std::size_t>(it - cumulative.begin()), cumulative.size() - 1);
}

void add_edge_samples(const morph::TriangleMesh& mesh, const SamplingOptions& options,
                      std::vector<SurfaceSample>& out) {
  struct HalfEdge {
    std::uint64_t key;
    std::uint32_t triangle;
  };
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const morph::Triangle& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = std::min(tri[k], tri[(k + 1) % 3]);
      const std::uint32_t b = std::max(tri[k], tri[(k + 1) % 3]);
      if (a == b) continue;
      half_edges.push_back({(std::uint64_t{a} << 32) | b, static_cast<std::uint32_t>(t)});
    }
  }
  std::sort(half_edges.begin(), half_edges.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return x.key != y.key ? x.key < y.key : x.triangle < y.triangle;
  });
  struct Edge {
    std::uint32_t a, b, triangle;
    Eigen::Vector3d normal;
  };
  std::vector<Edge> edges;
  std::vector<double> cumulative;
  double total = 0;
  for (std::size_t i = 0; i < half_edges.size();) {
    std::size_t j = i;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();
    for (; j < half_edges.size() && half_edges[j].key == half_edges[i].key; ++j)
      normal += morph::face_normal(mesh, half_edges[j].triangle);
    const auto a = static_cast<std::uint32_t>(half_edges[i].key >> 32);
    const auto b = static_cast<std::uint32_t>(half_edges[i].key & 0xffffffffu);
    const double length = (mesh.vertices[b] - mesh.vertices[a]).norm();
    if (length > 0) {
      if (normal.norm() > 0) normal.normalize();
      edges.push_back({a, b, half_edges[i].triangle, normal});
      total += length;
      cumulative.push_back(total);
    }
    i = j;
  }
  if (edges.empty()) throw morph::InputError("sample_surface: edge samples asked for a mesh without edges");
  std::mt19937_64 rng(options.seed ^ 0x9e3779b97f4a7c15ull);
  for (std::size_t s = 0; s < options.edge_samples; ++s) {
    const Edge& e = edges[pick(cumulative, unit_uniform(rng) * total)];
    const double t = unit_uniform(rng);
    SurfaceSample sample;
    sample.position = (1 - t) * mesh.vertices[e.a] + t * mesh.vertices[e.b];
    sample.normal = e.normal;
    sample.triangle = e.triangle;
    sample.kind = SampleKind::Edge;
    out.push_back(sample);
  }
}

void add_face_samples(const morph::TriangleMesh& mesh, const SamplingOptions& options,
                      std::vector<SurfaceSample>& out) {
  std::vector<double> cumulative(mesh.triangles.size());
  double total = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const morph::Triangle& tri = mesh.triangles[t];
    total += 0.5 * (mesh.vertices[tri[1]] - mesh.vertices[tri[0]])
                       .cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]])
                       .norm();
    cumulative[t] = total;
  }
  if (!(total > 0)) throw morph::InputError("sample_surface: face samples asked for a mesh of zero area");
  std::mt19937_64 rng(options.seed);
  for (std::size_t s = 0; s < options.face_samples; ++s) {
    const std::size_t t = pick(cumulative, unit_uniform(rng) * total);
    // Square-root warp: uniform by area over the triangle (Osada et al. 2002).
    const double r1 = std::sqrt(unit_uniform(rng));
    const double r2 = unit_uniform(rng);
    const morph::Triangle& tri = mesh.triangles[t];
    SurfaceSample sample;
    sample.position = (1 - r1) * mesh.vertices[tri[0]] + r1 * (1 - r2) * mesh.vertices[tri[1]] +
                      r1 * r2 * mesh.vertices[tri[2]];
    sample.normal = morph::face_normal(mesh, t);
    sample.triangle = static_cast<std::uint32_t>(t);
    sample.kind = SampleKind::Face;
    out.push_back(sample);
  }
}

}  // namespace

std::vector<SurfaceSample> sample_surface(const morph::TriangleMesh& mesh, const SamplingOptions& options) {
  mesh.validate("sample_surface");
  std::vector<SurfaceSample> out;
  out.reserve((options.vertices ? mesh.vertices.size() : 0) + options.edge_samples + options.face_samples +
              (options.centroids ? mesh.triangles.size() : 0));
  if (options.vertices) {
    const std::vector<Eigen::Vector3d> normals =
        options.vertex_normals ? angle_weighted_vertex_normals(mesh) : std::vector<Eigen::Vector3d>{};
    constexpr std::uint32_t kUnused = 0xffffffffu;
    std::vector<std::uint32_t> first_triangle(mesh.vertices.size(), kUnused);
    for (std::size_t t = mesh.triangles.size(); t-- > 0;)
      for (std::uint32_t v : mesh.triangles[t]) first_triangle[v] = static_cast<std::uint32_t>(t);
    for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
      if (first_triangle[v] == kUnused) continue;
      SurfaceSample sample;
      sample.position = mesh.vertices[v];
      sample.normal = options.vertex_normals ? normals[v] : Eigen::Vector3d::Zero();
      sample.triangle = first_triangle[v];
      sample.kind = SampleKind::Vertex;
      out.push_back(sample);
    }
  }
  if (options.edge_samples > 0) add_edge_samples(mesh, options, out);
  if (options.face_samples > 0) add_face_samples(mesh, options, out);
  if (options.centroids)
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const morph::Triangle& tri = mesh.triangles[t];
      SurfaceSample sample;
      sample.position = (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3.0;
      sample.normal = morph::face_normal(mesh, t);
      sample.triangle = static_cast<std::uint32_t>(t);
      sample.kind = SampleKind::Face;
      out.push_back(sample);
    }
  return out;
}

}  // namespace raytest
