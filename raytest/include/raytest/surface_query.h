// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file surface_query.h
/// Closest-point, signed-distance and ray queries against a triangle mesh, accelerated by Embree
/// (single precision) and refined in double precision so distances are exact for exact inputs.
#include <morph/mesh.h>

#include <cstdint>
#include <limits>
#include <memory>

namespace raytest {

/// Nearest point of the surface to a query point.
struct ClosestPoint {
  bool found = false;  ///< false when the mesh is empty or nothing lies within max_distance
  double distance = std::numeric_limits<double>::infinity();  ///< unsigned, mesh units
  Eigen::Vector3d point = Eigen::Vector3d::Zero();            ///< closest point on the surface
  std::uint32_t triangle = 0;  ///< triangle holding `point` (lowest index on ties)
};

/// First intersection of a ray with the surface.
struct RayHit {
  bool hit = false;
  double t = std::numeric_limits<double>::infinity();  ///< ray parameter (distance for a unit direction)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  std::uint32_t triangle = 0;
  double u = 0, v = 0;  ///< barycentrics of `point`: point = (1-u-v) a + u b + v c
};

/// An immutable acceleration structure over a copy of a mesh. All queries are const and
/// thread-safe. Embree errors become morph::GeometryError.
class SurfaceQuery {
 public:
  explicit SurfaceQuery(morph::TriangleMesh mesh);
  ~SurfaceQuery();
  SurfaceQuery(SurfaceQuery&&) noexcept;
  SurfaceQuery& operator=(SurfaceQuery&&) noexcept;

  const morph::TriangleMesh& mesh() const;

  /// Exact (double precision) closest point; searches only within `max_distance` (mesh units).
  ClosestPoint closest_point(const Eigen::Vector3d& p,
                             double max_distance = std::numeric_limits<double>::infinity()) const;

  /// The same result, found faster when `hint_triangle` (any triangle index, e.g. the answer for a
  /// nearby point) lies close to p: its distance bounds the search from the start.
  ClosestPoint closest_point(const Eigen::Vector3d& p, double max_distance,
                             std::uint32_t hint_triangle) const;

  /// Signed distance to the surface: negative inside, from the angle-weighted pseudo-normal of
  /// the closest feature (face, edge or vertex). Meaningful for closed, outward-wound meshes.
  /// Returns +infinity when nothing lies within `max_distance`.
  double signed_distance(const Eigen::Vector3d& p, ClosestPoint* closest = nullptr,
                         double max_distance = std::numeric_limits<double>::infinity()) const;

  /// Sign (+1 outside, -1 inside) of `p` seen from the closest point `closest` of this surface.
  /// Its pseudo-normals are built on the first call (or by prepare_sides()).
  double side(const Eigen::Vector3d& p, const ClosestPoint& closest) const;

  /// Builds the pseudo-normals side() needs now, so that many threads about to call side() do
  /// not all wait for the first of them to build them.
  void prepare_sides() const;

  /// First hit along `origin + t * direction` for t in [t_min, t_max]; `direction` need not be
  /// unit (t is then in units of its length). The hit parameter is refined in double precision
  /// against the hit triangle's plane.
  RayHit first_hit(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t_min = 0.0,
                   double t_max = std::numeric_limits<double>::infinity()) const;

  /// The nearer of the first hits along +direction and -direction within `max_distance`
  /// (`direction` is normalised here). The returned t is signed: negative for a hit along -direction.
  RayHit nearest_hit_both_ways(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                               double max_distance) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace raytest
