// SPDX-License-Identifier: Apache-2.0
#include "verify/view3d_surface.h"

#include <morph/parallel.h>
#include <raytest/regions.h>
#include <raytest/surface_query.h>

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <algorithm>
#include <stdexcept>
#include <vector>

namespace morphmill {

namespace {

// Double precision, as the part's own coordinates.
struct DoubleTraits : OpenMesh::DefaultTraits {
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
};
using OmMesh = OpenMesh::TriMesh_ArrayKernelT<DoubleTraits>;

// The source's connectivity in OpenMesh. Faces OpenMesh refuses (a non-manifold edge) are left
// out of the decimation; they are few and the view stays a picture of the part.
OmMesh to_openmesh(const morph::TriangleMesh& mesh) {
  OmMesh om;
  std::vector<OmMesh::VertexHandle> handles;
  handles.reserve(mesh.vertices.size());
  for (const Eigen::Vector3d& v : mesh.vertices)
    handles.push_back(om.add_vertex(OmMesh::Point(v.x(), v.y(), v.z())));
  for (const morph::Triangle& t : mesh.triangles) {
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    om.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
  }
  return om;
}

morph::TriangleMesh from_openmesh(const OmMesh& om) {
  morph::TriangleMesh mesh;
  mesh.vertices.reserve(om.n_vertices());
  for (const auto& v : om.vertices()) {
    const OmMesh::Point& p = om.point(v);
    mesh.vertices.emplace_back(p[0], p[1], p[2]);
  }
  mesh.triangles.reserve(om.n_faces());
  for (const auto& f : om.faces()) {
    morph::Triangle t{};
    int k = 0;
    for (const auto& v : f.vertices()) t[k++] = static_cast<std::uint32_t>(v.idx());
    mesh.triangles.push_back(t);
  }
  return mesh;
}

}  // namespace

ViewSurface decimated_for_view(const morph::TriangleMesh& mesh, std::size_t max_triangles) {
  if (max_triangles == 0) throw std::invalid_argument("3D view: the triangle cap must be positive");
  ViewSurface out;
  out.source_triangles = mesh.triangles.size();
  if (mesh.triangles.size() <= max_triangles) {
    out.mesh = mesh;
    return out;
  }
  OmMesh om = to_openmesh(mesh);
  OpenMesh::Decimater::DecimaterT<OmMesh> decimater(om);
  OpenMesh::Decimater::ModQuadricT<OmMesh>::Handle quadric;
  decimater.add(quadric);
  decimater.initialize();
  decimater.decimate_to_faces(0, max_triangles);
  om.garbage_collection();
  out.mesh = from_openmesh(om);
  out.decimated = true;
  if (!mesh.tags.empty()) {
    const raytest::SurfaceQuery source(mesh);
    out.mesh.tags.resize(out.mesh.triangles.size());
    morph::for_each_index(morph::ExecutionPolicy::Parallel, 0, out.mesh.triangles.size(), [&](std::size_t t) {
      const morph::Triangle& tri = out.mesh.triangles[t];
      const Eigen::Vector3d centroid =
          (out.mesh.vertices[tri[0]] + out.mesh.vertices[tri[1]] + out.mesh.vertices[tri[2]]) / 3.0;
      const raytest::ClosestPoint nearest = source.closest_point(centroid);
      if (nearest.found) out.mesh.tags[t] = mesh.tags[nearest.triangle];
    });
  }
  return out;
}

ViewSurface view_surface(const morph::TriangleMesh& mesh, std::size_t max_triangles) {
  if (mesh.triangles.size() > max_triangles) return decimated_for_view(mesh, max_triangles);
  const double diagonal = morph::bounds(mesh).diagonal().norm();
  ViewSurface out;
  out.source_triangles = mesh.triangles.size();
  out.mesh = raytest::refine_long_edges(mesh, std::max(diagonal / 150.0, 1e-9), max_triangles).mesh;
  return out;
}

}  // namespace morphmill
