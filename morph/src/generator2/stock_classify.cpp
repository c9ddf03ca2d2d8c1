// SPDX-License-Identifier: Apache-2.0
// Which parts of a sweep facet lie inside a mesh stock: the facet's pieces are split where a
// stock triangle crosses them (within the triangle's edge planes, by its support), and each part
// takes the side of the last triangle it was split by or found lying against. A part that no
// triangle touches is apart from the surface, and the winding number about one of its points
// decides it (never close to one half there).
#include <morph/exceptions.h>
#include <morph/stock_mesh.h>

#include <algorithm>
#include <cmath>

namespace morph {
namespace {

using Eigen::AlignedBox3d;
using Eigen::Vector3d;

AlignedBox3d box_of(const ConvexPiece& piece) {
  AlignedBox3d box;
  for (const Vector3d& x : corners(piece)) box.extend(x);
  const double margin = 1e-7 * (1 + box.min().cwiseAbs().maxCoeff() + box.max().cwiseAbs().maxCoeff());
  box.min().array() -= margin;
  box.max().array() += margin;
  return box;
}

enum class Status { Unknown, Outside, Inside };

struct Cell {
  ConvexPiece piece;
  Status status = Status::Unknown;
};

// The side of `support` (a triangle's plane) the part `inside` (within the triangle's edge
// planes) lies against the triangle on, or Unknown when it is not against it: it has an edge
// on the plane, or lies in it exactly (the perturbation puts it on one side). `crossing` when
// the plane splits it.
Status against(const ConvexPiece& inside, const ExactPlane& support, bool& crossing) {
  crossing = false;
  for (const ExactPlane& e : inside.edges)
    if (e.rank == support.rank) return e.direction == support.direction ? Status::Inside : Status::Outside;
  const std::size_t n = inside.edges.size();
  int below = 0, above = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const int s = side_at_vertex(inside.support, inside.edges[(k + n - 1) % n], inside.edges[k], support);
    below += s < 0;
    above += s > 0;
  }
  if (below > 0 && above > 0) {
    crossing = true;
    return Status::Unknown;
  }
  for (std::size_t k = 0; k < n; ++k)
    if (limit_side_at_vertex(inside.support, inside.edges[(k + n - 1) % n], inside.edges[k], support) != 0)
      return Status::Unknown;
  return below > 0 ? Status::Inside : Status::Outside;
}

}  // namespace

double winding_number(const MeshStock& stock, const Vector3d& point) {
  // Van Oosterom and Strackee's solid angle of each triangle, summed over 4π.
  double sum = 0.0;
  for (const std::array<int, 3>& t : stock.triangles) {
    const Vector3d a = stock.vertices[t[0]] - point, b = stock.vertices[t[1]] - point,
                   c = stock.vertices[t[2]] - point;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    sum += 2.0 * std::atan2(numerator, denominator);
  }
  return sum / (4.0 * M_PI);
}

std::vector<ConvexPiece> keep_inside(const MeshStock& stock, std::vector<ConvexPiece> pieces) {
  std::vector<ConvexPiece> kept;
  if (pieces.empty()) return kept;
  AlignedBox3d reach;
  for (const ConvexPiece& p : pieces) reach.extend(box_of(p));
  std::vector<std::uint32_t> near;
  stock.tree.for_each_overlapping(reach,
                                  [&](std::size_t t) { near.push_back(static_cast<std::uint32_t>(t)); });
  std::sort(near.begin(), near.end());

  std::vector<Cell> cells, next;
  for (ConvexPiece& p : pieces) cells.push_back(Cell{std::move(p), Status::Unknown});
  std::vector<ConvexPiece> outside;
  for (std::uint32_t t : near) {
    const ConvexPiece& face = stock.faces[t];
    next.clear();
    for (Cell& cell : cells) {
      if (!box_of(cell.piece).intersects(stock.boxes[t])) {
        next.push_back(std::move(cell));
        continue;
      }
      const ConvexPiece inside = intersect(cell.piece, face.edges);
      bool crossing = false;
      const Status status = inside.empty() ? Status::Unknown : against(inside, face.support, crossing);
      if (!crossing && status == Status::Unknown) {
        next.push_back(std::move(cell));
        continue;
      }
      // The parts outside the triangle's edge planes keep what they were; the part within takes
      // the triangle's sides.
      outside.clear();
      subtract(cell.piece, face.edges, outside);
      for (ConvexPiece& o : outside) next.push_back(Cell{std::move(o), cell.status});
      if (!crossing) {
        next.push_back(Cell{inside, status});
        continue;
      }
      ConvexPiece below = clip(inside, face.support), above = clip(inside, flipped(face.support));
      if (!below.empty()) next.push_back(Cell{std::move(below), Status::Inside});
      if (!above.empty()) next.push_back(Cell{std::move(above), Status::Outside});
    }
    cells.swap(next);
  }
  for (Cell& cell : cells) {
    if (cell.status == Status::Unknown) {
      Vector3d centre = Vector3d::Zero();
      const std::vector<Vector3d> c = corners(cell.piece);
      for (const Vector3d& x : c) centre += x;
      centre /= static_cast<double>(c.size());
      const double w = winding_number(stock, centre);
      if (std::fabs(w - 0.5) < 0.25)
        throw GeometryError(
            "generator 2: a sweep facet's part apart from the mesh stock has winding number " +
            std::to_string(w));
      cell.status = w > 0.5 ? Status::Inside : Status::Outside;
    }
    if (cell.status == Status::Inside) kept.push_back(std::move(cell.piece));
  }
  return kept;
}

}  // namespace morph
