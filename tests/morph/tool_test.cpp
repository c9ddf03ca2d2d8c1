// SPDX-License-Identifier: Apache-2.0
// Every tool shape against closed forms: distances at chosen points, the profile's distance
// against a dense sampling of its boundary, volumes of the tool and of single sweeps (Cavalieri
// for straight moves, Pappus for a full circle) against quasi-Monte Carlo integration of the
// exact swept distance, and the refusals of bad sizes, each naming its field.
#include <gtest/gtest.h>
#include <morph/path.h>
#include <morph/sweep_distance.h>
#include <morph/tool.h>

#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

using Eigen::Vector2d;
using Eigen::Vector3d;
using morph::Tool;

namespace {

struct Named {
  std::string name;
  Tool tool;
};

// One tool of every shape (job units: mm), with the CAMotics projects' own shapes among them.
std::vector<Named> every_shape() {
  return {
      {"sphere", morph::sphere_tool(2.0)},
      {"ball", morph::ball_tool(1.5, 6.0)},
      {"flat", morph::flat_tool(3.0, 8.0)},
      {"bullnose", morph::bullnose_tool(4.0, 1.5, 9.0)},
      {"vbit 90", morph::conical_tool(3.0, 90.0, 7.0)},
      {"camotics conical", morph::conical_tool(1.0, morph::cone_angle(1.0, 2.0), 2.0)},
      {"engraving cone", morph::conical_tool(2.0, 60.0, 6.0, 0.25)},
      {"tapered (snubnose)", morph::tapered_tool(1.0, 2.0, 5.5)},
      {"tapered ball", morph::tapered_ball_tool(0.75, 8.0, 10.0)},
      {"spheroid", morph::spheroid_tool(2.0, 5.0)},
      {"apt", morph::apt_tool(8.0, 1.0, 10.0, 5.0, 12.0)},
  };
}

// Halton points in the unit cube: deterministic, low discrepancy.
double radical_inverse(std::uint64_t i, int base) {
  double inverse = 1.0 / base, value = 0.0, digit = inverse;
  for (; i > 0; i /= base, digit *= inverse) value += digit * double(i % base);
  return value;
}

// Volume of {p in box : f(p) < 0} by N Halton points, and the 4-sigma bound of plain Monte Carlo
// with N points (quasi-random points do better; the bound is what the tests allow).
std::pair<double, double> volume_by_sampling(const Eigen::AlignedBox3d& box,
                                             const std::function<double(const Vector3d&)>& f, int n) {
  int inside = 0;
  for (int i = 1; i <= n; ++i) {
    const Vector3d u(radical_inverse(i, 2), radical_inverse(i, 3), radical_inverse(i, 5));
    if (f(box.min() + u.cwiseProduct(box.sizes())) < 0.0) ++inside;
  }
  const double p = double(inside) / n, v = box.volume();
  return {p * v, 4.0 * std::sqrt(p * (1.0 - p) / n) * v};
}

morph::Move line_move(const Vector3d& a, const Vector3d& b) {
  morph::Move m;
  m.start = a;
  m.end = b;
  m.tool = 1;
  return m;
}

// Full counter-clockwise circle of radius `radius` about the z axis at height z.
morph::Move circle(double radius, double z) {
  morph::Move m;
  m.kind = morph::MoveKind::Arc;
  m.center = Vector3d(0, 0, z);
  m.axis = Vector3d::UnitZ();
  m.start = Vector3d(radius, 0, z);
  m.end = m.start;
  m.sweep = 2.0 * M_PI;
  m.tool = 1;
  return m;
}

// Points densely along the profile's boundary (the check of the exact 2D distance).
std::vector<Vector2d> boundary_samples(const morph::ToolProfile& profile, int per_piece) {
  std::vector<Vector2d> points;
  for (const morph::ProfilePiece& piece : profile.pieces())
    for (int i = 0; i <= per_piece; ++i) {
      const double s = double(i) / per_piece;
      if (piece.kind == morph::ProfilePiece::Kind::Segment) {
        points.push_back(piece.from + s * (piece.to - piece.from));
      } else {
        const double a = piece.angle0 + s * (piece.angle1 - piece.angle0);
        points.push_back(piece.centre +
                         Vector2d(piece.radii.x() * std::cos(a), piece.radii.y() * std::sin(a)));
      }
    }
  return points;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const morph::ToolError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST(ToolShapes, DistancesAtChosenPoints) {
  auto d = [](const Tool& tool, double r, double h) { return tool.profile.signed_distance(r, h); };
  const Tool flat = morph::flat_tool(3.0, 20.0);
  EXPECT_NEAR(d(flat, 5, 10), 2.0, 1e-15);
  EXPECT_NEAR(d(flat, 1, -2), 2.0, 1e-15);
  EXPECT_NEAR(d(flat, 5, -4), std::sqrt(20.0), 1e-14);
  EXPECT_NEAR(d(flat, 2, 10), -1.0, 1e-15);
  EXPECT_NEAR(d(flat, 0, 1), -1.0, 1e-15);
  EXPECT_NEAR(d(flat, 0, 23), 3.0, 1e-15);

  const Tool bull = morph::bullnose_tool(5.0, 2.0, 20.0);  // corner centre (3, 2)
  EXPECT_NEAR(d(bull, 6, -1), std::sqrt(18.0) - 2.0, 1e-14);
  EXPECT_NEAR(d(bull, 3, 2), -2.0, 1e-15);
  EXPECT_NEAR(d(bull, 1, -1), 1.0, 1e-15);  // under the flat part of the bottom

  const Tool vbit = morph::conical_tool(3.0, 90.0, 10.0);  // cone to (3, 3), shank to 10
  EXPECT_NEAR(d(vbit, 0, -1), 1.0, 1e-15);
  EXPECT_NEAR(d(vbit, 3, 0), 3.0 / std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(d(vbit, 0, 2), -2.0 / std::sqrt(2.0), 1e-14);
  EXPECT_NEAR(d(vbit, 4, 6), 1.0, 1e-15);

  const Tool snub = morph::tapered_tool(1.0, 2.0, 5.5);  // CAMotics slant_test's tool
  EXPECT_NEAR(d(snub, 0, -1), 1.0, 1e-15);
  EXPECT_NEAR(d(snub, 2, 0), 1.0 * 5.5 / std::hypot(1.0, 5.5),
              1e-14);  // beside the tip edge, off the side line
  EXPECT_NEAR(snub.angle, std::atan(1.0 / 5.5) * 180.0 / M_PI, 1e-12);

  const Tool tball = morph::tapered_ball_tool(1.0, 10.0, 10.0);
  EXPECT_NEAR(d(tball, 0, -2), 2.0, 1e-15);
  EXPECT_NEAR(d(tball, 0, 1), -1.0, 1e-14);  // the ball's centre: the ball and the tangent side at 1
  // Along the tangent side's outward normal (cos 10, -sin 10) from its top end.
  const double a = 10.0 * M_PI / 180.0;
  const Vector2d top(std::cos(a) + (10.0 - 1.0 + std::sin(a)) * std::tan(a), 10.0);
  EXPECT_NEAR(tball.radius, top.x(), 1e-14);
  const Vector2d side(std::cos(a) + (6.0 - 1.0 + std::sin(a)) * std::tan(a), 6.0);
  EXPECT_NEAR(d(tball, side.x() + 0.5 * std::cos(a), side.y() - 0.5 * std::sin(a)), 0.5, 1e-12);

  const Tool spheroid = morph::spheroid_tool(2.0, 6.0);  // semi-axes 2 (r), 3 (h), centre h = 3
  EXPECT_NEAR(d(spheroid, 0, -1), 1.0, 1e-15);
  EXPECT_NEAR(d(spheroid, 3, 3), 1.0, 1e-15);
  EXPECT_NEAR(d(spheroid, 0, 3), -2.0, 1e-15);
  EXPECT_NEAR(d(spheroid, 0, 7), 1.0, 1e-15);

  const Tool sphere = morph::sphere_tool(2.0);  // the tool point is the centre
  EXPECT_NEAR(morph::tool_signed_distance(sphere, Vector3d(1, 1, 1), Vector3d(1, 1, 4)), 1.0, 1e-15);
  EXPECT_NEAR(sphere.profile.signed_distance(0.0, 2.0 + 3.0), 1.0, 1e-15);
}

TEST(ToolShapes, ProfileDistanceIsTheDistanceToItsBoundary) {
  std::mt19937_64 rng(24);
  for (const Named& shape : every_shape()) {
    const morph::ToolProfile& profile = shape.tool.profile;
    const std::vector<Vector2d> boundary = boundary_samples(profile, 20000);
    std::uniform_real_distribution<double> r(0.0, 1.5 * profile.radius()),
        h(-0.3 * profile.height(), 1.3 * profile.height());
    for (int i = 0; i < 300; ++i) {
      const Vector2d p(r(rng), h(rng));
      double nearest = std::numeric_limits<double>::infinity();
      for (const Vector2d& q : boundary) nearest = std::min(nearest, (q - p).norm());
      const double exact = profile.signed_distance(p.x(), p.y());
      // Dense samples give an upper bound of the distance within half their spacing.
      EXPECT_LE(std::abs(exact), nearest + 1e-12) << shape.name << " at " << p.transpose();
      EXPECT_GE(std::abs(exact), nearest - 2e-3) << shape.name << " at " << p.transpose();
      const bool inside = p.y() > 0 && p.y() < profile.height() && p.x() < profile.radius_at(p.y());
      if (nearest > 1e-3) {
        EXPECT_EQ(exact < 0.0, inside) << shape.name << " at " << p.transpose();
      }
    }
  }
}

TEST(ToolShapes, BallAndSphereProfilesMatchTheirClosedForms) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-8.0, 8.0);
  for (const Tool& tool : {morph::ball_tool(1.5, 6.0), morph::sphere_tool(2.0)}) {
    for (int i = 0; i < 2000; ++i) {
      const Vector3d p(u(rng), u(rng), u(rng));
      const double closed = morph::tool_signed_distance(tool, Vector3d::Zero(), p);
      const double r = std::hypot(p.x(), p.y());
      const double profile = tool.profile.signed_distance(r, p.z() + tool.profile.point_height());
      if (profile >= 0.0 || p.z() <= tool.radius || tool.type == morph::ToolType::Sphere) {
        ASSERT_NEAR(closed, profile, 1e-12) << morph::to_string(tool.type) << " at " << p.transpose();
      } else {
        // Inside the ball end above its ball's centre the closed form is the union's value:
        // the right sign, never deeper than the profile's exact distance.
        ASSERT_LT(closed, 0.0);
        ASSERT_GE(closed, profile - 1e-12);
      }
    }
  }
}

TEST(ToolShapes, VolumesAndSectionsInClosedForm) {
  const double R = 3.0, L = 8.0;
  EXPECT_NEAR(morph::flat_tool(R, L).profile.volume(), M_PI * R * R * L, 1e-12);
  EXPECT_NEAR(morph::flat_tool(R, L).profile.section_area(), 2 * R * L, 1e-12);
  EXPECT_NEAR(morph::ball_tool(R, L).profile.volume(), 2.0 / 3.0 * M_PI * R * R * R + M_PI * R * R * L,
              1e-12);
  EXPECT_NEAR(morph::ball_tool(R, L).profile.section_area(), 0.5 * M_PI * R * R + 2 * R * L, 1e-12);
  EXPECT_NEAR(morph::sphere_tool(R).profile.volume(), 4.0 / 3.0 * M_PI * R * R * R, 1e-12);
  EXPECT_NEAR(morph::conical_tool(R, 90.0, R).profile.volume(), M_PI * R * R * R / 3.0, 1e-12);
  EXPECT_NEAR(morph::conical_tool(R, 90.0, R).profile.section_area(), R * R, 1e-12);
  EXPECT_NEAR(morph::spheroid_tool(R, L).profile.volume(), 4.0 / 3.0 * M_PI * R * R * (L / 2), 1e-12);
  EXPECT_NEAR(morph::spheroid_tool(R, L).profile.section_area(), M_PI * R * (L / 2), 1e-12);
  // Frustum: pi h (r0^2 + r0 r1 + r1^2) / 3.
  EXPECT_NEAR(morph::tapered_tool(1.0, 2.0, 5.5).profile.volume(), M_PI * 5.5 * (1 + 2 + 4) / 3.0, 1e-12);
  // Bull nose: cylinder minus the corner ring's missing material (Pappus on the corner's outer
  // square minus quarter disc: area c^2 (1 - pi/4) at centroid distance from the axis).
  const double c = 1.5, R4 = 4.0, H = 9.0;
  const double missing_area = c * c * (1.0 - M_PI / 4.0);
  // Centroid of the square-minus-quarter-disc region towards the outer corner: (R - c) + c * k,
  // with k = (1/2 - 1/3 * 1/(1 - pi/4) * ... ) computed by moments about the corner centre.
  const double moment =
      c * c * c / 2.0 - c * c * c / 3.0;  // x-moment of square minus quarter disc about the centre
  const double centroid = (R4 - c) + moment / missing_area;
  EXPECT_NEAR(morph::bullnose_tool(R4, c, H).profile.volume(),
              M_PI * R4 * R4 * H - 2.0 * M_PI * centroid * missing_area, 1e-12);
  // APT with alpha = beta = 0 is the bull nose; with r = 0 and alpha = 45, a 90-degree V-bit with shank.
  EXPECT_NEAR(morph::apt_tool(8.0, 1.5, 0.0, 0.0, 9.0).profile.volume(),
              morph::bullnose_tool(4.0, 1.5, 9.0).profile.volume(), 1e-12);
  EXPECT_NEAR(morph::apt_tool(6.0, 0.0, 45.0, 0.0, 7.0).profile.volume(),
              morph::conical_tool(3.0, 90.0, 7.0).profile.volume(), 1e-12);
  const Tool apt = morph::apt_tool(8.0, 1.5, 0.0, 0.0, 9.0, 2.5, 1.5);  // e, f given and consistent
  EXPECT_NEAR(apt.apt_e, 2.5, 1e-12);
  EXPECT_NEAR(apt.apt_f, 1.5, 1e-12);
}

TEST(ToolShapes, LevelMoveDistanceIsTheProfilesSectionConvergedTo1e12) {
  // Across the middle of a long level move, the sweep's section is the tool's section through
  // its axis: the swept distance is the profile's 2D distance, reached by the 1-D search.
  std::mt19937_64 rng(3);
  for (const Named& shape : every_shape()) {
    const morph::ToolProfile& profile = shape.tool.profile;
    const double lift = profile.point_height();
    std::uniform_real_distribution<double> y(-1.4 * profile.radius(), 1.4 * profile.radius()),
        h(-0.2 * profile.height(), 1.2 * profile.height());
    for (int i = 0; i < 200; ++i) {
      const double py = y(rng), ph = h(rng);
      const Vector3d p(0.37, py, ph - lift);
      const double swept =
          morph::swept_signed_distance(shape.tool, Vector3d(-50, 0, 0), Vector3d(50, 0, 0), p);
      const double exact = profile.signed_distance(std::abs(py), ph);
      if (exact > 0.0 || shape.tool.type != morph::ToolType::BallEnd) {
        ASSERT_NEAR(swept, exact, 1e-12) << shape.name;
      } else {
        // The ball end's fast path (capsule of the ball, search over the body) is exact outside
        // the sweep, like every sweep distance; inside it is the union's value: the right sign,
        // never deeper than the truth.
        ASSERT_LE(swept, 0.0) << shape.name;
        ASSERT_GE(swept, exact - 1e-12) << shape.name;
      }
    }
  }
}

TEST(ToolShapes, RampAndHelixDistancesMatchDenseSamplingOfTheMove) {
  std::mt19937_64 rng(11);
  morph::Move helix = circle(6.0, 0.0);
  helix.sweep = 1.5 * M_PI;
  helix.end = Vector3d(0, -6.0, -2.0);
  for (const Named& shape : every_shape()) {
    std::uniform_real_distribution<double> u(-9.0, 9.0);
    for (const morph::Move& move : {line_move(Vector3d(-4, -1, 2), Vector3d(5, 3, -3)), helix}) {
      for (int i = 0; i < 12; ++i) {
        const Vector3d p(u(rng), u(rng), 0.5 * u(rng));
        double dense = std::numeric_limits<double>::infinity();
        for (int k = 0; k <= 20000; ++k)
          dense =
              std::min(dense, morph::tool_signed_distance(shape.tool, morph::point_at(move, k / 20000.0), p));
        const double exact = morph::swept_signed_distance(shape.tool, move, p);
        // Dense sampling is an upper bound within the step (the distance is 1-Lipschitz).
        const double step = morph::length(move) / 20000.0;
        EXPECT_LE(exact, dense + 1e-9) << shape.name << (move.is_arc() ? " helix" : " ramp");
        EXPECT_GE(exact, dense - step) << shape.name << (move.is_arc() ? " helix" : " ramp");
      }
    }
  }
}

TEST(ToolShapes, SingleSweepVolumesMatchCavalieriAndPappus) {
  // Level move of length D: V = V(K) + D * section area (flat: box + two half cylinders; V-bit:
  // triangular prism + two half cones; ...). Plunge of depth D: V = V(K) + D * pi R^2.
  const double D = 7.0;
  const int n = 30000;
  for (const Named& shape : every_shape()) {
    const morph::ToolProfile& profile = shape.tool.profile;
    const double R = profile.radius(), H = profile.height(), lift = profile.point_height();
    for (bool level : {true, false}) {
      const Vector3d a(0, 0, lift), b = level ? Vector3d(D, 0, lift) : Vector3d(0, 0, lift - D);
      const double expected = profile.volume() + D * (level ? profile.section_area() : M_PI * R * R);
      Eigen::AlignedBox3d box(Vector3d(-R, -R, level ? 0.0 : -D), Vector3d(level ? D + R : R, R, H));
      box.min() -= Vector3d::Constant(1e-3);
      box.max() += Vector3d::Constant(1e-3);
      const auto [volume, bound] = volume_by_sampling(
          box, [&](const Vector3d& p) { return morph::swept_signed_distance(shape.tool, a, b, p); }, n);
      EXPECT_NEAR(volume, expected, bound) << shape.name << (level ? " level" : " plunge");
    }
  }
  // The closed forms the issue names, independently of the profile's integrals.
  const double R = 3.0, L = 8.0;
  EXPECT_NEAR(morph::flat_tool(R, L).profile.volume() + D * morph::flat_tool(R, L).profile.section_area(),
              2 * R * L * D + M_PI * R * R * L, 1e-12);  // box + two half cylinders
  const Tool vbit = morph::conical_tool(R, 90.0, R);     // height R
  EXPECT_NEAR(vbit.profile.volume() + D * vbit.profile.section_area(), R * R * D + M_PI * R * R * R / 3.0,
              1e-12);  // triangular prism + two half cones
}

TEST(ToolShapes, FullCircleSweepVolumeIsPappus) {
  // A full XY circle of radius Ra >= the tool's radius sweeps 4 pi Ra * integral of r dh.
  const int n = 8000;
  for (const Tool& tool :
       {morph::flat_tool(1.0, 3.0), morph::conical_tool(1.5, 90.0, 1.5), morph::spheroid_tool(1.0, 3.0)}) {
    const double Ra = 4.0, H = tool.profile.height();
    const morph::Move move = circle(Ra, 0.0);
    const Eigen::AlignedBox3d box(Vector3d(-Ra - 1.6, -Ra - 1.6, -0.01),
                                  Vector3d(Ra + 1.6, Ra + 1.6, H + 0.01));
    const auto [volume, bound] = volume_by_sampling(
        box, [&](const Vector3d& p) { return morph::swept_signed_distance(tool, move, p); }, n);
    EXPECT_NEAR(volume, 2.0 * M_PI * Ra * tool.profile.section_area(), bound) << morph::describe(tool);
  }
}

TEST(ToolShapes, BadSizesNameTheirField) {
  EXPECT_EQ(message_of([] { morph::flat_tool(-3, 10); }), "radius: must be greater than 0, got -3");
  EXPECT_EQ(message_of([] { morph::flat_tool(3, 0); }), "length: must be greater than 0, got 0");
  EXPECT_EQ(message_of([] { morph::bullnose_tool(3, 4, 10); }),
            "corner_radius: must not exceed the radius 3, got 4");
  EXPECT_EQ(message_of([] { morph::bullnose_tool(3, -1, 10); }),
            "corner_radius: must be greater than 0, got -1");
  EXPECT_EQ(message_of([] { morph::conical_tool(3, 180, 10); }),
            "angle: must be an included angle between 0 and 180 degrees (exclusive), got 180");
  EXPECT_EQ(message_of([] { morph::conical_tool(3, 90, 2); }).substr(0, 7), "length:");
  EXPECT_EQ(message_of([] { morph::conical_tool(3, 90, 10, 3); }).substr(0, 11), "tip_radius:");
  EXPECT_EQ(message_of([] { morph::tapered_tool(2, 1, 5); }).substr(0, 7), "radius:");
  EXPECT_EQ(message_of([] { morph::tapered_ball_tool(1, 95, 5); }).substr(0, 6), "angle:");
  EXPECT_EQ(message_of([] { morph::spheroid_tool(1, std::nan("")); }),
            "length: must be a finite number, got nan");
  EXPECT_EQ(message_of([] { morph::apt_tool(8, 1, 50, 45, 10); }).substr(0, 5), "beta:");
  EXPECT_EQ(message_of([] { morph::apt_tool(8, 1, 0, 0, 10, 2.5); }).substr(0, 2), "e:");
  EXPECT_EQ(message_of([] { morph::apt_tool(2, 5, 0, 0, 10); }).substr(0, 14), "corner_radius:");
  // A raw profile that is not convex (an inward notch) or does not close on the axis.
  using P = morph::ProfilePiece;
  EXPECT_NE(message_of([] {
              morph::ToolProfile({P::segment({0, 0}, {3, 0}), P::segment({3, 0}, {1, 2}),
                                  P::segment({1, 2}, {3, 4}), P::segment({3, 4}, {0, 4})},
                                 0.0);
            }).find("not convex"),
            std::string::npos);
  EXPECT_NE(message_of([] {
              morph::ToolProfile({P::segment({0, 0}, {3, 0}), P::segment({3, 0}, {3, 4})}, 0.0);
            }).find("end on the axis"),
            std::string::npos);
}

TEST(ToolShapes, ExtentsAndNames) {
  const morph::ToolExtent sphere = morph::tool_extent(morph::sphere_tool(2.0));
  EXPECT_EQ(sphere.below, 2.0);
  EXPECT_EQ(sphere.above, 2.0);
  const morph::ToolExtent vbit = morph::tool_extent(morph::conical_tool(3.0, 90.0, 7.0));
  EXPECT_EQ(vbit.below, 0.0);
  EXPECT_NEAR(vbit.above, 7.0, 1e-15);
  EXPECT_EQ(vbit.radius, 3.0);
  EXPECT_EQ(morph::tool_type_from_string("vbit", "x"), morph::ToolType::Conical);
  EXPECT_EQ(morph::tool_type_from_string("snubnose", "x"), morph::ToolType::Tapered);
  EXPECT_EQ(morph::tool_type_from_string("ball", "x"), morph::ToolType::BallEnd);
  EXPECT_THROW(morph::tool_type_from_string("drill", "x"), morph::InputError);
  EXPECT_EQ(morph::describe(morph::bullnose_tool(5, 1, 20)),
            "bullnose diameter 10, corner radius 1, length 20");
  EXPECT_TRUE(morph::ball_tool(1, 2).sphere_or_ball_end());
  EXPECT_TRUE(morph::sphere_tool(1).sphere_or_ball_end());
  EXPECT_FALSE(morph::flat_tool(1, 2).sphere_or_ball_end());
}
