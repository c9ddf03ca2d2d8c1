// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file stock_mesh.h
/// The generator's mesh stock as exact planes. The mesh's vertices are rounded to a grid of a power
/// of two (the finest from 2^-20 mm up to the stock's deviation budget on which this works), so
/// that each triangle's plane through its three vertices is exact in doubles (integer normal reduced by its gcd, integer offset times the
/// grid); the planes of all triangles at a vertex pass exactly through it. A triangle is a convex
/// piece of its plane bounded by three edge planes: across a crease, the neighbour's plane turned
/// so the triangle is inside it (the seam is then one plane pair, the same on both sides); between
/// coplanar neighbours, which share one support rank, an exact plane through the edge. Stock
/// planes are outward and contracting, ranked stock_rank(k) (supports first, then edge planes).
///
/// keep_inside() (stock_classify.cpp) splits a sweep facet's pieces by the stock triangles that
/// cross them and keeps those inside the stock: one exact decision per piece, shared by both
/// sides of each trimming curve (the triangle's piece minus the sweep meets the facet's piece on
/// the same plane pair, with the same perturbed predicates).
#include <morph/aabb_tree.h>
#include <morph/facet_clipping.h>
#include <morph/mesh.h>

#include <Eigen/Geometry>

#include <array>
#include <string>
#include <vector>

namespace morph {

struct MeshStock {
  double grid = 0.0;                          ///< spacing of the vertices' grid (mm, a power of two)
  std::vector<Eigen::Vector3d> vertices;      ///< rounded to the grid
  std::vector<std::array<int, 3>> triangles;  ///< outward (counter-clockwise seen from outside)
  /// Per triangle: its support plane and its three edge planes, a convex piece (the triangle).
  std::vector<ConvexPiece> faces;
  std::vector<Eigen::AlignedBox3d> boxes;  ///< per triangle, grown by a rounding margin
  AabbTree tree;                           ///< over `boxes`
  Eigen::AlignedBox3d bounds;              ///< of the vertices, grown by a rounding margin
  std::size_t planes = 0;                  ///< distinct supports
  std::size_t edge_planes = 0;             ///< planes through edges between coplanar triangles
};

/// The mesh stock of `mesh` (closed, outward, each edge used once each way) within `deviation`
/// (mm): vertices rounded to the finest power-of-two grid from 2^-20 mm on which every plane is
/// exact in doubles, at most the one with half its cell's diagonal within `deviation`.
/// `what` names the mesh in messages. Throws InputError when the mesh is not a closed 2-manifold,
/// when a triangle becomes degenerate on the grid, or when an exact plane needs more than 53 bits
/// (coordinates too large for the deviation).
MeshStock mesh_stock(const TriangleMesh& mesh, double deviation, const std::string& what);

/// `pieces` (of one sweep facet, one support) split by the stock triangles crossing them, and
/// of the parts those inside the stock. A part next to a triangle is decided by the side of that
/// triangle's plane it lies on (exact, perturbed); a part next to none by the winding number of
/// the stock about one of its points (it is apart from the surface). Deterministic.
std::vector<ConvexPiece> keep_inside(const MeshStock& stock, std::vector<ConvexPiece> pieces);

/// The generalized winding number of the stock about `point` (1 inside, 0 outside), in doubles.
double winding_number(const MeshStock& stock, const Eigen::Vector3d& point);

}  // namespace morph
