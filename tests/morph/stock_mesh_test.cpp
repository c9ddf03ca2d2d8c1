// SPDX-License-Identifier: Apache-2.0
// Generator 2's mesh stock: exact planes through the rounded vertices; a box given as a mesh is
// carved as the box stock is (same volume, pieces and topology); a non-convex mesh (an L) cut
// by slots has the closed-form volume; the outcome is closed, oriented and manifold.
#include <morph/erode.h>
#include <morph/exceptions.h>
#include <morph/stock_mesh.h>
#include <morph/tool.h>
#include <morph/topology.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "common/test_jobs.h"

namespace {

using Eigen::Vector3d;

// The prism y0 <= y <= y1 over a polygon of the (x, z) plane, counter-clockwise, star-shaped
// from its first vertex (its caps are fans from there).
morph::TriangleMesh prism(const std::vector<Eigen::Vector2d>& polygon, double y0, double y1) {
  morph::TriangleMesh mesh;
  const auto n = static_cast<std::uint32_t>(polygon.size());
  for (double y : {y0, y1})
    for (const Eigen::Vector2d& p : polygon) mesh.vertices.emplace_back(p.x(), y, p.y());
  for (std::uint32_t k = 1; k + 1 < n; ++k) {
    mesh.triangles.push_back({0, k, k + 1});          // y0: normal -y
    mesh.triangles.push_back({n, n + k + 1, n + k});  // y1: normal +y
  }
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t j = (k + 1) % n;
    mesh.triangles.push_back({k, n + j, j});
    mesh.triangles.push_back({k, n + k, n + j});
  }
  return mesh;
}

morph::TriangleMesh box_mesh(const Eigen::AlignedBox3d& box) {
  const Vector3d a = box.min(), b = box.max();
  return prism({{a.x(), a.z()}, {b.x(), a.z()}, {b.x(), b.z()}, {a.x(), b.z()}}, a.y(), b.y());
}

// An L: a plate 20 x 10 x 10 (x, y, z) with a wall 5 thick rising to z = 20 along x = 0.
morph::TriangleMesh l_mesh() {
  return prism({{5, 10}, {5, 20}, {0, 20}, {0, 0}, {20, 0}, {20, 10}}, 0, 10);
}

morph::Job job_of(const morph::Stock& stock, const morph::Tool& tool, const std::vector<Vector3d>& polyline,
                  double tolerance = 0.05) {
  return morphmill_test::polyline_job(stock, tool, polyline, tolerance);
}

morph::Stock mesh_stock_of(morph::TriangleMesh mesh) {
  morph::Stock s;
  s.type = morph::StockType::Mesh;
  s.mesh = std::move(mesh);
  return s;
}

morph::Stock box_stock_of(const Eigen::AlignedBox3d& box) {
  morph::Stock s;
  s.type = morph::StockType::Box;
  s.box = box;
  return s;
}

// The area of the triangles that come from sweeps (mm²).
double sweep_area(const morph::TriangleMesh& mesh) {
  double area = 0.0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    if (mesh.tags[t].kind == morph::PatchKind::StockFace) continue;
    const morph::Triangle& f = mesh.triangles[t];
    area +=
        0.5 *
        (mesh.vertices[f[1]] - mesh.vertices[f[0]]).cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]).norm();
  }
  return area;
}

struct Outcome {
  morph::ErodeResult result;
  morph::TopologyReport topology;
};

Outcome closed(const morph::Job& job, const char* what) {
  Outcome o;
  o.result = morph::erode(job);
  o.topology = morph::topology_report(o.result.mesh);
  const morph::TopologyReport& t = o.topology;
  EXPECT_TRUE(t.closed_manifold()) << what << ": " << t.boundary_edges << " boundary, "
                                   << t.non_manifold_edges << " non-manifold, " << t.inconsistent_edges
                                   << " inconsistent edges, " << t.non_manifold_vertices
                                   << " non-manifold vertices";
  EXPECT_EQ(t.degenerate_triangles, 0u) << what;
  return o;
}

