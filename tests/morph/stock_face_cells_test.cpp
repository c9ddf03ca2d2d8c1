// SPDX-License-Identifier: Apache-2.0
// A stock face cut into cells (stock_face_cells.h): the cells partition the face, each lists
// exactly the sweeps whose boxes meet it, and is split no further than it must be.
#include <morph/stock_face_cells.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace {

using Eigen::AlignedBox3d;
using Eigen::Vector3d;

const AlignedBox3d kStock(Vector3d(0, 0, -5), Vector3d(20, 20, 0));

// Random small boxes over the stock's top, as sweeps' boxes are: sides 1 to 3 mm, 2 mm tall.
std::vector<AlignedBox3d> scattered_boxes(std::size_t count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> at(-2.0, 22.0), side(1.0, 3.0);
  std::vector<AlignedBox3d> boxes;
  for (std::size_t k = 0; k < count; ++k) {
    const Vector3d low(at(random), at(random), -1.5);
    boxes.emplace_back(low, low + Vector3d(side(random), side(random), 2.0));
  }
  return boxes;
}

// True when (x, y) lies inside the convex polygon of the corners (counter-clockwise seen from
// +z), farther than `margin` from every edge; `near_edge` is set when it is within the margin.
bool inside_xy(const std::vector<Vector3d>& polygon, double x, double y, double margin, bool& near_edge) {
  bool inside = true;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Vector3d &p = polygon[k], &q = polygon[(k + 1) % polygon.size()];
    const double ex = q.x() - p.x(), ey = q.y() - p.y();
    const double cross = (ex * (y - p.y()) - ey * (x - p.x())) / std::hypot(ex, ey);
    if (std::fabs(cross) <= margin) near_edge = true;
    if (cross < 0) inside = false;
  }
  return inside;
}

TEST(CellLattice, HoldsTheStockAndRanksAPlaneByItsPlace) {
  const std::vector<AlignedBox3d> boxes{AlignedBox3d(Vector3d(0, 0, 0), Vector3d(28, 2, 6))};
  const morph::CellLattice lattice = morph::CellLattice::of(kStock, boxes);
  EXPECT_EQ(lattice.root, 64.0);  // twice the power of two above the extent 20
  EXPECT_EQ(lattice.depth, 7);    // finest 0.5: a quarter of the smallest box side, 2
  for (int a = 0; a < 3; ++a) {
    EXPECT_LE(lattice.origin[a], kStock.min()[a]);
    EXPECT_GE(lattice.origin[a] + lattice.root, kStock.max()[a]);
  }
  const morph::ExactPlane p = lattice.plane(0, 3), again = lattice.plane(0, 3);
  EXPECT_EQ(p.rank, again.rank);
  EXPECT_EQ(p.offset, again.offset);
  EXPECT_NE(lattice.plane(1, 3).rank, p.rank);
  EXPECT_NE(lattice.plane(0, 4).rank, p.rank);
  // Off the lattice line by a good part of a finest cell (0.5) either way, below every sweep rank.
  EXPECT_GT(p.offset, lattice.origin.x() + 1.5 + 0.1);
  EXPECT_LT(p.offset, lattice.origin.x() + 2.0 - 0.1);
  EXPECT_LT(p.rank, morph::sweep_rank(0, 0));
}

