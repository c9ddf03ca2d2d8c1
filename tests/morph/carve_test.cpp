// SPDX-License-Identifier: Apache-2.0
#include <morph/carve.h>
#include <morph/sweep_polytope.h>
#include <morph/tool.h>
#include <morph/tool_polytope.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;
using morph::CarvedPiece;

const Eigen::AlignedBox3d kBox(Vector3d(0, 0, -5), Vector3d(10, 8, 0));
constexpr double kBoxVolume = 10 * 8 * 5;
constexpr double kBoxArea = 2 * (10 * 8 + 10 * 5 + 8 * 5);

struct Segment {
  Vector3d from, to;
};

struct Carved {
  std::vector<CarvedPiece> pieces;
  double volume = 0, area = 0;
  std::size_t pieces_of(int move) const {
    return static_cast<std::size_t>(
        std::count_if(pieces.begin(), pieces.end(), [&](const CarvedPiece& p) { return p.move == move; }));
  }
};

// The box minus the sweeps of `tool` along the segments, with the enclosed volume by the
// divergence theorem (each planar piece contributes (area vector · a corner) / 3).
Carved carve(const morph::ConvexPolytope& tool, const std::vector<Segment>& moves) {
  const morph::SweepPolytopeBuilder builder(tool);
  std::vector<std::vector<morph::ExactPlane>> sweeps;
  std::vector<Eigen::AlignedBox3d> boxes;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    sweeps.push_back(
        morph::sweep_planes(builder.halfspaces(moves[i].from, moves[i].to), static_cast<std::uint32_t>(i)));
    boxes.push_back(builder(moves[i].from, moves[i].to).bounds());
  }
  Carved out;
  out.pieces = morph::carve_box(kBox, sweeps, boxes);
  for (const CarvedPiece& p : out.pieces) {
    const Vector3d a = morph::area_vector(p.piece);
    const double sign = p.faces_out() ? 1.0 : -1.0;
    out.area += a.norm();
    out.volume += sign * a.dot(morph::corners(p.piece).front()) / 3;
  }
  return out;
}

// Area of the convex hull of points (monotone chain) clipped to y <= top: a sweep's cross
// section perpendicular to a level move is the tool's projection, so a slot through the whole
// box removes length × this area (Cavalieri).
double hull_area_below(std::vector<Vector2d> p, double top) {
  std::sort(p.begin(), p.end(), [](const Vector2d& a, const Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  auto cross = [](const Vector2d& o, const Vector2d& a, const Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Vector2d> hull(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], p[i]) <= 0) --k;
    hull[k++] = p[i];
  }
  hull.resize(k - 1);
  std::vector<Vector2d> clipped;  // Sutherland-Hodgman against y <= top
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const Vector2d& a = hull[i];
    const Vector2d& b = hull[(i + 1) % hull.size()];
    if (a.y() <= top) clipped.push_back(a);
    if ((a.y() < top) != (b.y() < top)) clipped.push_back(a + (b - a) * ((top - a.y()) / (b.y() - a.y())));
  }
  double area = 0;
  for (std::size_t i = 0; i < clipped.size(); ++i) {
    const Vector2d& a = clipped[i];
    const Vector2d& b = clipped[(i + 1) % clipped.size()];
    area += a.x() * b.y() - a.y() * b.x();
  }
  return std::fabs(area) / 2;
}

// The tool's projection along x (onto y, z) or along y (onto x, z), placed at `point`.
double slot_section(const morph::ConvexPolytope& tool, int along, const Vector3d& point, double top) {
  std::vector<Vector2d> p;
  const int across = along == 0 ? 1 : 0;
  for (const Vector3d& v : tool.vertices) p.emplace_back(v[across] + point[across], v.z() + point.z());
  return hull_area_below(p, top);
}

double extent(const morph::ConvexPolytope& tool, int axis) {
  double lo = 1e300, hi = -1e300;
  for (const Vector3d& v : tool.vertices) lo = std::min(lo, v[axis]), hi = std::max(hi, v[axis]);
  return hi - lo;
}

morph::ConvexPolytope flat_mill() {
  return morph::tool_polytope(morph::flat_tool(1.0, 10.0).profile, 0.02).polytope;
}
morph::ConvexPolytope ball_mill() {
  return morph::tool_polytope(morph::ball_tool(1.0, 10.0).profile, 0.05).polytope;
}

TEST(Carve, UntouchedBoxIsItsSixFaces) {
  const Carved c = carve(flat_mill(), {{Vector3d(5, 4, 3), Vector3d(8, 4, 3)}});
  EXPECT_EQ(c.pieces.size(), 6u);
  EXPECT_NEAR(c.volume, kBoxVolume, 1e-9);
  EXPECT_NEAR(c.area, kBoxArea, 1e-9);
}

TEST(Carve, SlotThroughTheBoxRemovesLengthTimesSection) {
  for (const auto& tool : {flat_mill(), ball_mill()}) {
    const Vector3d a(-3, 4, -0.5), b(13, 4, -0.5);
    const Carved c = carve(tool, {{a, b}});
    const double removed = 10 * slot_section(tool, 0, a, 0.0);
    EXPECT_NEAR(c.volume, kBoxVolume - removed, 1e-9 * kBoxVolume);
    EXPECT_GT(c.pieces_of(0), 2u);
  }
  // A flat mill's slot: walls and floor added, the top strip and the two end notches gone.
  const morph::ConvexPolytope tool = flat_mill();
  const double w = extent(tool, 1), d = 0.5;
  const Carved c = carve(tool, {{Vector3d(-3, 4, -d), Vector3d(13, 4, -d)}});
  EXPECT_NEAR(c.area, kBoxArea - 2 * w * d + 2 * 10 * d, 1e-9 * kBoxArea);
}

