// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file conform.h
/// The generator's conforming step: the carved pieces (carve.h) become polygons over shared
/// vertices. A vertex is its plane triple (the perturbed arrangement is in general position, so
/// the triple names one point), hence both sides of every crease name it alike; and every vertex
/// lying on a piece's edge line strictly inside the edge is inserted into it (decided by the
/// exact predicates), so no T-junctions remain.
#include <morph/carve.h>
#include <morph/carved_pieces.h>
#include <morph/parallel.h>

#include <array>
#include <cstdint>
#include <vector>

namespace morph {

struct ConformedPolygon {
  std::vector<std::uint32_t> loop;  ///< counter-clockwise seen from outside the solid
  std::size_t corners = 0;          ///< the piece's own corners (the rest were inserted)
  std::int32_t move = -1;           ///< the sweep's move, -1 for a stock face
  std::int32_t face = 0;            ///< the stock face or the sweep's facet
};

/// A surface's vertices as triples of planes in one table of its distinct planes: a plane is
/// named by many vertices, and a triple of copies (288 bytes a vertex) was a gigabyte on cameo.nc.
struct VertexPlanes {
  std::vector<ExactPlane> planes;                     ///< one per rank, in increasing rank
  std::vector<std::array<std::uint32_t, 3>> triples;  ///< each vertex's, indices in `planes`
  std::size_t size() const { return triples.size(); }
  /// Vertex v's planes, sorted by rank (its key).
  PlaneTriple operator[](std::size_t v) const {
    const std::array<std::uint32_t, 3>& t = triples[v];
    return {{&planes[t[0]], &planes[t[1]], &planes[t[2]]}};
  }
  /// The index in `planes` of one of its planes.
  std::uint32_t index_of(const ExactPlane& plane) const {
    return static_cast<std::uint32_t>(&plane - planes.data());
  }
};

struct ConformedSurface {
  VertexPlanes vertices;
  std::vector<ConformedPolygon> polygons;
  std::size_t inserted = 0;  ///< vertices inserted into other pieces' edges
};

/// Each plane-pair line's vertices are sorted along it once; lines and pieces are independent and
/// done in parallel under `policy` (the output does not depend on it).
ConformedSurface conform(const CarvedPieces& pieces, ExecutionPolicy policy = ExecutionPolicy::Parallel);
/// The same for pieces as values (carve_box()'s).
ConformedSurface conform(const std::vector<CarvedPiece>& pieces,
                         ExecutionPolicy policy = ExecutionPolicy::Parallel);

}  // namespace morph
