// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <morph/stock_polytope.h>

#include <algorithm>
#include <cmath>

#include <string>
#include <vector>

namespace morph {
namespace {

// Ranks for the helper box a piece starts from: after every stock plane, before every sweep. Its
// planes lie strictly outside the polytope, so no piece keeps one of them.
constexpr std::uint32_t kHelperRank = 0xFFFFFF00u;

std::array<ExactPlane, 6> helper_box(const Eigen::AlignedBox3d& bounds) {
  // Grown by a tenth of its size (and a millimetre): far from every stock plane.
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(1.0) + 0.1 * bounds.sizes();
  std::array<ExactPlane, 6> planes =
      box_planes(Eigen::AlignedBox3d(bounds.min() - margin, bounds.max() + margin));
  for (std::uint32_t k = 0; k < 6; ++k) planes[k].rank = stock_rank(kHelperRank + k);
  return planes;
}

bool finite_positive(double x) {
  return std::isfinite(x) && x > 0.0;
}

}  // namespace

StockPolytope box_stock_polytope(const Eigen::AlignedBox3d& box) {
  StockPolytope out;
  const std::array<ExactPlane, 6> planes = box_planes(box);
  out.planes.assign(planes.begin(), planes.end());
  out.bounds = box;
  out.box = true;
  return out;
}

int cylinder_sides(double radius, double deviation) {
  if (!finite_positive(radius) || !finite_positive(deviation))
    throw InputError("cylinder stock: the radius and the deviation must be positive, got " +
                     std::to_string(radius) + " and " + std::to_string(deviation));
  // r·tan²(π/2N) ≤ deviation  ⇔  N ≥ π / (2·atan(√(deviation/r))); a multiple of 8 (side_directions).
  const double n = std::ceil(M_PI / (2.0 * std::atan(std::sqrt(deviation / radius))) / 8.0) * 8.0;
  if (!(n <= 1e6)) throw InputError("cylinder stock: the deviation is too small for the radius");
  return std::max(8, static_cast<int>(n));
}

namespace {

// The side normals' directions at angles 2πk/N (N a multiple of 8): the first octant computed,
// the rest its exact images under the square's symmetries (mirrors in the diagonal, quarter
// turns), so the prism is as symmetric about the axes as the tool polytope's rings are. With
// rounded angles, a prism edge meant to lie on an axis missed it by 1e-15, and a pass along that
// axis, whose tool edges lie on it exactly, met it in a cluster of exact points 1.3e-14 apart
// (stress seed 103, case 498: one edge collapsed by the output rounding).
std::vector<Eigen::Vector2d> side_directions(int sides) {
  const int eighth = sides / 8, quarter = sides / 4;
  std::vector<Eigen::Vector2d> d(static_cast<std::size_t>(sides));
  for (int k = 0; k < eighth; ++k) {
    const double angle = 2.0 * M_PI * k / sides;
    d[k] = {std::cos(angle), std::sin(angle)};
  }
  d[eighth] = Eigen::Vector2d::Constant(std::sqrt(0.5));
  for (int k = eighth + 1; k <= quarter; ++k) d[k] = {d[quarter - k].y(), d[quarter - k].x()};
  for (int k = quarter + 1; k < sides; ++k) d[k] = {-d[k - quarter].y(), d[k - quarter].x()};
  return d;
}

}  // namespace

StockPolytope cylinder_stock_polytope(const Stock& stock, double deviation) {
  if (!finite_positive(stock.height) || !finite_positive(stock.radius))
    throw InputError("cylinder stock: the radius and the height must be positive, got " +
                     std::to_string(stock.radius) + " and " + std::to_string(stock.height));
  const Eigen::Vector3d axis = stock.axis.normalized();
  const int sides = cylinder_sides(stock.radius, deviation);
  const double half = M_PI / sides;
  const double outer = 2.0 * stock.radius / (1.0 + std::cos(half));  // edges
  const double apothem = outer * std::cos(half);                     // faces
  // An axis along a coordinate axis gives side normals with exact zeros there, so the side planes
  // are exactly perpendicular to the end planes.
  Eigen::Vector3d u = Eigen::Vector3d::UnitX(), w = Eigen::Vector3d::UnitY();
  if (axis != Eigen::Vector3d::UnitZ()) {
    u = axis.unitOrthogonal();
    w = axis.cross(u);
  }
  StockPolytope out;
  auto add = [&](const Eigen::Vector3d& normal, double offset) {
    out.planes.push_back(
        ExactPlane{normal, offset, stock_rank(static_cast<std::uint32_t>(out.planes.size())), -1});
  };
  const Eigen::Vector3d top = stock.base + stock.height * axis;
  add(-axis, -axis.dot(stock.base));
  add(axis, axis.dot(top));
  const std::vector<Eigen::Vector2d> directions = side_directions(sides);
  for (int k = 0; k < sides; ++k) {
    const double angle = 2.0 * half * k;
    const Eigen::Vector3d normal = directions[k].x() * u + directions[k].y() * w;
    add(normal, normal.dot(stock.base) + apothem);
    // The prism's edges at this face's counter-clockwise end, at both ends of the axis.
    const Eigen::Vector3d radial = std::cos(angle + half) * u + std::sin(angle + half) * w;
    out.bounds.extend(stock.base + outer * radial);
    out.bounds.extend(top + outer * radial);
  }
  // The corners above are rounded; grown so that the bounds contain the exact polytope.
  const double margin =
      1e-9 * (1.0 + out.bounds.min().cwiseAbs().maxCoeff() + out.bounds.max().cwiseAbs().maxCoeff());
  out.bounds.min().array() -= margin;
  out.bounds.max().array() += margin;
  return out;
}

StockPolytope convex_stock_polytope(const Stock& stock, double deviation) {
  switch (stock.type) {
    case StockType::Box:
      return box_stock_polytope(stock.box);
    case StockType::Cylinder:
      return cylinder_stock_polytope(stock, deviation);
    case StockType::Mesh:
      break;
  }
  throw InputError("erode: a mesh stock is not a convex polytope");
}

StockPolytope generator2_stock(const Stock& stock, double deviation) {
  if (stock.type != StockType::Mesh) return convex_stock_polytope(stock, deviation);
  StockPolytope out;
  out.mesh = std::make_shared<const MeshStock>(
      mesh_stock(stock.mesh, deviation, stock.mesh_path.empty() ? "(in memory)" : stock.mesh_path));
  out.bounds = out.mesh->bounds;
  return out;
}

std::size_t stock_face_count(const StockPolytope& stock) {
  return stock.mesh ? stock.mesh->faces.size() : stock.planes.size();
}

ConvexPiece stock_face(const StockPolytope& stock, std::size_t f) {
  return stock.mesh ? stock.mesh->faces[f] : piece_in_stock(stock.planes[f], stock);
}

ConvexPiece piece_in_bounds(const ExactPlane& support, const Eigen::AlignedBox3d& bounds) {
  return piece_in_box(support, helper_box(bounds));
}

ConvexPiece piece_in_stock(const ExactPlane& support, const StockPolytope& stock) {
  if (stock.box) {
    std::array<ExactPlane, 6> box;
    std::copy(stock.planes.begin(), stock.planes.end(), box.begin());
    return piece_in_box(support, box);
  }
  return intersect(piece_in_box(support, helper_box(stock.bounds)), stock.planes);
}

}  // namespace morph