TEST(Carve, MoveInsideTheStockLeavesItsSweepAsACavity) {
  // Short tools (1.5 long), so that the whole sweep is inside the stock.
  for (const auto& tool : {morph::tool_polytope(morph::flat_tool(1.0, 1.5).profile, 0.02).polytope,
                           morph::tool_polytope(morph::ball_tool(1.0, 1.5).profile, 0.05).polytope}) {
    const Vector3d a(3, 4, -4.2), b(7, 5, -3.2);  // the ball end's polytope is 2.5 tall
    ASSERT_LT(tool.bounds().max().z() + b.z(), 0.0);
    const morph::ConvexPolytope sweep = morph::sweep_polytope(tool, a, b);
    const Carved c = carve(tool, {{a, b}});
    EXPECT_NEAR(c.volume, kBoxVolume - sweep.volume(), 1e-9 * kBoxVolume);
    EXPECT_NEAR(c.area, kBoxArea + sweep.area(), 1e-9 * kBoxArea);
    EXPECT_EQ(c.pieces_of(-1), 6u);
  }
}

TEST(Carve, RetraceIsExactlyTheSingleMove) {
  for (const auto& tool : {flat_mill(), ball_mill()}) {
    const Vector3d a(-3, 4, -0.5), b(13, 4, -0.5);
    const Carved once = carve(tool, {{a, b}});
    const Carved twice = carve(tool, {{a, b}, {b, a}});
    EXPECT_EQ(twice.pieces_of(1), 0u) << "the retrace's facets all coincide with the first pass's";
    // (The first pass's pieces may be split into more convex pieces by the retrace's planes.)
    EXPECT_NEAR(twice.volume, once.volume, 1e-12 * kBoxVolume);
    EXPECT_NEAR(twice.area, once.area, 1e-12 * kBoxArea);
  }
}

TEST(Carve, CrossingSlotsAtOneDepthShareTheirFloor) {
  const morph::ConvexPolytope tool = flat_mill();
  const double d = 0.5, wx = extent(tool, 0), wy = extent(tool, 1);
  const Carved c =
      carve(tool, {{Vector3d(-3, 4, -d), Vector3d(13, 4, -d)}, {Vector3d(5, -3, -d), Vector3d(5, 11, -d)}});
  EXPECT_NEAR(c.volume, kBoxVolume - d * (10 * wy + 8 * wx - wx * wy), 1e-9 * kBoxVolume);
  // The floors are coplanar: the earlier move owns the shared square, and the floor is whole.
  double floor = 0;
  for (const CarvedPiece& p : c.pieces)
    if (!p.faces_out() && p.piece.support.normal.z() < -0.999) floor += morph::area_vector(p.piece).norm();
  EXPECT_NEAR(floor, 10 * wy + 8 * wx - wx * wy, 1e-9);
}

TEST(Carve, PlungeAndRetractIsThePlunge) {
  const morph::ConvexPolytope tool = flat_mill();
  double bottom = 0;
  for (const morph::PolytopeFacet& f : tool.facets)
    if (f.normal.z() < -0.999) bottom = morph::loop_area_vector(tool.vertices, f.loop).norm();
  const Vector3d above(5, 4, 2), below(5, 4, -1);
  const Carved plunge = carve(tool, {{above, below}});
  const Carved both = carve(tool, {{above, below}, {below, above}});
  EXPECT_NEAR(plunge.volume, kBoxVolume - bottom * 1.0, 1e-9 * kBoxVolume);
  EXPECT_NEAR(both.volume, plunge.volume, 1e-12 * kBoxVolume);
  EXPECT_NEAR(both.area, plunge.area, 1e-12 * kBoxArea);
  EXPECT_EQ(both.pieces_of(1), 0u);
}

}  // namespace

// The reach of a piece holds its corners and meets a box that only touches it, but grows by no
// more than 1e-7 of the coordinates' size.
TEST(Carve, APiecesReachHoldsItsCornersAndMeetsWhatTouchesIt) {
  const Eigen::AlignedBox3d stock(Vector3d(1000, -3, -2), Vector3d(1004, 5, 0));
  const std::array<morph::ExactPlane, 6> planes = morph::box_planes(stock);
  const morph::ConvexPiece top = morph::piece_in_box(planes[5], planes);
  const Eigen::AlignedBox3d reach = morph::reach_of(top);
  for (const Vector3d& x : morph::corners(top)) EXPECT_TRUE(reach.contains(x));
  const Eigen::AlignedBox3d touching(Vector3d(1004, 5, 0), Vector3d(1010, 9, 3));
  EXPECT_TRUE(reach.intersects(touching));
  const Eigen::AlignedBox3d beside(Vector3d(1004.001, -3, -2), Vector3d(1010, 9, 3));
  EXPECT_FALSE(reach.intersects(beside));
  EXPECT_LT((reach.max() - Vector3d(1004, 5, 0)).maxCoeff(), 1e-7 * 1005 + 1e-12);
  EXPECT_GT((reach.max() - Vector3d(1004, 5, 0)).minCoeff(), 0.0);
}
