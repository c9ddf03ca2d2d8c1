// SPDX-License-Identifier: Apache-2.0
#include <morph/carved_pieces.h>

#include <morph/exceptions.h>

#include <algorithm>
#include <limits>

namespace morph {

CarvedPieces compact(const std::vector<CarvedPiece>& pieces) {
  CarvedPieces out;
  // Every plane a piece names, by (rank, direction) and where it is named; sorted, each distinct
  // one is a table entry.
  struct Named {
    std::uint64_t rank;
    int direction;
    std::uint64_t at;  // 0 for piece 0's support, then its edges, then piece 1's support, ...
  };
  std::vector<Named> named;
  std::vector<const ExactPlane*> plane_at;
  for (const CarvedPiece& p : pieces) {
    plane_at.push_back(&p.piece.support);
    for (const ExactPlane& e : p.piece.edges) plane_at.push_back(&e);
  }
  named.reserve(plane_at.size());
  for (std::uint64_t k = 0; k < plane_at.size(); ++k)
    named.push_back({plane_at[k]->rank, plane_at[k]->direction, k});
  std::sort(named.begin(), named.end(), [](const Named& a, const Named& b) {
    return a.rank < b.rank ||
           (a.rank == b.rank && (a.direction < b.direction || (a.direction == b.direction && a.at < b.at)));
  });
  std::vector<std::uint32_t> index_at(plane_at.size());
  for (std::size_t k = 0; k < named.size(); ++k) {
    if (k == 0 || named[k].rank != named[k - 1].rank || named[k].direction != named[k - 1].direction)
      out.planes.push_back(*plane_at[named[k].at]);
    index_at[named[k].at] = static_cast<std::uint32_t>(out.planes.size() - 1);
  }
  out.pieces.reserve(pieces.size());
  out.edges.reserve(plane_at.size() - pieces.size());
  std::uint64_t at = 0;
  for (const CarvedPiece& p : pieces) {
    CarvedPieces::Piece piece;
    piece.support = index_at[at++];
    piece.first_edge = out.edges.size();
    piece.edge_count = static_cast<std::uint32_t>(p.piece.edges.size());
    piece.move = p.move;
    piece.face = p.face;
    for (std::size_t k = 0; k < p.piece.edges.size(); ++k) out.edges.push_back(index_at[at++]);
    out.pieces.push_back(piece);
  }
  return out;
}

std::vector<CarvedPiece> expanded(const CarvedPieces& pieces) {
  std::vector<CarvedPiece> out;
  out.reserve(pieces.size());
  for (const CarvedPieces::Piece& p : pieces.pieces) {
    CarvedPiece piece;
    piece.piece.support = pieces.support(p);
    for (std::size_t k = 0; k < p.edge_count; ++k) piece.piece.edges.push_back(pieces.edge(p, k));
    piece.move = p.move;
    piece.face = p.face;
    out.push_back(std::move(piece));
  }
  return out;
}

CarvedPieces concatenated(std::vector<CarvedPieces>& parts, ExecutionPolicy policy) {
  std::vector<std::size_t> first_plane(parts.size() + 1, 0), first_edge(parts.size() + 1, 0),
      first_piece(parts.size() + 1, 0);
  for (std::size_t k = 0; k < parts.size(); ++k) {
    first_plane[k + 1] = first_plane[k] + parts[k].planes.size();
    first_edge[k + 1] = first_edge[k] + parts[k].edges.size();
    first_piece[k + 1] = first_piece[k] + parts[k].pieces.size();
  }
  if (first_plane.back() > std::numeric_limits<std::uint32_t>::max())
    throw LimitError("carving: more than 2^32 planes in the pieces' table");
  CarvedPieces out;
  // Storage faulted in by both threads (growing it piece by piece copied it again and again).
  resize_faulted_in(out.planes, first_plane.back(), policy);
  resize_faulted_in(out.edges, first_edge.back(), policy);
  resize_faulted_in(out.pieces, first_piece.back(), policy);
  for_each_index(policy, 0, parts.size(), [&](std::size_t k) {
    CarvedPieces& part = parts[k];
    std::copy(part.planes.begin(), part.planes.end(),
              out.planes.begin() + static_cast<std::ptrdiff_t>(first_plane[k]));
    const auto plane_shift = static_cast<std::uint32_t>(first_plane[k]);
    for (std::size_t e = 0; e < part.edges.size(); ++e)
      out.edges[first_edge[k] + e] = part.edges[e] + plane_shift;
    for (std::size_t i = 0; i < part.pieces.size(); ++i) {
      CarvedPieces::Piece p = part.pieces[i];
      p.first_edge += first_edge[k];
      p.support += plane_shift;
      out.pieces[first_piece[k] + i] = p;
    }
    std::vector<ExactPlane>().swap(part.planes);
    std::vector<std::uint32_t>().swap(part.edges);
    std::vector<CarvedPieces::Piece>().swap(part.pieces);
  });
  return out;
}

}  // namespace morph
