// SPDX-License-Identifier: Apache-2.0
// The carving's pieces with their planes in a table (carved_pieces.h): the same pieces as values,
// each oriented plane held once, and parts joined with their indices moved.
#include <gtest/gtest.h>
#include <morph/carved_pieces.h>

#include <set>
#include <utility>

namespace {

using Eigen::Vector3d;

morph::ExactPlane plane(const Vector3d& normal, double offset, std::uint64_t rank) {
  return morph::ExactPlane{normal, offset, rank, 1};
}

bool same(const morph::ExactPlane& a, const morph::ExactPlane& b) {
  return a.normal == b.normal && a.offset == b.offset && a.rank == b.rank && a.direction == b.direction &&
         a.exact.offset == b.exact.offset && a.exact.normal == b.exact.normal;
}

bool same(const std::vector<morph::CarvedPiece>& a, const std::vector<morph::CarvedPiece>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].move != b[i].move || a[i].face != b[i].face || !same(a[i].piece.support, b[i].piece.support) ||
        a[i].piece.edges.size() != b[i].piece.edges.size())
      return false;
    for (std::size_t k = 0; k < a[i].piece.edges.size(); ++k)
      if (!same(a[i].piece.edges[k], b[i].piece.edges[k])) return false;
  }
  return true;
}

// Two squares side by side in the plane z = 0 sharing the edge x = 1, which one holds as it is
// and the other turned over; a third piece names the first's support as its edge.
std::vector<morph::CarvedPiece> squares() {
  const morph::ExactPlane floor = plane({0, 0, 1}, 0, 10), x0 = plane({-1, 0, 0}, 0, 11),
                          x1 = plane({1, 0, 0}, 1, 12), x2 = plane({1, 0, 0}, 2, 13),
                          y0 = plane({0, -1, 0}, 0, 14), y1 = plane({0, 1, 0}, 1, 15),
                          wall = plane({0, 1, 0}, 3, 16);
  std::vector<morph::CarvedPiece> pieces(3);
  pieces[0] = {{floor, {x0, y0, x1, y1}}, 4, 2};
  pieces[1] = {{floor, {morph::flipped(x1), y0, x2, y1}}, 4, 2};
  pieces[2] = {{wall, {floor, x0, x2}}, -1, 5};
  return pieces;
}

TEST(CarvedPieces, HoldEachOrientedPlaneOnceAndGiveThePiecesBack) {
  const std::vector<morph::CarvedPiece> pieces = squares();
  const morph::CarvedPieces table = morph::compact(pieces);
  // floor, x0, x1, x1 turned over, x2, y0, y1, wall: eight distinct oriented planes of 14 named.
  EXPECT_EQ(table.planes.size(), 8u);
  std::set<std::pair<std::uint64_t, int>> oriented;
  for (const morph::ExactPlane& p : table.planes) oriented.insert({p.rank, p.direction});
  EXPECT_EQ(oriented.size(), table.planes.size());
  EXPECT_EQ(table.edges.size(), 11u);
  EXPECT_EQ(table.pieces[0].support, table.pieces[1].support);
  EXPECT_EQ(table.edge(table.pieces[2], 0).rank, 10u);
  EXPECT_TRUE(same(morph::expanded(table), pieces));
}

TEST(CarvedPieces, JoinedPartsKeepTheirPiecesInOrder) {
  const std::vector<morph::CarvedPiece> pieces = squares();
  std::vector<morph::CarvedPieces> parts{morph::compact({pieces[0]}), morph::compact({pieces[1], pieces[2]}),
                                         morph::compact({})};
  for (morph::ExecutionPolicy policy :
       {morph::ExecutionPolicy::Sequential, morph::ExecutionPolicy::Parallel}) {
    std::vector<morph::CarvedPieces> copy = parts;
    const morph::CarvedPieces joined = morph::concatenated(copy, policy);
    EXPECT_EQ(joined.size(), 3u);
    EXPECT_TRUE(same(morph::expanded(joined), pieces));
    EXPECT_TRUE(copy[1].pieces.empty()) << "the parts are moved out";
  }
}

}  // namespace