TEST(StockMesh, PlanesAreExactThroughTheRoundedVertices) {
  const morph::TriangleMesh box = box_mesh(Eigen::AlignedBox3d(Vector3d(0, 0, 0), Vector3d(10, 6, 2)));
  ASSERT_GT(morph::enclosed_volume(box), 0.0);
  const morph::MeshStock stock = morph::mesh_stock(box, 0.002, "box");
  EXPECT_EQ(stock.grid, std::ldexp(1.0, -20));  // the finest: an axis-aligned box's planes are small
  EXPECT_EQ(stock.planes, 6u);                  // coplanar triangles share their support
  EXPECT_EQ(stock.edge_planes, 6u);             // each face's diagonal
  ASSERT_EQ(stock.faces.size(), 12u);
  for (std::size_t t = 0; t < 12; ++t) {
    const morph::ConvexPiece& f = stock.faces[t];
    ASSERT_EQ(f.edges.size(), 3u);
    EXPECT_EQ(f.support.direction, -1);
    // The support's plane passes exactly through the triangle's vertices; the corners are them.
    for (int v : stock.triangles[t]) EXPECT_EQ(f.support.normal.dot(stock.vertices[v]), f.support.offset);
    for (const Vector3d& c : morph::corners(f)) {
      double nearest = 1e300;
      for (int v : stock.triangles[t]) nearest = std::min(nearest, (c - stock.vertices[v]).norm());
      EXPECT_LT(nearest, 1e-12);
    }
  }
  EXPECT_NEAR(morph::winding_number(stock, Vector3d(5, 3, 1)), 1.0, 1e-12);
  EXPECT_NEAR(morph::winding_number(stock, Vector3d(5, 3, 3)), 0.0, 1e-12);

  // Vertices off the grid move by at most the deviation.
  morph::TriangleMesh off = box;
  for (Vector3d& v : off.vertices) v += Vector3d(0.0123456, -0.00077, 0.1);
  const morph::MeshStock rounded = morph::mesh_stock(off, 0.002, "off");
  for (std::size_t v = 0; v < off.vertices.size(); ++v)
    EXPECT_LE((rounded.vertices[v] - off.vertices[v]).norm(), 0.002);
}

TEST(StockMesh, RefusesMeshesThatAreNotClosedManifolds) {
  morph::TriangleMesh open = box_mesh(Eigen::AlignedBox3d(Vector3d(0, 0, 0), Vector3d(1, 1, 1)));
  open.triangles.pop_back();
  EXPECT_THROW(morph::mesh_stock(open, 0.002, "open"), morph::InputError);
  morph::TriangleMesh flat = open;
  flat.triangles.push_back({0, 0, 1});
  EXPECT_THROW(morph::mesh_stock(flat, 0.002, "flat"), morph::InputError);
  // A box 1e9 mm out still has exact planes (axis-aligned: small normals); 1e13 mm is off the grid;
  // a tilted tetrahedron of 1 m edges 1 km out needs more than 53 bits for its planes' offsets,
  // the same of 1 mm edges at the origin does not.
  auto tetra = [](const Vector3d& at, double size) {
    morph::TriangleMesh m;
    m.vertices = {at, at + size * Vector3d(1.37, 0.11, 0.23), at + size * Vector3d(0.19, 1.53, 0.07),
                  at + size * Vector3d(0.31, 0.17, 1.71)};
    m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    return m;
  };
  ASSERT_GT(morph::enclosed_volume(tetra(Vector3d::Zero(), 1.0)), 0.0);
  EXPECT_THROW(
      morph::mesh_stock(tetra(Vector3d(1e6 + 0.3, 1e6 - 0.7, 1e6 + 0.1), 987.654321), 0.002, "tetra"),
      morph::InputError);
  const morph::MeshStock small = morph::mesh_stock(tetra(Vector3d::Zero(), 1.0), 0.002, "tetra");
  EXPECT_EQ(small.faces.size(), 4u);
  // A tilted triangle's plane needs about 3·log2(size / grid) bits: a coarser grid than 2^-20,
  // at most 2^-9 (2^-9·√3/2 = 0.0017 <= 0.002 < 2^-8·√3/2).
  EXPECT_GT(small.grid, std::ldexp(1.0, -20));
  EXPECT_LE(small.grid, std::ldexp(1.0, -9));
  EXPECT_THROW(morph::mesh_stock(morph::TriangleMesh{}, 0.002, "empty"), morph::InputError);
}

