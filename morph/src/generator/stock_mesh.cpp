// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/stock_mesh.h>
#include <morph/stock_polytope.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <string>

namespace morph {
namespace {

using Int = __int128;
using GridPoint = std::array<std::int64_t, 3>;

// A plane n·q <= offset on grid points q, n reduced by its gcd: equal planes compare equal.
struct GridPlane {
  std::array<Int, 3> n{};
  Int offset = 0;
  bool operator<(const GridPlane& o) const {
    return std::tie(n[0], n[1], n[2], offset) < std::tie(o.n[0], o.n[1], o.n[2], o.offset);
  }
  Int value(const GridPoint& q) const { return n[0] * q[0] + n[1] * q[1] + n[2] * q[2] - offset; }
};

Int magnitude(Int x) {
  return x < 0 ? -x : x;
}

Int gcd(Int a, Int b) {
  a = magnitude(a), b = magnitude(b);
  while (b != 0) {
    const Int r = a % b;
    a = b, b = r;
  }
  return a;
}

GridPlane plane_through(std::array<Int, 3> n, const GridPoint& q) {
  const Int g = gcd(gcd(n[0], n[1]), n[2]);
  for (Int& c : n) c /= g;
  return GridPlane{n, n[0] * q[0] + n[1] * q[1] + n[2] * q[2]};
}

// Doubles hold every integer up to 2^53 exactly.
bool fits(Int x) {
  constexpr Int limit = Int{1} << 53;
  return magnitude(x) <= limit;
}

ExactPlane exact_plane(const GridPlane& p, double grid, std::uint32_t index) {
  return ExactPlane{
      Eigen::Vector3d(static_cast<double>(p.n[0]), static_cast<double>(p.n[1]), static_cast<double>(p.n[2])),
      static_cast<double>(p.offset) * grid, stock_rank(index), -1};
}

Eigen::AlignedBox3d grown(Eigen::AlignedBox3d box) {
  const double margin = 1e-7 * (1 + box.min().cwiseAbs().maxCoeff() + box.max().cwiseAbs().maxCoeff());
  box.min().array() -= margin;
  box.max().array() += margin;
  return box;
}

// The mesh stock on the grid `out.grid`; false when a coordinate or a plane needs more bits than
// the grid allows there (a coarser grid may do).
bool build_on_grid(const TriangleMesh& mesh, const std::string& what, MeshStock& out) {
  // Vertices on the grid; those that round to one grid point become one vertex.
  std::map<GridPoint, int> index_of;
  std::vector<GridPoint> points;
  std::vector<int> vertex_of(mesh.vertices.size());
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    GridPoint q{};
    for (int a = 0; a < 3; ++a) {
      const double x = mesh.vertices[v][a] / out.grid;
      if (!std::isfinite(x))
        throw InputError("mesh stock " + what + ": vertex " + std::to_string(v) + " is not finite");
      if (!(std::fabs(x) < 0x1p40)) return false;
      q[a] = std::llround(x);
    }
    auto [it, added] = index_of.emplace(q, static_cast<int>(points.size()));
    if (added) {
      points.push_back(q);
      out.vertices.emplace_back(q[0] * out.grid, q[1] * out.grid, q[2] * out.grid);
    }
    vertex_of[v] = it->second;
  }

  // Supports: one rank per distinct exact plane (coplanar triangles share it).
  const std::size_t n = mesh.triangles.size();
  std::vector<GridPlane> support(n);
  std::map<GridPlane, std::uint32_t> plane_rank;
  std::vector<std::uint32_t> rank(n);
  for (std::size_t t = 0; t < n; ++t) {
    std::array<int, 3> tri{};
    for (int k = 0; k < 3; ++k) tri[k] = vertex_of[mesh.triangles[t][k]];
    out.triangles.push_back(tri);
    const GridPoint &a = points[tri[0]], &b = points[tri[1]], &c = points[tri[2]];
    const std::array<Int, 3> u{Int{b[0]} - a[0], Int{b[1]} - a[1], Int{b[2]} - a[2]};
    const std::array<Int, 3> w{Int{c[0]} - a[0], Int{c[1]} - a[1], Int{c[2]} - a[2]};
    const std::array<Int, 3> normal{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                    u[0] * w[1] - u[1] * w[0]};
    if (normal[0] == 0 && normal[1] == 0 && normal[2] == 0)
      throw InputError("mesh stock " + what + ": triangle " + std::to_string(t) +
                       " is degenerate on the generator's grid of " + std::to_string(out.grid) + " mm");
    support[t] = plane_through(normal, a);
    if (!fits(support[t].offset) || !fits(support[t].n[0]) || !fits(support[t].n[1]) ||
        !fits(support[t].n[2]))
      return false;
    rank[t] = plane_rank.emplace(support[t], static_cast<std::uint32_t>(plane_rank.size())).first->second;
  }
  out.planes = plane_rank.size();

