// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file carved_pieces.h
/// The carving's pieces (carve.h) with their planes in one table: a plane that many pieces name
/// (a sweep facet's support in each of its pieces, the edge two neighbouring pieces share) is
/// held once. A piece's planes as copies were some 650 bytes a piece, 1.4 GB on cameo.nc.
#include <morph/carve.h>
#include <morph/parallel.h>

#include <cstdint>
#include <vector>

namespace morph {

struct CarvedPieces {
  struct Piece {
    std::uint64_t first_edge = 0;  ///< its edges' planes are edges[first_edge, first_edge + edge_count)
    std::uint32_t edge_count = 0;
    std::uint32_t support = 0;  ///< index in `planes`
    std::int32_t move = -1;     ///< as CarvedPiece
    std::int32_t face = 0;
    bool faces_out() const { return move < 0; }
  };
  /// Each distinct oriented plane once (rank and direction; a plane and its flipped() are two).
  std::vector<ExactPlane> planes;
  std::vector<std::uint32_t> edges;  ///< every piece's edges' planes (indices in `planes`), in order
  std::vector<Piece> pieces;

  std::size_t size() const { return pieces.size(); }
  const ExactPlane& support(const Piece& p) const { return planes[p.support]; }
  const ExactPlane& edge(const Piece& p, std::size_t k) const { return planes[edges[p.first_edge + k]]; }
};

/// The pieces with their planes in a table, in the same order (the table in increasing rank).
CarvedPieces compact(const std::vector<CarvedPiece>& pieces);

/// The pieces as CarvedPiece values again (tests compare them with carve_box()'s).
std::vector<CarvedPiece> expanded(const CarvedPieces& pieces);

/// The parts one after another (their tables too: a plane may be in several), each part's pieces
/// in order; moved out of `parts` in parallel under `policy`.
CarvedPieces concatenated(std::vector<CarvedPieces>& parts, ExecutionPolicy policy);

}  // namespace morph