TEST(StockMesh, BoxAsAMeshIsCarvedAsTheBox) {
  const Eigen::AlignedBox3d box(Vector3d(0, 0, 0), Vector3d(20, 10, 6));
  const morph::Tool ball = morph::ball_tool(1.5, 6.0);
  const std::vector<std::vector<Vector3d>> paths = {
      {Vector3d(-3, 5, 4.5), Vector3d(23, 4, 5.5)},  // a groove right across
      {Vector3d(5, 5, 2), Vector3d(15, 6, 3)},       // a cavity
      {Vector3d(4, -3, 7), Vector3d(4, 5, 4), Vector3d(16, 5, 4), Vector3d(16, 13, 7)},  // a U in the top
      {Vector3d(18.5, 8.5, 3), Vector3d(18.5, 8.5, -3)},              // a plunge through a corner
      {Vector3d(-3, 5, 6), Vector3d(23, 5, 6), Vector3d(10, 7, 5)}};  // grazing the top, then in
  for (const std::vector<Vector3d>& path : paths) {
    const Outcome as_box = closed(job_of(box_stock_of(box), ball, path), "box");
    const Outcome as_mesh = closed(job_of(mesh_stock_of(box_mesh(box)), ball, path), "box as a mesh");
    EXPECT_NEAR(as_mesh.topology.volume, as_box.topology.volume, 1e-9 * box.volume());
    EXPECT_LT(as_mesh.topology.volume, box.volume() - 1.0);
    EXPECT_EQ(as_mesh.topology.components, as_box.topology.components);
    EXPECT_EQ(as_mesh.topology.euler_characteristic, as_box.topology.euler_characteristic);
    EXPECT_NEAR(as_mesh.topology.area, as_box.topology.area, 1e-9 * as_box.topology.area);
    // The same sweep surface: the mesh's pieces are the box's, split more finely (along its
    // faces' diagonals and its triangles' edge planes).
    const double box_sweep = sweep_area(as_box.result.mesh), mesh_sweep = sweep_area(as_mesh.result.mesh);
    EXPECT_GT(box_sweep, 1.0);
    EXPECT_NEAR(mesh_sweep, box_sweep, 1e-9 * box_sweep);
  }
}

TEST(StockMesh, SlotsInANonConvexMeshHaveTheClosedFormVolume) {
  const morph::Stock l = mesh_stock_of(l_mesh());
  const double whole = 20 * 10 * 10 + 5 * 10 * 10;
  ASSERT_NEAR(morph::enclosed_volume(l.mesh), whole, 1e-9);
  const double R = 1.5, tolerance = 0.02;
  const morph::Tool flat = morph::flat_tool(R, 14.0);
  {  // Along y across the plate, 2 deep: removes 2R x 2 x 10.
    const Outcome o =
        closed(job_of(l, flat, {Vector3d(12, -4, 8), Vector3d(12, 14, 8)}, tolerance), "plate slot");
    EXPECT_EQ(o.topology.components, 1u);
    EXPECT_NEAR(o.topology.volume, whole - 2 * R * 2 * 10, tolerance * o.topology.area);
    EXPECT_LT(o.topology.volume, whole - 0.9 * 2 * R * 2 * 10);
  }
  {  // Along x through the wall's top 5 and on above the plate: removes 5 x 2R x 5 of the wall.
    const Outcome o =
        closed(job_of(l, flat, {Vector3d(-4, 5, 15), Vector3d(24, 5, 15)}, tolerance), "wall slot");
    EXPECT_EQ(o.topology.components, 1u);
    EXPECT_NEAR(o.topology.volume, whole - 5 * 2 * R * 5, tolerance * o.topology.area);
    EXPECT_LT(o.topology.volume, whole - 0.9 * 5 * 2 * R * 5);
  }
  {  // Along x with the flat bottom exactly on the plate's top (z = 10): the wall's top half goes,
     // the sweep's bottom lies in the plate's top face (a tie the perturbation decides, one way).
    const Outcome o =
        closed(job_of(l, flat, {Vector3d(-4, 5, 10), Vector3d(24, 5, 10)}, tolerance), "on the plate");
    EXPECT_EQ(o.topology.components, 1u);
    EXPECT_NEAR(o.topology.volume, whole - 5 * 2 * R * 10, tolerance * o.topology.area);
    EXPECT_LT(o.topology.volume, whole - 0.9 * 5 * 2 * R * 10);
  }
  {  // Along x at z = 8 through the wall and the plate: 2 deep in the plate, through the wall.
    const Outcome o = closed(job_of(l, flat, {Vector3d(-4, 5, 8), Vector3d(24, 5, 8)}, tolerance), "both");
    EXPECT_EQ(o.topology.components, 1u);
    EXPECT_NEAR(o.topology.volume, whole - 2 * R * 2 * 15 - 5 * 2 * R * 12, tolerance * o.topology.area);
  }
}

