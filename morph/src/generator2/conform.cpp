// SPDX-License-Identifier: Apache-2.0
#include <morph/conform.h>

#include <algorithm>
#include <map>
#include <unordered_map>
#include <utility>

namespace morph {
namespace {

using Key = std::array<std::uint64_t, 3>;
using Pair = std::pair<std::uint64_t, std::uint64_t>;

struct KeyHash {
  std::size_t operator()(const Key& k) const {
    std::size_t h = 0;
    for (std::uint64_t r : k) h = h * 1000003u ^ std::hash<std::uint64_t>()(r);
    return h;
  }
};

Pair pair_of(std::uint64_t a, std::uint64_t b) {
  return a < b ? Pair{a, b} : Pair{b, a};
}

// The vertex's plane that is neither of the line's two.
const ExactPlane& third(const std::array<ExactPlane, 3>& v, std::uint64_t s, std::uint64_t e) {
  for (const ExactPlane& p : v)
    if (p.rank != s && p.rank != e) return p;
  return v[0];
}

class Builder {
 public:
  std::uint32_t vertex(const ExactPlane& a, const ExactPlane& b, const ExactPlane& c) {
    std::array<ExactPlane, 3> planes{a, b, c};
    std::sort(planes.begin(), planes.end(),
              [](const ExactPlane& x, const ExactPlane& y) { return x.rank < y.rank; });
    const Key key{planes[0].rank, planes[1].rank, planes[2].rank};
    auto [it, added] = index_.emplace(key, static_cast<std::uint32_t>(surface_.vertices.size()));
    if (added) {
      surface_.vertices.push_back(planes);
      for (int i = 0; i < 3; ++i) on_line_[pair_of(key[i], key[(i + 1) % 3])].push_back(it->second);
    }
    return it->second;
  }

  // The vertices strictly inside the edge from corner p to corner q on the line of planes s and
  // e, ordered from p: another vertex r of that line is inside iff its third plane separates
  // p from q, and r1 comes before r2 iff r1's plane separates p from r2.
  std::vector<std::uint32_t> inside_edge(const ExactPlane& s, const ExactPlane& e, std::uint32_t p,
                                         std::uint32_t q) {
    const ExactPlane& a = third(surface_.vertices[p], s.rank, e.rank);
    const ExactPlane& b = third(surface_.vertices[q], s.rank, e.rank);
    std::vector<std::uint32_t> inside;
    for (std::uint32_t r : on_line_[pair_of(s.rank, e.rank)]) {
      if (r == p || r == q) continue;
      const ExactPlane& c = third(surface_.vertices[r], s.rank, e.rank);
      if (side_at_vertex(s, e, a, c) != side_at_vertex(s, e, b, c)) inside.push_back(r);
    }
    std::sort(inside.begin(), inside.end(), [&](std::uint32_t r1, std::uint32_t r2) {
      const ExactPlane& c1 = third(surface_.vertices[r1], s.rank, e.rank);
      const ExactPlane& c2 = third(surface_.vertices[r2], s.rank, e.rank);
      return side_at_vertex(s, e, a, c1) != side_at_vertex(s, e, c2, c1);
    });
    return inside;
  }

  ConformedSurface& surface() { return surface_; }

 private:
  ConformedSurface surface_;
  std::unordered_map<Key, std::uint32_t, KeyHash> index_;
  std::map<Pair, std::vector<std::uint32_t>> on_line_;
};

}  // namespace

ConformedSurface conform(const std::vector<CarvedPiece>& pieces) {
  Builder builder;
  std::vector<std::vector<std::uint32_t>> corner_ids(pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const ConvexPiece& piece = pieces[i].piece;
    const std::size_t n = piece.edges.size();
    for (std::size_t k = 0; k < n; ++k)
      corner_ids[i].push_back(builder.vertex(piece.support, piece.edges[(k + n - 1) % n], piece.edges[k]));
  }
  ConformedSurface& surface = builder.surface();
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const ConvexPiece& piece = pieces[i].piece;
    const std::vector<std::uint32_t>& ids = corner_ids[i];
    const std::size_t n = ids.size();
    ConformedPolygon polygon{{}, n, pieces[i].move, pieces[i].face};
    for (std::size_t k = 0; k < n; ++k) {  // edge k runs from corner k to corner k+1
      polygon.loop.push_back(ids[k]);
      const std::vector<std::uint32_t> inside =
          builder.inside_edge(piece.support, piece.edges[k], ids[k], ids[(k + 1) % n]);
      polygon.loop.insert(polygon.loop.end(), inside.begin(), inside.end());
      surface.inserted += inside.size();
    }
    // Corners run counter-clockwise about the support's normal: out of the solid for a stock
    // face, into it for a sweep's facet.
    if (!pieces[i].faces_out()) std::reverse(polygon.loop.begin(), polygon.loop.end());
    surface.polygons.push_back(std::move(polygon));
  }
  return std::move(surface);
}

}  // namespace morph
