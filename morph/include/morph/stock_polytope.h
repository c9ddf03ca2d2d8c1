// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file stock_polytope.h
/// The generator's stock as exact planes: the box is its six planes, a cylinder a prism of
/// N side planes and its two end planes that straddles the exact cylinder within a deviation
/// budget (as the tool polytope straddles the tool: the planes are the exact object, their
/// doubles taken as exact rationals; the corners are derived). Every stock plane is outward,
/// contracting and ranked stock_rank(k) in the order of `planes`, so the carving treats a prism
/// face exactly as a box face. A mesh stock is its triangles (stock_mesh.h).
#include <morph/facet_clipping.h>
#include <morph/stock.h>
#include <morph/stock_mesh.h>

#include <Eigen/Geometry>

#include <memory>
#include <vector>

namespace morph {

/// The generator's stock: a convex one is the intersection of the halfspaces of `planes`; a mesh
/// stock has no `planes` and its triangles in `mesh`.
struct StockPolytope {
  std::vector<ExactPlane> planes;  ///< outward, contracting, ranked stock_rank(0..n-1)
  /// Contains the stock; for a box it is the box itself (mm).
  Eigen::AlignedBox3d bounds;
  bool box = false;                       ///< the six planes of box_planes(bounds), in that order
  std::shared_ptr<const MeshStock> mesh;  ///< a mesh stock, or none
};

/// The box's six planes (box_planes() order) and the box as bounds.
StockPolytope box_stock_polytope(const Eigen::AlignedBox3d& box);

/// Number of side planes of the prism about a cylinder of `radius` (mm) whose faces and edges
/// both stay within `deviation` (mm) of the exact side: r·tan²(π/2N) ≤ deviation, the least
/// multiple of 8 that does it (the sides' normals are then exactly symmetric about the axes).
int cylinder_sides(double radius, double deviation);

/// The prism about the cylinder of `stock` (StockType::Cylinder): cylinder_sides() side planes
/// at apothem a and edges at radius R with (R + a)/2 = radius, so every point of its side lies
/// within `deviation` of the exact side (mm); the bottom plane, then the top, then the sides in
/// counter-clockwise order about the axis. Throws InputError for a radius or height that is not
/// positive and finite.
StockPolytope cylinder_stock_polytope(const Stock& stock, double deviation);

/// The polytope of a convex stock (box or cylinder) within `deviation` (mm; the box is exact).
/// Throws InputError for a mesh stock.
StockPolytope convex_stock_polytope(const Stock& stock, double deviation);

/// The generator's stock of any type within `deviation` (mm): convex_stock_polytope(), or the
/// mesh_stock() of a mesh (its vertices rounded to a grid within the deviation).
StockPolytope generator2_stock(const Stock& stock, double deviation);

/// The number of stock faces (planes of a convex stock, triangles of a mesh) and face f as a
/// convex piece bounded by stock planes.
std::size_t stock_face_count(const StockPolytope& stock);
ConvexPiece stock_face(const StockPolytope& stock, std::size_t f);

/// `support`'s plane within the stock polytope, as a convex piece whose edges are stock planes;
/// empty when they miss. For a box, piece_in_box(); for a mesh, piece_in_bounds() (the parts
/// outside the mesh are told by keep_inside()).
ConvexPiece piece_in_stock(const ExactPlane& support, const StockPolytope& stock);

/// `support`'s plane within a box around `bounds` whose six planes lie well outside it (ranks
/// after every stock plane and before every sweep): a bounded piece to clip from.
ConvexPiece piece_in_bounds(const ExactPlane& support, const Eigen::AlignedBox3d& bounds);

}  // namespace morph
