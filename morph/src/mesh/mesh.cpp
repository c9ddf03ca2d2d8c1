// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/mesh.h>

#include <algorithm>

namespace morph {

const char* to_string(PatchKind kind) {
  switch (kind) {
    case PatchKind::StockFace:
      return "stock_face";
    case PatchKind::CutSurface:
      return "cut_surface";
    case PatchKind::SideSweep:
      return "side_sweep";
    case PatchKind::FrontSweep:
      return "front_sweep";
    case PatchKind::Reference:
      return "reference";
    case PatchKind::Unknown:
      break;
  }
  return "unknown";
}

void TriangleMesh::append(const TriangleMesh& other) {
  const auto offset = static_cast<std::uint32_t>(vertices.size());
  const bool keep_tags = (tags.size() == triangles.size()) && (other.tags.size() == other.triangles.size());
  const bool keep_colors =
      (colors.size() == vertices.size()) && (other.colors.size() == other.vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (const Triangle& t : other.triangles)
    triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  if (keep_tags)
    tags.insert(tags.end(), other.tags.begin(), other.tags.end());
  else
    tags.clear();
  if (keep_colors)
    colors.insert(colors.end(), other.colors.begin(), other.colors.end());
  else
    colors.clear();
  std::vector<VertexScalar> kept;
  for (VertexScalar& s : scalars) {
    if (const VertexScalar* o = other.scalar(s.name)) {
      s.values.insert(s.values.end(), o->values.begin(), o->values.end());
      kept.push_back(std::move(s));
    }
  }
  scalars = std::move(kept);
}

void TriangleMesh::validate(const std::string& what) const {
  const std::size_t n = vertices.size();
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (std::uint32_t v : triangles[t])
      if (v >= n)
        throw InputError(what + ": triangle " + std::to_string(t) + " refers to vertex " + std::to_string(v) +
                         " but there are " + std::to_string(n) + " vertices");
  if (!tags.empty() && tags.size() != triangles.size())
    throw InputError(what + ": " + std::to_string(tags.size()) + " face tags for " +
                     std::to_string(triangles.size()) + " triangles");
  if (!colors.empty() && colors.size() != n)
    throw InputError(what + ": " + std::to_string(colors.size()) + " colours for " + std::to_string(n) +
                     " vertices");
  for (const VertexScalar& s : scalars)
    if (s.values.size() != n)
      throw InputError(what + ": scalar '" + s.name + "' has " + std::to_string(s.values.size()) +
                       " values for " + std::to_string(n) + " vertices");
}

const VertexScalar* TriangleMesh::scalar(const std::string& name) const {
  for (const VertexScalar& s : scalars)
    if (s.name == name) return &s;
  return nullptr;
}

Eigen::AlignedBox3d bounds(const TriangleMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (const Eigen::Vector3d& v : mesh.vertices) box.extend(v);
  return box;
}

double surface_area(const TriangleMesh& mesh) {
  double area = 0.0;
  for (const Triangle& t : mesh.triangles) {
    const Eigen::Vector3d& a = mesh.vertices[t[0]];
    area += 0.5 * (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).norm();
  }
  return area;
}

double enclosed_volume(const TriangleMesh& mesh) {
  // Relative to the bounds' centre, so large coordinates do not cost precision.
  const Eigen::Vector3d origin = mesh.vertices.empty() ? Eigen::Vector3d(Eigen::Vector3d::Zero())
                                                       : Eigen::Vector3d(bounds(mesh).center());
  double six_volume = 0.0;
  for (const Triangle& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]] - origin;
    const Eigen::Vector3d b = mesh.vertices[t[1]] - origin;
    const Eigen::Vector3d c = mesh.vertices[t[2]] - origin;
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6.0;
}

bool zero_area(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  constexpr double kRelativeEpsilon = 1e-14;
  const double longest_squared =
      std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return (b - a).cross(c - a).norm() <= kRelativeEpsilon * longest_squared;
}

Eigen::Vector3d face_normal(const TriangleMesh& mesh, std::size_t t) {
  const Triangle& tri = mesh.triangles[t];
  const Eigen::Vector3d n =
      (mesh.vertices[tri[1]] - mesh.vertices[tri[0]]).cross(mesh.vertices[tri[2]] - mesh.vertices[tri[0]]);
  const double len = n.norm();
  return len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

}  // namespace morph