// The octahedron |x| + |y| + |z| <= a: four triangles meet at each vertex.
morph::TriangleMesh octahedron(double a) {
  morph::TriangleMesh mesh;
  mesh.vertices = {{a, 0, 0}, {-a, 0, 0}, {0, a, 0}, {0, -a, 0}, {0, 0, a}, {0, 0, -a}};
  for (std::uint32_t x : {0u, 1u})
    for (std::uint32_t y : {2u, 3u})
      for (std::uint32_t z : {4u, 5u}) {
        // Outward: counter-clockwise seen from the octant's side.
        const int negatives = (x == 1) + (y == 3) + (z == 5);
        const bool even = negatives % 2 == 0;
        mesh.triangles.push_back(even ? morph::Triangle{x, y, z} : morph::Triangle{x, z, y});
      }
  return mesh;
}

// A part of a sweep facet split by one triangle about a vertex where four meet, and cut off
// there by a neighbour's edge plane, kept the side of the first triangle though it stood beyond
// the opposite one, outside the stock (stress seed 103, case 1133: an open surface with 157
// intersecting pairs). A flat tool's slot right through an octahedron, its floor passing the
// two equatorial vertices 0.04 mm above: the removed volume is the octahedron's part with
// |y - y0| <= R and z >= z0, ∫ (a - z0 - |y|)² dy over the slot's width.
TEST(StockMesh, AVertexOfFourTrianglesClassifiesEachPartByTheTriangleItTouches) {
  const double a = 7.444, R = 1.878, y0 = -1.396, tolerance = 0.05;
  ASSERT_NEAR(morph::enclosed_volume(octahedron(a)), 4.0 / 3.0 * a * a * a, 1e-9);
  for (double z0 : {1.3146 - R, 0.5}) {
    const morph::Stock stock = mesh_stock_of(octahedron(a));
    const morph::Tool flat = morph::flat_tool(R, 2 * a);
    const Outcome o = closed(
        job_of(stock, flat, {Vector3d(-11.7, y0, z0), Vector3d(11.7, y0, z0)}, tolerance), "octahedron");
    EXPECT_EQ(o.topology.components, 1u);
    EXPECT_EQ(morph::fallbacks_fired(o.result.stats), 0u);
    // (b - |y|)² is a quadratic on each side of 0: Simpson's rule is exact on each.
    const double b = a - z0;
    const auto f = [&](double y) { return std::pow(std::max(0.0, b - std::abs(y)), 2); };
    const auto simpson = [&](double lo, double hi) {
      return (hi - lo) / 6 * (f(lo) + 4 * f(0.5 * (lo + hi)) + f(hi));
    };
    const double lo = y0 - R, hi = y0 + R;
    ASSERT_TRUE(lo < 0 && hi > 0 && lo > -b && hi < b);
    const double removed = simpson(lo, 0) + simpson(0, hi);
    EXPECT_NEAR(o.topology.volume, 4.0 / 3.0 * a * a * a - removed, tolerance * o.topology.area) << z0;
    EXPECT_GT(removed, 10.0);
  }
}

}  // namespace
