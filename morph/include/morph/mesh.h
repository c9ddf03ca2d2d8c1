// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file mesh.h
/// The exchange type between morph, vdb_ref and raytest: a plain indexed triangle mesh with a
/// provenance tag on every face and optional per-vertex scalars and colours.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace morph {

/// What produced a face.
enum class PatchKind : std::uint8_t {
  Unknown = 0,
  StockFace = 1,   ///< a face of the stock the tool never reached
  CutSurface = 2,  ///< a stock face trimmed along the erosion contour
  SideSweep = 3,   ///< the arches swept perpendicular to a move
  FrontSweep = 4,  ///< the caps (hemispheres) at path ends and direction changes
  Reference = 5,   ///< a face of the level-set reference (source = nearest move)
};

/// Short lower-case name of a patch kind ("side_sweep", ...).
const char* to_string(PatchKind kind);

/// Provenance of one face. `source` is the stock face index for StockFace/CutSurface and the
/// global move index (Job::move(i)) for sweeps; `line` is the G-code line of that move, 0 if none.
struct FaceTag {
  PatchKind kind = PatchKind::Unknown;
  std::int32_t source = -1;
  std::int32_t line = 0;
  friend bool operator==(const FaceTag& a, const FaceTag& b) {
    return a.kind == b.kind && a.source == b.source && a.line == b.line;
  }
};

using Triangle = std::array<std::uint32_t, 3>;
using Color = std::array<std::uint8_t, 3>;

/// A named per-vertex scalar (for example a deviation in job units).
struct VertexScalar {
  std::string name;
  std::vector<double> values;  ///< one per vertex
};

/// A value-type indexed triangle mesh. Triangles wind counter-clockwise seen from outside.
/// `tags` is empty or has one entry per triangle; `colors` is empty or has one per vertex.
struct TriangleMesh {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<Triangle> triangles;
  std::vector<FaceTag> tags;
  std::vector<VertexScalar> scalars;
  std::vector<Color> colors;

  std::size_t vertex_count() const { return vertices.size(); }
  std::size_t triangle_count() const { return triangles.size(); }
  bool empty() const { return triangles.empty(); }

  /// Appends `other`, offsetting its indices. Tags, scalars and colours are kept where both have them.
  void append(const TriangleMesh& other);
  /// Throws InputError when an index is out of range or a per-element array has the wrong size.
  void validate(const std::string& what) const;
  /// Pointer to the named scalar, nullptr if absent.
  const VertexScalar* scalar(const std::string& name) const;
};

/// Axis-aligned bounds of the vertices (empty box for an empty mesh).
Eigen::AlignedBox3d bounds(const TriangleMesh& mesh);
/// Sum of the triangle areas.
double surface_area(const TriangleMesh& mesh);
/// Signed enclosed volume by the divergence theorem; positive for a closed outward-wound mesh.
double enclosed_volume(const TriangleMesh& mesh);
/// Unit normal of triangle t (zero vector for a degenerate one).
Eigen::Vector3d face_normal(const TriangleMesh& mesh, std::size_t t);
/// Zero area relative to the triangle's size: |(b - a) x (c - a)| <= 1e-14 * longest edge^2, so
/// that a sliver whose third corner lies on the opposite edge up to rounding counts as degenerate
/// (topology_report()'s degenerate triangles; the generator's fans and rounding avoid them).
bool zero_area(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace morph
