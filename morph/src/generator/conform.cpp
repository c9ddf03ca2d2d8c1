// SPDX-License-Identifier: Apache-2.0
#include <morph/conform.h>
#include <morph/facet_clipping.h>
#include <morph/parallel.h>

#include <morph/exceptions.h>

#include <algorithm>
#include <limits>
#include <optional>
#include <string>
#include <utility>

namespace morph {
namespace {

using Key = std::array<std::uint64_t, 3>;

// The slot of a vertex's line through planes s and e: the index (in the vertex's rank-sorted
// planes) of its third plane.
int slot_of(const PlaneTriple& v, std::uint64_t s, std::uint64_t e) {
  for (int i = 0; i < 3; ++i)
    if (v[i].rank != s && v[i].rank != e) return i;
  return 0;
}

// The vertices, and every plane-pair line with its vertices sorted along it once (by the exact
// predicates), so an edge finds the vertices strictly inside it by two positions.
class Builder {
 public:
  // Numbers the pieces' corners: each distinct plane triple is one vertex, numbered in the order
  // the corners (piece by piece, edge by edge) first name it; then lists each plane-pair line's
  // vertices. Sorts instead of hash tables, so both run in parallel; the numbers are the same.
  // Returns each corner's vertex, the corners of piece i from first_corner[i].
  std::vector<std::uint32_t> number(const CarvedPieces& pieces, const std::vector<std::size_t>& first_corner,
                                    ExecutionPolicy policy) {
    struct Corner {
      Key key;
      std::size_t index;  // piece by piece, edge by edge
    };
    std::vector<Corner> corners;
    resize_faulted_in(corners, first_corner.back(), policy);
    for_each_index(policy, 0, pieces.size(), [&](std::size_t i) {
      const CarvedPieces::Piece& piece = pieces.pieces[i];
      const std::size_t n = piece.edge_count;
      for (std::size_t k = 0; k < n; ++k) {
        Key key{pieces.support(piece).rank, pieces.edge(piece, (k + n - 1) % n).rank,
                pieces.edge(piece, k).rank};
        std::sort(key.begin(), key.end());
        corners[first_corner[i] + k] = {key, first_corner[i] + k};
      }
    });
    sort_under(policy, corners.begin(), corners.end(), [](const Corner& a, const Corner& b) {
      return a.key < b.key || (a.key == b.key && a.index < b.index);
    });
    // Runs of one key, ordered by their first corner: the vertices.
    std::vector<std::pair<std::size_t, std::size_t>> runs;  // first corner, start in `corners`
    for (std::size_t c = 0; c < corners.size(); ++c)
      if (c == 0 || corners[c].key != corners[c - 1].key) runs.emplace_back(corners[c].index, c);
    sort_under(policy, runs.begin(), runs.end(),
               [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::uint32_t> vertex_of;
    resize_faulted_in(vertex_of, corners.size(), policy);
    // Each vertex's planes where its first corner's piece holds them, sorted by rank.
    std::vector<std::array<const ExactPlane*, 3>> source;
    resize_faulted_in(source, runs.size(), policy);
    for_each_index(policy, 0, runs.size(), [&](std::size_t v) {
      const std::size_t first = runs[v].first;
      const std::size_t i = static_cast<std::size_t>(
          std::upper_bound(first_corner.begin(), first_corner.end(), first) - first_corner.begin() - 1);
      const CarvedPieces::Piece& piece = pieces.pieces[i];
      const std::size_t n = piece.edge_count, k = first - first_corner[i];
      source[v] = {&pieces.support(piece), &pieces.edge(piece, (k + n - 1) % n), &pieces.edge(piece, k)};
      std::sort(source[v].begin(), source[v].end(),
                [](const ExactPlane* x, const ExactPlane* y) { return x->rank < y->rank; });
      for (std::size_t c = runs[v].second;
           c < corners.size() && corners[c].key == corners[runs[v].second].key; ++c)
        vertex_of[corners[c].index] = static_cast<std::uint32_t>(v);
    });
    make_plane_table(source, policy);
    make_lines(policy);
    return vertex_of;
  }

  // Sorts every line's vertices along the direction lo × hi of its planes (lo the lower rank):
  // r1 comes first iff r1 is inside r2's third plane c2 and c2 faces along the direction, or
  // outside it and c2 faces back.
  void order_lines(ExecutionPolicy policy) {
    position_.clear();
    resize_faulted_in(position_, surface_.vertices.size(), policy);  // zeros
    for_each_index(policy, 0, line_count(), [&](std::size_t l) {
      std::uint32_t* line = line_vertices_.data() + line_start_[l];
      const std::size_t count = line_size(l);
      if (count > 1) {
        const PlaneTriple first = surface_.vertices[line[0]];
        const int third = slot_of_line(line[0], static_cast<std::uint32_t>(l));
        const ExactPlane& lo = first[third == 0 ? 1 : 0];
        const ExactPlane& hi = first[third == 2 ? 1 : 2];
        // Each vertex with the sign of its third plane's normal along the line, and the float look
        // at it (facet_clipping.h): the look orders most pairs, the exact predicate the rest
        // (ties and near ties), with the same answers.
        // Where the look is not sure, the exact side at the vertex's grid point when it is one
        // (side_at_vertex_near(): the same sign as side_at_vertex() at a fraction of its cost),
        // looked for once per vertex.
        struct OnLine {
          std::uint32_t vertex;
          int facing;
          const ExactPlane* third;
          double length;  // of third->normal
          std::optional<CornerLook> look;
          VertexGrid grid;
        };
        std::vector<OnLine> on_line;
        on_line.reserve(count);
        for (std::size_t k = 0; k < count; ++k) {
          const ExactPlane& third = third_plane(line[k], static_cast<std::uint32_t>(l));
          on_line.push_back({line[k], normals_orientation(lo, hi, third), &third, third.normal.norm(),
                             corner_look(lo, hi, third), VertexGrid{}});
        }
        auto exact_side = [&](OnLine& r1, const ExactPlane& plane) {
          return r1.look ? side_at_vertex_near(lo, hi, *r1.third, r1.look->point, r1.grid, plane)
                         : side_at_vertex(lo, hi, *r1.third, plane);
        };
        std::sort(on_line.begin(), on_line.end(), [&](OnLine& r1, OnLine& r2) {
          if (r1.vertex == r2.vertex) return false;
          int side = r1.look ? look_side(*r1.look, *r2.third, r2.length) : 0;
          if (side == 0) side = exact_side(r1, *r2.third);
          return (side < 0) == (r2.facing > 0);
        });
        for (std::size_t k = 0; k < count; ++k) line[k] = on_line[k].vertex;
      }
      for (std::size_t k = 0; k < count; ++k)
        position_[line[k]][slot_of_line(line[k], static_cast<std::uint32_t>(l))] =
            static_cast<std::uint32_t>(k);
    });
  }

  // The vertices strictly inside the edge from corner p to corner q on the line of planes s and
  // e, ordered from p.
  std::vector<std::uint32_t> inside_edge(const ExactPlane& s, const ExactPlane& e, std::uint32_t p,
                                         std::uint32_t q) const {
    const int slot_p = slot_of(surface_.vertices[p], s.rank, e.rank);
    const int slot_q = slot_of(surface_.vertices[q], s.rank, e.rank);
    const std::uint32_t* line = line_vertices_.data() + line_start_[vertex_lines_[p][slot_p]];
    const std::uint32_t from = position_[p][slot_p], to = position_[q][slot_q];
    if (from < to) return std::vector<std::uint32_t>(line + from + 1, line + to);
    std::vector<std::uint32_t> inside(line + to + 1, line + from);
    std::reverse(inside.begin(), inside.end());
    return inside;
  }

  ConformedSurface& surface() { return surface_; }

 private:
  std::size_t line_count() const { return line_start_.size() - 1; }
  std::size_t line_size(std::size_t l) const { return line_start_[l + 1] - line_start_[l]; }

  int slot_of_line(std::uint32_t r, std::uint32_t l) const {
    const std::array<std::uint32_t, 3>& lines = vertex_lines_[r];
    return lines[0] == l ? 0 : (lines[1] == l ? 1 : 2);
  }
  const ExactPlane& third_plane(std::uint32_t r, std::uint32_t l) const {
    return surface_.vertices[r][slot_of_line(r, l)];
  }

  // The vertices' planes, each rank once (the first vertex slot naming it gives the copy: a
  // plane and its flipped() name one point alike), and each vertex's triple of indices.
  void make_plane_table(const std::vector<std::array<const ExactPlane*, 3>>& source, ExecutionPolicy policy) {
    struct Named {
      std::uint64_t rank;
      std::uint32_t slot;  // 3 · vertex + its index in the vertex's triple
    };
    if (source.size() > std::numeric_limits<std::uint32_t>::max() / 3)
      throw LimitError("conform: more than " + std::to_string(std::numeric_limits<std::uint32_t>::max() / 3) +
                       " vertices");
    std::vector<Named> named;
    resize_faulted_in(named, 3 * source.size(), policy);
    for_each_index(policy, 0, source.size(), [&](std::size_t v) {
      for (std::uint32_t k = 0; k < 3; ++k)
        named[3 * v + k] = {source[v][k]->rank, static_cast<std::uint32_t>(3 * v + k)};
    });
    sort_under(policy, named.begin(), named.end(), [](const Named& a, const Named& b) {
      return a.rank < b.rank || (a.rank == b.rank && a.slot < b.slot);
    });
    VertexPlanes& vertices = surface_.vertices;
    resize_faulted_in(vertices.triples, source.size(), policy);
    for (std::size_t e = 0; e < named.size(); ++e) {
      if (e == 0 || named[e].rank != named[e - 1].rank)
        vertices.planes.push_back(*source[named[e].slot / 3][named[e].slot % 3]);
      vertices.triples[named[e].slot / 3][named[e].slot % 3] =
          static_cast<std::uint32_t>(vertices.planes.size() - 1);
    }
  }

  // Each line of two of a vertex's planes with its vertices in increasing order (each vertex once:
  // its three lines are distinct), and each vertex's line by slot (the slot of the third plane).
  void make_lines(ExecutionPolicy policy) {
    // A line is named by its two planes' indices in the table (in increasing rank, as the
    // planes are), the lower in the high half.
    struct OnLine {
      std::uint64_t line;
      std::uint32_t vertex;
      std::uint32_t slot;
    };
    std::vector<OnLine> entries;
    resize_faulted_in(entries, 3 * surface_.vertices.size(), policy);
    for_each_index(policy, 0, surface_.vertices.size(), [&](std::size_t v) {
      const std::array<std::uint32_t, 3>& planes = surface_.vertices.triples[v];
      for (std::uint32_t slot = 0; slot < 3; ++slot) {
        const std::uint32_t a = planes[(slot + 1) % 3], b = planes[(slot + 2) % 3];
        entries[3 * v + slot] = {std::uint64_t{std::min(a, b)} << 32 | std::max(a, b),
                                 static_cast<std::uint32_t>(v), slot};
      }
    });
    sort_under(policy, entries.begin(), entries.end(), [](const OnLine& a, const OnLine& b) {
      return a.line < b.line || (a.line == b.line && a.vertex < b.vertex);
    });
    // The lines one after another in one array (a vector per line cost a million small
    // allocations, made one at a time).
    resize_faulted_in(vertex_lines_, surface_.vertices.size(), policy);
    resize_faulted_in(line_vertices_, entries.size(), policy);
    line_start_.clear();
    for (std::size_t e = 0; e < entries.size(); ++e) {
      if (e == 0 || entries[e].line != entries[e - 1].line) line_start_.push_back(e);
      line_vertices_[e] = entries[e].vertex;
      vertex_lines_[entries[e].vertex][static_cast<std::size_t>(entries[e].slot)] =
          static_cast<std::uint32_t>(line_start_.size() - 1);
    }
    line_start_.push_back(entries.size());
  }

  ConformedSurface surface_;
  std::vector<std::uint32_t> line_vertices_;  ///< each line's vertices, sorted by order_lines(), line by line
  std::vector<std::size_t> line_start_;  ///< line l's in line_vertices_[line_start_[l], line_start_[l + 1])
  std::vector<std::array<std::uint32_t, 3>> vertex_lines_;  ///< per vertex, its line by slot
  std::vector<std::array<std::uint32_t, 3>> position_;      ///< per vertex, its index on each line
};

}  // namespace

ConformedSurface conform(const std::vector<CarvedPiece>& pieces, ExecutionPolicy policy) {
  return conform(compact(pieces), policy);
}

ConformedSurface conform(const CarvedPieces& pieces, ExecutionPolicy policy) {
  Builder builder;
  std::vector<std::size_t> first_corner(pieces.size() + 1, 0);
  for (std::size_t i = 0; i < pieces.size(); ++i)
    first_corner[i + 1] = first_corner[i] + pieces.pieces[i].edge_count;
  const std::vector<std::uint32_t> vertex_of = builder.number(pieces, first_corner, policy);
  builder.order_lines(policy);
  ConformedSurface& surface = builder.surface();
  resize_faulted_in(surface.polygons, pieces.size(), policy);
  std::vector<std::size_t> inserted(pieces.size(), 0);
  for_each_index(policy, 0, pieces.size(), [&](std::size_t i) {
    const CarvedPieces::Piece& piece = pieces.pieces[i];
    const std::uint32_t* ids = vertex_of.data() + first_corner[i];
    const std::size_t n = piece.edge_count;
    ConformedPolygon polygon{{}, n, piece.move, piece.face};
    for (std::size_t k = 0; k < n; ++k) {  // edge k runs from corner k to corner k+1
      polygon.loop.push_back(ids[k]);
      const std::vector<std::uint32_t> inside =
          builder.inside_edge(pieces.support(piece), pieces.edge(piece, k), ids[k], ids[(k + 1) % n]);
      polygon.loop.insert(polygon.loop.end(), inside.begin(), inside.end());
      inserted[i] += inside.size();
    }
    // Corners run counter-clockwise about the support's normal: out of the solid for a stock
    // face, into it for a sweep's facet.
    if (!piece.faces_out()) std::reverse(polygon.loop.begin(), polygon.loop.end());
    surface.polygons[i] = std::move(polygon);
  });
  for (std::size_t n : inserted) surface.inserted += n;
  return std::move(surface);
}

}  // namespace morph
