// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>
#include <morph/path.h>
#include <morph/stock.h>

#include <cmath>

using Eigen::Vector3d;
using morph::Move;

namespace {
Move helix(double radius, double sweep, double rise) {
  Move m;
  m.kind = morph::MoveKind::Arc;
  m.center = Vector3d(1, 2, 3);
  m.axis = Vector3d::UnitZ();
  m.start = m.center + Vector3d(radius, 0, 0);
  m.sweep = sweep;
  m.end = m.center + Vector3d(radius * std::cos(sweep), radius * std::sin(sweep), rise);
  return m;
}
}  // namespace

TEST(Path, ArcPointsLieOnTheCircleAndEndsAreExact) {
  const Move m = helix(5.0, M_PI / 2, 0.0);
  EXPECT_EQ(morph::point_at(m, 0.0), m.start);
  EXPECT_EQ(morph::point_at(m, 1.0), m.end);
  for (int i = 0; i <= 10; ++i) {
    const Vector3d p = morph::point_at(m, i / 10.0);
    EXPECT_NEAR((p - m.center).norm(), 5.0, 1e-12);
  }
  // Counter-clockwise about +z: the midpoint is at 45 degrees.
  const Vector3d mid = morph::point_at(m, 0.5) - m.center;
  EXPECT_NEAR(std::atan2(mid.y(), mid.x()), M_PI / 4, 1e-12);
}

TEST(Path, HelixLengthIsClosedForm) {
  const Move m = helix(4.0, 6 * M_PI, 9.0);
  EXPECT_NEAR(morph::length(m), std::hypot(4.0 * 6 * M_PI, 9.0), 1e-9);
  EXPECT_NEAR(morph::point_at(m, 0.5).z(), m.center.z() + 4.5, 1e-12);
}

TEST(Path, ChordParametersMeetTheTolerance) {
  const Move m = helix(10.0, 2 * M_PI, 0.0);
  const double tolerance = 0.01;
  const std::vector<double> ts = morph::chord_parameters(m, tolerance);
  ASSERT_GE(ts.size(), 3u);
  double worst = 0.0;
  for (std::size_t i = 0; i + 1 < ts.size(); ++i) {
    const Vector3d a = morph::point_at(m, ts[i]), b = morph::point_at(m, ts[i + 1]);
    const Vector3d mid = morph::point_at(m, 0.5 * (ts[i] + ts[i + 1]));
    worst = std::max(worst, (mid - 0.5 * (a + b)).norm());
  }
  EXPECT_LE(worst, tolerance);
  EXPECT_GT(worst, 0.5 * tolerance);  // not wastefully fine
}

TEST(Stock, BoxAndCylinderSignedDistanceAreExact) {
  morph::Stock box;
  box.box = Eigen::AlignedBox3d(Vector3d(0, 0, 0), Vector3d(10, 6, 2));
  EXPECT_DOUBLE_EQ(morph::analytic_signed_distance(box, Vector3d(5, 3, 1.5)), -0.5);
  EXPECT_DOUBLE_EQ(morph::analytic_signed_distance(box, Vector3d(13, 10, 1)), 5.0);
  EXPECT_DOUBLE_EQ(morph::volume(box), 120.0);
  EXPECT_DOUBLE_EQ(morph::surface_area(box), 2 * (60 + 12 + 20));

  morph::Stock cyl;
  cyl.type = morph::StockType::Cylinder;
  cyl.base = Vector3d(0, 0, 0);
  cyl.axis = Vector3d::UnitZ();
  cyl.radius = 3;
  cyl.height = 10;
  EXPECT_DOUBLE_EQ(morph::analytic_signed_distance(cyl, Vector3d(0, 0, 5)), -3.0);
  EXPECT_DOUBLE_EQ(morph::analytic_signed_distance(cyl, Vector3d(7, 0, 13)), 5.0);
  EXPECT_DOUBLE_EQ(morph::analytic_signed_distance(cyl, Vector3d(0, 0, 9.5)), -0.5);
  EXPECT_NEAR(morph::volume(cyl), M_PI * 90, 1e-12);
  const Eigen::AlignedBox3d b = morph::bounds(cyl);
  EXPECT_NEAR(b.min().x(), -3, 1e-12);
  EXPECT_NEAR(b.max().z(), 10, 1e-12);
}