TEST(StockFaceCells, CellsPartitionTheFaceAndListTheSweepsThatMeetThem) {
  const std::array<morph::ExactPlane, 6> planes = morph::box_planes(kStock);
  const morph::ConvexPiece top = morph::piece_in_box(planes[5], planes);
  const std::vector<AlignedBox3d> boxes = scattered_boxes(300, 7);
  std::vector<std::uint32_t> near;
  for (std::uint32_t j = 0; j < boxes.size(); j += 2) near.push_back(j);  // every other one
  const morph::CellLattice lattice = morph::CellLattice::of(kStock, boxes);
  const double finest = std::ldexp(lattice.root, -lattice.depth);
  const std::size_t most = 8;
  const std::vector<morph::FaceCell> cells = morph::stock_face_cells(top, near, boxes, lattice, most);
  ASSERT_GT(cells.size(), 16u);

  double area = 0.0;
  std::vector<std::vector<Vector3d>> polygons;
  for (const morph::FaceCell& cell : cells) {
    ASSERT_FALSE(cell.piece.empty());
    EXPECT_EQ(cell.piece.support.rank, top.support.rank);
    area += morph::area_vector(cell.piece).z();
    polygons.push_back(morph::corners(cell.piece));
    // Exactly the listed sweeps whose boxes meet the cell's part, in order.
    const AlignedBox3d reach = morph::reach_of(cell.piece);
    std::vector<std::uint32_t> meeting;
    for (std::uint32_t j : near)
      if (reach.intersects(boxes[j])) meeting.push_back(j);
    EXPECT_EQ(cell.sweeps, meeting);
    // Split until few sweeps are left, or to the finest cell.
    if (cell.sweeps.size() > most) {
      EXPECT_LE(reach.sizes().x(), finest + 1e-6);
      EXPECT_LE(reach.sizes().y(), finest + 1e-6);
    }
  }
  EXPECT_NEAR(area, 400.0, 1e-9);
  // Every point of the face lies in exactly one cell (points near a cell edge left out).
  std::mt19937 random(11);
  std::uniform_real_distribution<double> at(0.0, 20.0);
  int tested = 0;
  for (int k = 0; k < 4000; ++k) {
    const double x = at(random), y = at(random);
    int holders = 0;
    bool near_edge = false;
    for (const std::vector<Vector3d>& polygon : polygons)
      holders += inside_xy(polygon, x, y, 1e-9, near_edge);
    if (near_edge) continue;
    ++tested;
    EXPECT_EQ(holders, 1) << x << " " << y;
  }
  EXPECT_GT(tested, 3900);
}

// A stock face on a lattice line (-12 = origin -32 plus 20) is not cut a hair's width inside it:
// such a strip's triangles round flat (stress seed 53, case 386).
TEST(StockFaceCells, NoCellIsASliverWhereTheFaceLiesOnALatticeLine) {
  const AlignedBox3d stock(Vector3d(-12, -12, -5), Vector3d(12, 12, 0));
  const std::array<morph::ExactPlane, 6> planes = morph::box_planes(stock);
  const morph::ConvexPiece top = morph::piece_in_box(planes[5], planes);
  std::vector<AlignedBox3d> boxes = scattered_boxes(400, 5);
  for (AlignedBox3d& box : boxes) box.translate(Vector3d(-10, -10, 0));  // over the shifted face
  std::vector<std::uint32_t> near(boxes.size());
  for (std::uint32_t j = 0; j < near.size(); ++j) near[j] = j;
  const morph::CellLattice lattice = morph::CellLattice::of(stock, boxes);
  ASSERT_EQ(lattice.origin.x(), -32.0);
  const double finest = std::ldexp(lattice.root, -lattice.depth);
  ASSERT_EQ(std::fmod(-12.0 - lattice.origin.x(), finest), 0.0);  // the face's edge is a lattice line
  const std::vector<morph::FaceCell> cells = morph::stock_face_cells(top, near, boxes, lattice, 8);
  ASSERT_GT(cells.size(), 16u);
  for (const morph::FaceCell& cell : cells) {
    AlignedBox3d extent;
    for (const Vector3d& x : morph::corners(cell.piece)) extent.extend(x);
    EXPECT_GT(extent.sizes().x(), 0.25 * finest);
    EXPECT_GT(extent.sizes().y(), 0.25 * finest);
  }
}

TEST(StockFaceCells, AFaceFewSweepsMeetIsOneCell) {
  const std::array<morph::ExactPlane, 6> planes = morph::box_planes(kStock);
  const morph::ConvexPiece top = morph::piece_in_box(planes[5], planes);
  const std::vector<AlignedBox3d> boxes = scattered_boxes(30, 3);
  std::vector<std::uint32_t> near(boxes.size());
  for (std::uint32_t j = 0; j < near.size(); ++j) near[j] = j;
  const std::vector<morph::FaceCell> cells =
      morph::stock_face_cells(top, near, boxes, morph::CellLattice::of(kStock, boxes), 30);
  ASSERT_EQ(cells.size(), 1u);
  EXPECT_EQ(cells[0].piece.edges.size(), top.edges.size());
  // The boxes that meet the face (some lie beside it).
  std::vector<std::uint32_t> meeting;
  for (std::uint32_t j : near)
    if (morph::reach_of(top).intersects(boxes[j])) meeting.push_back(j);
  EXPECT_LT(meeting.size(), near.size());
  EXPECT_EQ(cells[0].sweeps, meeting);
}

}  // namespace
