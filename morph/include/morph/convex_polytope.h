// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file convex_polytope.h
/// A convex polytope as the generator holds it: shared vertices and planar convex facets, each a
/// loop of vertex indices turning counter-clockwise seen from outside, with its outward unit
/// normal and offset (the facet's plane is normal·x = offset; the polytope is where every
/// normal·x <= offset). Tool polytopes and sweep polytopes (tool ⊕ segment) are both of this
/// kind. Lengths in job units.
#include <morph/quantize.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

namespace morph {

struct PolytopeFacet {
  std::vector<int> loop;                             ///< vertex indices, counter-clockwise seen from outside
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< outward, unit
  double offset = 0.0;                               ///< normal·x = offset on the facet's plane
  /// The plane exactly, when the vertices are on a grid (quantize.h); normal and offset above
  /// are then its rounded look.
  IntegerPlane exact;
};

struct ConvexPolytope {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<PolytopeFacet> facets;

  /// Enclosed volume (cubic units), by the divergence theorem over the facets.
  double volume() const;
  /// Surface area (square units).
  double area() const;
  /// Area of the orthogonal projection onto the plane normal to the unit vector `u` (Cauchy:
  /// half the sum over facets of area·|normal·u|).
  double projected_area(const Eigen::Vector3d& u) const;
  /// Largest normal·p - offset over the facets: negative strictly inside, positive outside (a
  /// lower bound of the distance there), and minus the distance to the boundary inside.
  double plane_value(const Eigen::Vector3d& p) const;
  Eigen::AlignedBox3d bounds() const;
  /// The same polytope moved by `shift` (the facets' exact planes kept when `shift` is on their
  /// grid, else dropped).
  ConvexPolytope translated(const Eigen::Vector3d& shift) const;
  /// Number of directed facet edges without their reverse in another facet, plus those used
  /// twice: 0 for a closed, oriented surface.
  std::size_t unmatched_edges() const;
};

/// Area vector (area times unit normal, by Newell's method) of a planar loop of points.
Eigen::Vector3d loop_area_vector(const std::vector<Eigen::Vector3d>& vertices, const std::vector<int>& loop);

/// Unsigned Euclidean distance from `p` to the boundary of the polytope (exact: the nearest
/// point of the facet polygons, each fanned into triangles).
double boundary_distance(const ConvexPolytope& polytope, const Eigen::Vector3d& p);

}  // namespace morph
