// SPDX-License-Identifier: Apache-2.0
// Cross-check: morph's topology report (plain index arithmetic) against OpenMesh's half-edge view
// of the same mesh.
//
// OpenMesh's VectorT leaves its coordinates uninitialised by design, and GCC's -Wmaybe-uninitialized
// fires inside std::vector when OpenMesh's property containers grow; the warning is about the
// library's header, reported where it is inlined, so it is silenced for this file only.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <gtest/gtest.h>
#include <morph/topology.h>
#include <morphmill/mesh_io.h>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <queue>
#include <string>

#include "common/test_meshes.h"

namespace {

using OmMesh = OpenMesh::TriMesh_ArrayKernelT<>;

struct OpenMeshView {
  std::size_t refused_faces = 0;  // faces the half-edge structure cannot hold
  std::size_t vertices = 0, edges = 0, faces = 0, boundary_edges = 0, non_manifold_vertices = 0,
              components = 0;
};

OpenMeshView openmesh_view(const morph::TriangleMesh& mesh) {
  OmMesh om;
  for (const Eigen::Vector3d& p : mesh.vertices)
    om.add_vertex(OmMesh::Point(float(p.x()), float(p.y()), float(p.z())));
  OpenMeshView view;
  ::omerr().disable();  // OpenMesh reports each refused face on stderr; the count is what matters
  for (const morph::Triangle& t : mesh.triangles) {
    const OpenMesh::FaceHandle fh =
        om.add_face(OpenMesh::VertexHandle(int(t[0])), OpenMesh::VertexHandle(int(t[1])),
                    OpenMesh::VertexHandle(int(t[2])));
    if (!fh.is_valid()) ++view.refused_faces;
  }
  ::omerr().enable();
  for (const OpenMesh::VertexHandle vh : om.vertices()) {
    if (om.is_isolated(vh)) continue;
    ++view.vertices;
    if (!om.is_manifold(vh)) ++view.non_manifold_vertices;
  }
  view.edges = om.n_edges();
  view.faces = om.n_faces();
  for (const OpenMesh::EdgeHandle eh : om.edges())
    if (om.is_boundary(eh)) ++view.boundary_edges;
  // Components by walking face neighbours across edges.
  std::vector<char> seen(om.n_faces(), 0);
  for (const OpenMesh::FaceHandle start : om.faces()) {
    if (seen[start.idx()]) continue;
    ++view.components;
    std::queue<OpenMesh::FaceHandle> queue;
    queue.push(start);
    seen[start.idx()] = 1;
    while (!queue.empty()) {
      const OpenMesh::FaceHandle f = queue.front();
      queue.pop();
      for (const OpenMesh::FaceHandle g : om.ff_range(f))
        if (!seen[g.idx()]) seen[g.idx()] = 1, queue.push(g);
    }
  }
  return view;
}

void expect_agreement(const morph::TriangleMesh& mesh) {
  const morph::TopologyReport report = morph::topology_report(mesh);
  const OpenMeshView view = openmesh_view(mesh);
  ASSERT_EQ(view.refused_faces, 0u);
  EXPECT_EQ(report.vertices, view.vertices);
  EXPECT_EQ(report.edges, view.edges);
  EXPECT_EQ(report.triangles, view.faces);
  EXPECT_EQ(report.boundary_edges, view.boundary_edges);
  EXPECT_EQ(report.non_manifold_vertices, view.non_manifold_vertices);
  EXPECT_EQ(report.components, view.components);
  EXPECT_EQ(report.euler_characteristic, long(view.vertices) - long(view.edges) + long(view.faces));
  EXPECT_EQ(report.non_manifold_edges, 0u);
  EXPECT_EQ(report.inconsistent_edges, 0u);
}

TEST(TopologyVsOpenMesh, ManifoldMeshesAgree) {
  using morphmill_test::box;
  {
    SCOPED_TRACE("cube");
    expect_agreement(box({0, 0, 0}, {1, 2, 3}));
  }
  {
    SCOPED_TRACE("two cubes");
    morph::TriangleMesh two = box({0, 0, 0}, {1, 1, 1});
    two.append(box({2, 0, 0}, {3, 1, 1}));
    expect_agreement(two);
  }
  {
    SCOPED_TRACE("torus");
    expect_agreement(morphmill_test::torus(4, 1, 30, 12));
  }
  {
    SCOPED_TRACE("open box");
    morph::TriangleMesh open = box({0, 0, 0}, {1, 1, 1});
    open.triangles.erase(open.triangles.begin() + 2, open.triangles.begin() + 4);
    expect_agreement(open);
  }
  {
    SCOPED_TRACE("bow tie");
    expect_agreement(morphmill_test::bow_tie());  // OpenMesh holds it: a vertex with two gaps
  }
  for (const char* name : {"meshes/cube.stl", "meshes/tetra.obj", "meshes/block.stl"}) {
    SCOPED_TRACE(name);
    expect_agreement(morphmill::read_mesh(std::string(MORPHMILL_TEST_DATA) + "/" + name));
  }
}

TEST(TopologyVsOpenMesh, WhatOpenMeshRefusesIsWhatTheReportFlags) {
  // A half-edge structure cannot hold an edge with three faces or two faces running the same way:
  // OpenMesh refuses exactly the face that makes them.
  const morph::TriangleMesh fin = morphmill_test::fin();
  EXPECT_EQ(openmesh_view(fin).refused_faces, 1u);
  EXPECT_EQ(morph::topology_report(fin).non_manifold_edges, 1u);

  morph::TriangleMesh flipped = morphmill_test::box({0, 0, 0}, {1, 1, 1});
  std::swap(flipped.triangles.back()[1], flipped.triangles.back()[2]);
  EXPECT_EQ(openmesh_view(flipped).refused_faces, 1u);
  EXPECT_EQ(morph::topology_report(flipped).inconsistent_edges, 3u);

  // OpenMesh holds a non-manifold vertex only on a boundary (the bow tie above); two closed cubes
  // sharing a corner cannot be built, and the report flags exactly that vertex.
  morph::TriangleMesh cubes = morphmill_test::box({0, 0, 0}, {1, 1, 1});
  const morph::TriangleMesh other = morphmill_test::box({1, 1, 1}, {2, 2, 2});
  for (std::size_t i = 1; i < 8; ++i) cubes.vertices.push_back(other.vertices[i]);
  for (const morph::Triangle& t : other.triangles) {
    morph::Triangle w;
    for (int k = 0; k < 3; ++k) w[k] = t[k] == 0 ? 7 : t[k] + 7;
    cubes.triangles.push_back(w);
  }
  EXPECT_GT(openmesh_view(cubes).refused_faces, 0u);
  const morph::TopologyReport report = morph::topology_report(cubes);
  EXPECT_EQ(report.non_manifold_vertices, 1u);
  EXPECT_EQ(report.non_manifold_edges, 0u);
  EXPECT_EQ(report.boundary_edges, 0u);
}

}  // namespace
