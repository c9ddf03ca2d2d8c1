// SPDX-License-Identifier: Apache-2.0
// Which parts of a sweep facet lie inside a mesh stock. The facet's pieces are split where a
// stock triangle crosses them (within the triangle's edge planes, by its support), so no final
// part is crossed by the surface: each is wholly inside or wholly outside. Its side is then read
// off where it touches the surface: an edge of it that lies on a triangle (both ends within the
// triangle's edge planes), or the triangle it lies in. A part that touches no triangle so is apart
// from the surface, and the winding number about one of its points decides it (never close to
// one half there).
//
// A side is never carried from a part to what is cut off it later: a triangle's edge planes at a
// crease are its neighbours' planes, and about a vertex where four or more triangles meet the
// regions they bound overlap, so a part below one triangle within its edge planes may reach
// beyond another (stress seed 103, case 1133: an octahedron's vertex, where a part cut off that
// way kept "inside" from the triangle that first split it and stood outside the stock).
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
  /// Set only where the part lies in a triangle's plane within its edge planes (on it).
  Status on_triangle = Status::Unknown;
};

// How the part `inside` (within a triangle's edge planes) meets the triangle's plane `support`.
enum class Meeting {
  Apart,     ///< all on one side, touching it at most at points
  Crossing,  ///< on both sides: the plane splits it
  Touching,  ///< an edge of it lies on the plane
  LyingIn,   ///< it lies in the plane exactly (the perturbation puts it on one side: `lying_in`)
};

Meeting meeting(const ConvexPiece& inside, const ExactPlane& support, Status& lying_in) {
  lying_in = Status::Unknown;
  const std::size_t n = inside.edges.size();
  for (const ExactPlane& e : inside.edges)
    if (e.rank == support.rank) return Meeting::Touching;
  int below = 0, above = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const int s = side_at_vertex(inside.support, inside.edges[(k + n - 1) % n], inside.edges[k], support);
    below += s < 0;
    above += s > 0;
  }
  if (below > 0 && above > 0) return Meeting::Crossing;
  for (std::size_t k = 0; k < n; ++k)
    if (limit_side_at_vertex(inside.support, inside.edges[(k + n - 1) % n], inside.edges[k], support) != 0)
      return Meeting::Apart;
  lying_in = below > 0 ? Status::Inside : Status::Outside;
  return Meeting::LyingIn;
}

// Whether the corner of `piece` where edge planes a and b meet lies within `plane` (on it counts
// when the piece's own plane there faces the same way).
bool corner_within(const ConvexPiece& piece, const ExactPlane& a, const ExactPlane& b,
                   const ExactPlane& plane) {
  for (const ExactPlane* p : {&a, &b})
    if (p->rank == plane.rank) return p->direction == plane.direction;
  return side_at_vertex(piece.support, a, b, plane) < 0;
}

// The side of the surface a part not crossed by it lies on, from an edge of it on a triangle of
// `near`: below the triangle (its plane the same way round) is inside. Unknown when no edge is.
Status side_from_an_edge(const MeshStock& stock, const std::vector<std::uint32_t>& near,
                         const ConvexPiece& piece) {
  const std::size_t n = piece.edges.size();
  for (std::size_t k = 0; k < n; ++k) {
    const ExactPlane &edge = piece.edges[k], &before = piece.edges[(k + n - 1) % n],
                     &after = piece.edges[(k + 1) % n];
    for (std::uint32_t t : near) {
      const ConvexPiece& face = stock.faces[t];
      if (face.support.rank != edge.rank) continue;
      const bool on_face = std::all_of(face.edges.begin(), face.edges.end(), [&](const ExactPlane& f) {
        return corner_within(piece, before, edge, f) && corner_within(piece, edge, after, f);
      });
      if (on_face) return edge.direction == face.support.direction ? Status::Inside : Status::Outside;
    }
  }
  return Status::Unknown;
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
      Status lying_in = Status::Unknown;
      const Meeting how = inside.empty() ? Meeting::Apart : meeting(inside, face.support, lying_in);
      if (how == Meeting::Apart) {
        next.push_back(std::move(cell));
        continue;
      }
      // The part within the triangle's edge planes is cut off: it is split by the triangle, lies
      // on it, or has an edge on it (whose ends are then within the edge planes).
      outside.clear();
      subtract(cell.piece, face.edges, outside);
      for (ConvexPiece& o : outside) next.push_back(Cell{std::move(o), cell.on_triangle});
      if (how != Meeting::Crossing) {
        next.push_back(Cell{inside, how == Meeting::LyingIn ? lying_in : cell.on_triangle});
        continue;
      }
      ConvexPiece below = clip(inside, face.support), above = clip(inside, flipped(face.support));
      if (!below.empty()) next.push_back(Cell{std::move(below), Status::Unknown});
      if (!above.empty()) next.push_back(Cell{std::move(above), Status::Unknown});
    }
    cells.swap(next);
  }
  for (Cell& cell : cells) {
    Status status = cell.on_triangle;
    if (status == Status::Unknown) status = side_from_an_edge(stock, near, cell.piece);
    if (status == Status::Unknown) {
      Vector3d centre = Vector3d::Zero();
      const std::vector<Vector3d> c = corners(cell.piece);
      for (const Vector3d& x : c) centre += x;
      centre /= static_cast<double>(c.size());
      const double w = winding_number(stock, centre);
      if (std::fabs(w - 0.5) < 0.25)
        throw GeometryError(
            "erode: a sweep facet's part apart from the mesh stock has winding number " +
            std::to_string(w));
      status = w > 0.5 ? Status::Inside : Status::Outside;
    }
    if (status == Status::Inside) kept.push_back(std::move(cell.piece));
  }
  return kept;
}

}  // namespace morph