  // Edges: each used exactly once each way.
  std::map<std::pair<int, int>, std::vector<std::pair<std::size_t, int>>> uses;
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = out.triangles[t][k], b = out.triangles[t][(k + 1) % 3];
      uses[{std::min(a, b), std::max(a, b)}].emplace_back(t, k);
    }
  for (const auto& [edge, list] : uses) {
    const bool ok = list.size() == 2 && out.triangles[list[0].first][list[0].second] !=
                                            out.triangles[list[1].first][list[1].second];
    if (!ok)
      throw InputError(
          "mesh stock " + what + ": not a closed, oriented 2-manifold (the edge between vertices " +
          std::to_string(edge.first) + " and " + std::to_string(edge.second) + " is used " +
          std::to_string(list.size()) + " times" + (list.size() == 2 ? ", twice the same way)" : ")"));
  }

  // Each triangle's edge planes.
  std::map<std::pair<int, int>, std::pair<GridPlane, std::uint32_t>> edge_planes;
  std::vector<std::vector<ExactPlane>> edges(n);
  for (std::size_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const int a = out.triangles[t][k], b = out.triangles[t][(k + 1) % 3];
      const GridPoint& third = points[out.triangles[t][(k + 2) % 3]];
      const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
      const auto& list = uses.at(key);
      const std::size_t other = list[0].first == t ? list[1].first : list[0].first;
      if (rank[other] != rank[t]) {
        // A crease: the neighbour's plane, turned so that this triangle is inside it.
        const Int side = support[other].value(third);
        if (side == 0)
          throw InputError("mesh stock " + what + ": triangles " + std::to_string(t) + " and " +
                           std::to_string(other) + " fold onto each other");
        const ExactPlane p = exact_plane(support[other], out.grid, rank[other]);
        edges[t].push_back(side < 0 ? p : flipped(p));
        continue;
      }
      // Coplanar neighbours: an exact plane through the edge, across the support's dominant axis.
      auto found = edge_planes.find(key);
      if (found == edge_planes.end()) {
        const GridPoint &p = points[key.first], &q = points[key.second];
        const std::array<Int, 3> d{Int{q[0]} - p[0], Int{q[1]} - p[1], Int{q[2]} - p[2]};
        int axis = 0;
        for (int i = 1; i < 3; ++i)
          if (magnitude(support[t].n[i]) > magnitude(support[t].n[axis])) axis = i;
        std::array<Int, 3> m{};  // d × e_axis
        const int i1 = (axis + 1) % 3, i2 = (axis + 2) % 3;
        m[i1] = d[i2];
        m[i2] = -d[i1];
        const GridPlane plane = plane_through(m, p);
        if (!fits(plane.offset) || !fits(plane.n[i1]) || !fits(plane.n[i2])) return false;
        found =
            edge_planes.emplace(key, std::pair{plane, static_cast<std::uint32_t>(edge_planes.size())}).first;
      }
      const GridPlane& plane = found->second.first;
      const ExactPlane p =
          exact_plane(plane, out.grid, static_cast<std::uint32_t>(out.planes + found->second.second));
      edges[t].push_back(plane.value(third) < 0 ? p : flipped(p));
    }
  out.edge_planes = edge_planes.size();

  for (const Eigen::Vector3d& v : out.vertices) out.bounds.extend(v);
  out.bounds = grown(out.bounds);
  for (std::size_t t = 0; t < n; ++t) {
    const ExactPlane s = exact_plane(support[t], out.grid, rank[t]);
    ConvexPiece face = intersect(piece_in_bounds(s, out.bounds), edges[t]);
    if (face.edges.size() != 3)
      throw InputError("mesh stock " + what + ": triangle " + std::to_string(t) +
                       " is not a triangle of its planes");
    out.faces.push_back(canonical(std::move(face)));
    Eigen::AlignedBox3d box;
    for (int v : out.triangles[t]) box.extend(out.vertices[v]);
    out.boxes.push_back(grown(box));
  }
  out.tree = AabbTree(out.boxes);
  return true;
}

}  // namespace

MeshStock mesh_stock(const TriangleMesh& mesh, double deviation, const std::string& what) {
  if (!(std::isfinite(deviation) && deviation > 0.0))
    throw InputError("mesh stock " + what + ": the deviation must be positive");
  if (mesh.triangles.empty()) throw InputError("mesh stock " + what + " has no triangles");
  // The coarsest grid: half a cell's diagonal within the deviation, grid·√3/2 <= deviation. The
  // finest that keeps every plane within 53 bits is taken, from 2^-20 mm up: a fine grid moves
  // the vertices less and leaves small triangles whole.
  const int coarsest = static_cast<int>(std::floor(std::log2(2.0 * deviation / std::sqrt(3.0))));
  for (int e = std::min(-20, coarsest); e <= coarsest; ++e) {
    MeshStock out;
    out.grid = std::ldexp(1.0, e);
    if (build_on_grid(mesh, what, out)) return out;
  }
  throw InputError("mesh stock " + what + ": its planes need more than 53 bits on every grid within " +
                   std::to_string(deviation) +
                   " mm (coordinates too large for the tolerance; move the part "
                   "nearer the origin or raise the tolerance)");
}

}  // namespace morph
