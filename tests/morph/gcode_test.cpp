// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/gcode.h>
#include <morph/path.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

using Eigen::Vector3d;
using morph::GcodeOptions;
using morph::GcodeResult;
using morph::Move;
using morph::MoveKind;

namespace {

GcodeResult parse(const std::string& text, const GcodeOptions& options = {}) {
  std::istringstream in(text);
  return morph::parse_gcode(in, "test.ngc", options);
}

/// The InputError message of parsing `text`, or "" if it parsed.
std::string error_of(const std::string& text, const GcodeOptions& options = {}) {
  try {
    parse(text, options);
  } catch (const morph::InputError& e) {
    return e.what();
  }
  return "";
}

std::string data_file(const std::string& name) {
  return std::string(MORPHMILL_TEST_DATA) + "/gcode/" + name;
}

/// Checks that an arc move is the closed-form circle: every sample at `radius` from `center` in
/// the plane normal to `axis`, the axial coordinate linear in t, and the angle linear in t with
/// the move's sweep measured right-handed about `axis`.
void expect_on_circle(const Move& m, const Vector3d& center, const Vector3d& axis, double radius,
                      double sweep, double rise) {
  ASSERT_EQ(m.kind, MoveKind::Arc);
  EXPECT_NEAR((m.center - center).norm(), 0.0, 1e-12);
  EXPECT_NEAR((m.axis - axis).norm(), 0.0, 1e-15);
  EXPECT_NEAR(m.sweep, sweep, 1e-12);
  const Vector3d u = (m.start - center) / radius;
  const Vector3d v = axis.cross(u);
  for (int i = 0; i <= 16; ++i) {
    const double t = i / 16.0;
    const Vector3d expected =
        center + radius * (std::cos(t * sweep) * u + std::sin(t * sweep) * v) + t * rise * axis;
    EXPECT_NEAR((morph::point_at(m, t) - expected).norm(), 0.0, 1e-9) << "t = " << t << " line " << m.line;
  }
}

bool has_warning(const GcodeResult& r, int line, const std::string& fragment) {
  for (const morph::Warning& w : r.warnings)
    if (w.line == line && w.message.find(fragment) != std::string::npos) return true;
  return false;
}

const Vector3d kX = Vector3d::UnitX(), kY = Vector3d::UnitY(), kZ = Vector3d::UnitZ();

}  // namespace

// ---- arcs against closed form --------------------------------------------------------------------

TEST(GcodeArcs, XyQuarterCounterClockwiseAndClockwise) {
  const GcodeResult r = parse("G21 F100 G17 G90\nG0 X10 Y0 Z2\nG3 X0 Y10 I-10 J0 F100\nG2 X10 Y0 I0 J-10\n");
  ASSERT_EQ(r.path.moves.size(), 2u);
  const Move& ccw = r.path.moves[0];
  EXPECT_EQ(ccw.line, 3);
  EXPECT_EQ(ccw.end, Vector3d(0, 10, 2));
  expect_on_circle(ccw, Vector3d(0, 0, 2), kZ, 10.0, M_PI / 2, 0.0);
  // Counter-clockwise seen from +Z: the middle is at 45 degrees.
  EXPECT_NEAR((morph::point_at(ccw, 0.5) - Vector3d(10 / M_SQRT2, 10 / M_SQRT2, 2)).norm(), 0.0, 1e-12);
  const Move& cw = r.path.moves[1];
  expect_on_circle(cw, Vector3d(0, 0, 2), kZ, 10.0, -M_PI / 2, 0.0);
  EXPECT_NEAR((morph::point_at(cw, 0.5) - Vector3d(10 / M_SQRT2, 10 / M_SQRT2, 2)).norm(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(ccw.feed, 100.0);
}

TEST(GcodeArcs, ClockwiseTheLongWayIsThreeQuarters) {
  const GcodeResult r = parse("G21 F100\nG0 X10 Y0 Z0\nG2 X0 Y10 I-10 J0\n");
  ASSERT_EQ(r.path.moves.size(), 1u);
  expect_on_circle(r.path.moves[0], Vector3d::Zero(), kZ, 10.0, -3 * M_PI / 2, 0.0);
  EXPECT_NEAR((morph::point_at(r.path.moves[0], 1.0 / 3.0) - Vector3d(0, -10, 0)).norm(), 0.0, 1e-12);
}

TEST(GcodeArcs, HalfAndFullCircles) {
  const GcodeResult r = parse("G21 F100\nG0 X10 Y0 Z0\nG2 X-10 Y0 I-10\nG3 I10\nG2 X-10 Y0 I10 J0\n");
  ASSERT_EQ(r.path.moves.size(), 3u);
  // Clockwise half from +X passes through -Y.
  expect_on_circle(r.path.moves[0], Vector3d::Zero(), kZ, 10.0, -M_PI, 0.0);
  EXPECT_NEAR((morph::point_at(r.path.moves[0], 0.5) - Vector3d(0, -10, 0)).norm(), 0.0, 1e-12);
  // A centre with no axis words is a full circle back to the start.
  const Move& full = r.path.moves[1];
  EXPECT_EQ(full.start, full.end);
  expect_on_circle(full, Vector3d(0, 0, 0), kZ, 10.0, 2 * M_PI, 0.0);
  // End given explicitly equal to the start: also a full circle (clockwise).
  expect_on_circle(r.path.moves[2], Vector3d(0, 0, 0), kZ, 10.0, -2 * M_PI, 0.0);
}

TEST(GcodeArcs, ZxPlaneFollowsLinuxCncConvention) {
  // G18: first axis Z, second X; G3 turns from Z towards X, i.e. positively about +Y
  // (counter-clockwise seen from +Y), as LinuxCNC's ARC_FEED (normal +Y) does.
  const GcodeResult r = parse("G21 F100 G18\nG0 X10 Y0 Z0\nG3 X0 Z-10 I-10 K0\nG2 X10 Z0 I0 K10\n");
  ASSERT_EQ(r.path.moves.size(), 2u);
  expect_on_circle(r.path.moves[0], Vector3d::Zero(), kY, 10.0, M_PI / 2, 0.0);
  EXPECT_NEAR((morph::point_at(r.path.moves[0], 0.5) - Vector3d(10 / M_SQRT2, 0, -10 / M_SQRT2)).norm(), 0.0,
              1e-12);
  expect_on_circle(r.path.moves[1], Vector3d::Zero(), kY, 10.0, -M_PI / 2, 0.0);
  EXPECT_NEAR((morph::point_at(r.path.moves[1], 0.5) - Vector3d(10 / M_SQRT2, 0, -10 / M_SQRT2)).norm(), 0.0,
              1e-12);
}

TEST(GcodeArcs, YzPlaneTurnsAboutPlusX) {
  const GcodeResult r = parse("G21 F100 G19\nG0 X3 Y10 Z0\nG3 Y0 Z10 J-10 K0\nG2 Y0 Z-10 J0 K-10\n");
  ASSERT_EQ(r.path.moves.size(), 2u);
  expect_on_circle(r.path.moves[0], Vector3d(3, 0, 0), kX, 10.0, M_PI / 2, 0.0);
  EXPECT_NEAR((morph::point_at(r.path.moves[0], 0.5) - Vector3d(3, 10 / M_SQRT2, 10 / M_SQRT2)).norm(), 0.0,
              1e-12);
  // Clockwise half about +X from +Z goes through +Y.
  expect_on_circle(r.path.moves[1], Vector3d(3, 0, 0), kX, 10.0, -M_PI, 0.0);
  EXPECT_NEAR((morph::point_at(r.path.moves[1], 0.5) - Vector3d(3, 10, 0)).norm(), 0.0, 1e-12);
}

TEST(GcodeArcs, RadiusFormatBothSignsBothDirections) {
  const GcodeResult r = parse(
      "G21 F100\nG0 X10 Y0 Z0\n"
      "G3 X0 Y10 R10\n"     // short counter-clockwise: centre at the origin
      "G3 X10 Y0 R-10\n"    // long counter-clockwise back: centre at the origin again
      "G2 X0 Y10 R10\n"     // short clockwise: centre (10, 10)
      "G2 X10 Y0 R-10\n"    // long clockwise back: centre (10, 10)
      "G2 X-10 Y0 R10\n");  // half circle, clockwise from +X through -Y
  ASSERT_EQ(r.path.moves.size(), 5u);
  expect_on_circle(r.path.moves[0], Vector3d::Zero(), kZ, 10.0, M_PI / 2, 0.0);
  expect_on_circle(r.path.moves[1], Vector3d::Zero(), kZ, 10.0, 3 * M_PI / 2, 0.0);
  expect_on_circle(r.path.moves[2], Vector3d(10, 10, 0), kZ, 10.0, -M_PI / 2, 0.0);
  expect_on_circle(r.path.moves[3], Vector3d(10, 10, 0), kZ, 10.0, -3 * M_PI / 2, 0.0);
  expect_on_circle(r.path.moves[4], Vector3d::Zero(), kZ, 10.0, -M_PI, 0.0);
  EXPECT_NEAR((morph::point_at(r.path.moves[4], 0.5) - Vector3d(0, -10, 0)).norm(), 0.0, 1e-9);
}

TEST(GcodeArcs, RadiusFormatInOtherPlanes) {
  const GcodeResult r =
      parse("G21 F100 G18\nG0 X10 Y0 Z0\nG3 X0 Z-10 R10\nG19 G0 X0 Y10 Z0\nG2 Y0 Z10 R-10\n");
  ASSERT_EQ(r.path.moves.size(), 3u);
  expect_on_circle(r.path.moves[0], Vector3d::Zero(), kY, 10.0, M_PI / 2, 0.0);
  // G19 clockwise (negative about +X) from +Y to +Z the long way: round the origin, 270 degrees.
  expect_on_circle(r.path.moves[2], Vector3d::Zero(), kX, 10.0, -3 * M_PI / 2, 0.0);
}

TEST(GcodeArcs, HelixRiseAlongThePlaneNormal) {
  const GcodeResult r = parse("G21 F100\nG0 X5 Y0 Z0\nG3 X5 Y0 Z-3 I-5 J0 P3\nG18 G2 X-5 Y4 I-5\n");
  ASSERT_EQ(r.path.moves.size(), 2u);
  const Move& helix = r.path.moves[0];
  expect_on_circle(helix, Vector3d::Zero(), kZ, 5.0, 6 * M_PI, -3.0);
  EXPECT_NEAR((morph::point_at(helix, 1.0 / 6.0) - Vector3d(-5, 0, -0.5)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(morph::length(helix), std::hypot(6 * M_PI * 5.0, 3.0), 1e-9);
  // G18 helix: Y is the linear axis; the centre sits at the start's Y.
  const Move& side = r.path.moves[1];
  expect_on_circle(side, Vector3d(0, 0, -3), kY, 5.0, -M_PI, 4.0);
  EXPECT_NEAR((morph::point_at(side, 0.5) - Vector3d(0, 2, 2)).norm(), 0.0, 1e-12);
}

TEST(GcodeArcs, EndOffTheCircleWithinToleranceKeepsTheProgrammedEnd) {
  // 0.02 mm mismatch on a 100 mm radius: inside LinuxCNC's 0.028 mm and 0.1 %.
  const GcodeResult r = parse("G21 F100\nG0 X100 Y0 Z0\nG3 X0 Y100.02 I-100 J0\n");
  ASSERT_EQ(r.path.moves.size(), 1u);
  EXPECT_EQ(r.path.moves[0].end, Vector3d(0, 100.02, 0));
  EXPECT_EQ(morph::point_at(r.path.moves[0], 1.0), Vector3d(0, 100.02, 0));
  EXPECT_NEAR(r.path.moves[0].sweep, M_PI / 2, 1e-12);
}

TEST(GcodeArcs, RandomArcsInAllPlanesMatchClosedForm) {
  // Arcs built in closed form (plane, centre, radius, start angle, signed sweep, helix rise),
  // written as G-code with I/J/K or R in absolute or incremental axes, and read back.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int first_of[3] = {0, 2, 1}, second_of[3] = {1, 0, 2}, normal_of[3] = {2, 1, 0};
  const char* plane_code[3] = {"G17", "G18", "G19"};
  for (int k = 0; k < 600; ++k) {
    const int plane = k % 3;
    const bool radius_format = (k / 3) % 2 == 1, incremental = (k / 6) % 2 == 1;
    const Vector3d center(200 * unit(random) - 100, 200 * unit(random) - 100, 200 * unit(random) - 100);
    const double radius = 0.5 + 50 * unit(random), start_angle = 2 * M_PI * unit(random);
    // |sweep| in (0.05, 2 pi - 0.05), away from the half turn for R format where it is ill-conditioned.
    double turn = 0.05 + (2 * M_PI - 0.1) * unit(random);
    if (radius_format && std::abs(turn - M_PI) < 0.05) turn += 0.1;
    const double sweep = unit(random) < 0.5 ? turn : -turn;
    const double rise = unit(random) < 0.5 ? 0.0 : 20 * unit(random) - 10;
    const Vector3d u = Vector3d::Unit(first_of[plane]), v = Vector3d::Unit(second_of[plane]);
    const Vector3d n = Vector3d::Unit(normal_of[plane]);
    const Vector3d start = center + radius * (std::cos(start_angle) * u + std::sin(start_angle) * v);
    const Vector3d end =
        center + radius * (std::cos(start_angle + sweep) * u + std::sin(start_angle + sweep) * v) + rise * n;
    const Vector3d axis_words = incremental ? Vector3d(end - start) : end;
    char program[512];
    char centre_words[128];
    if (radius_format) {
      std::snprintf(centre_words, sizeof centre_words, "R%.12f", turn > M_PI ? -radius : radius);
    } else {
      const Vector3d offset = center - start;
      std::snprintf(centre_words, sizeof centre_words, "%c%.12f %c%.12f", "IJK"[first_of[plane]],
                    offset[first_of[plane]], "IJK"[second_of[plane]], offset[second_of[plane]]);
    }
    std::snprintf(program, sizeof program,
                  "G21 F100 G90\nG0 X%.12f Y%.12f Z%.12f\n%s %s %s X%.12f Y%.12f Z%.12f %s\n", start.x(),
                  start.y(), start.z(), incremental ? "G91" : "G90", plane_code[plane],
                  sweep > 0 ? "G3" : "G2", axis_words.x(), axis_words.y(), axis_words.z(), centre_words);
    const GcodeResult r = parse(program);
    ASSERT_EQ(r.path.moves.size(), 1u) << program;
    const Move& m = r.path.moves[0];
    ASSERT_EQ(m.kind, MoveKind::Arc) << program;
    const Vector3d axial_center = center + (start - center).dot(n) * n;  // centre in the start's plane
    EXPECT_NEAR((m.center - axial_center).norm(), 0.0, 1e-8 * radius) << program;
    EXPECT_EQ(m.axis, n) << program;
    EXPECT_NEAR(m.sweep, sweep, 1e-9) << program;
    for (int i = 0; i <= 8; ++i) {
      const double t = i / 8.0;
      const Vector3d expected =
          center + radius * (std::cos(start_angle + t * sweep) * u + std::sin(start_angle + t * sweep) * v) +
          t * rise * n;
      EXPECT_NEAR((morph::point_at(m, t) - expected).norm(), 0.0, 1e-8 * (1 + radius))
          << program << " t " << t;
    }
  }
}

// ---- modes -------------------------------------------------------------------------------------

TEST(GcodeModes, AFeedMoveWithoutAFeedRateIsReadAsProgrammedAndWarnedOnce) {
  // LinuxCNC refuses such a program; its path does not depend on the feed, so it is read, and the
  // warning (an error under --strict) names the first such line only.
  const GcodeResult r = parse("G21 G90\nG0 X0 Y0 Z1\nG1 X5\nG1 X6 F0\nG2 X10 Y0 R2\nF100 G1 X11\nM2\n");
  ASSERT_EQ(r.path.moves.size(), 4u);  // the G0 only sets the start (the start-position rule)
  EXPECT_EQ(r.path.moves[0].end, Vector3d(5, 0, 1));
  EXPECT_EQ(r.path.moves[1].end, Vector3d(6, 0, 1));
  EXPECT_EQ(r.path.moves[2].kind, MoveKind::Arc);
  EXPECT_EQ(r.path.moves[2].end, Vector3d(10, 0, 1));
  EXPECT_EQ(r.path.moves[3].end, Vector3d(11, 0, 1));
  std::size_t feed_warnings = 0;
  for (const morph::Warning& w : r.warnings)
    if (w.message.find("no feed rate") != std::string::npos) {
      ++feed_warnings;
      EXPECT_EQ(w.line, 3);
      EXPECT_NE(w.message.find("LinuxCNC refuses"), std::string::npos) << w.message;
    }
  EXPECT_EQ(feed_warnings, 1u);
  EXPECT_TRUE(parse("G21 G90 F100\nG0 X0 Y0 Z1\nG1 X5\nM2\n").warnings.empty());
}

TEST(GcodeModes, IncrementalAxesAndIncrementalCentresByDefault) {
  const GcodeResult r = parse(
      "G21 F100 G90\nG0 X0 Y0 Z5\nG91 G1 X10 F300\nY10\nG3 X-10 Y10 I-10 J0\nG1 Z-2\n"
      "G90 G90.1 G2 X10 Y10 I0 J10\nG91 G91.1 G2 X-10 Y-10 I-10 J0\n");
  ASSERT_EQ(r.path.moves.size(), 6u);
  EXPECT_EQ(r.path.moves[0].end, Vector3d(10, 0, 5));
  EXPECT_EQ(r.path.moves[1].end, Vector3d(10, 10, 5));
  expect_on_circle(r.path.moves[2], Vector3d(0, 10, 5), kZ, 10.0, M_PI / 2, 0.0);
  EXPECT_EQ(r.path.moves[2].end, Vector3d(0, 20, 5));
  EXPECT_EQ(r.path.moves[3].end, Vector3d(0, 20, 3));
  expect_on_circle(r.path.moves[4], Vector3d(0, 10, 3), kZ, 10.0, -M_PI / 2, 0.0);
  expect_on_circle(r.path.moves[5], Vector3d(0, 10, 3), kZ, 10.0, -M_PI / 2, 0.0);
  EXPECT_EQ(r.path.moves[5].end, Vector3d(0, 0, 3));
}

TEST(GcodeModes, AbsoluteCentresStayAbsoluteUnderIncrementalAxes) {
  const GcodeResult r = parse("G21 F100 G90.1\nG0 X20 Y20 Z0\nG91 G3 X-10 Y10 I10 J20\n");
  ASSERT_EQ(r.path.moves.size(), 1u);
  expect_on_circle(r.path.moves[0], Vector3d(10, 20, 0), kZ, 10.0, M_PI / 2, 0.0);
}

TEST(GcodeModes, InchProgramIntoMillimetreJob) {
  const GcodeResult r = parse("G20\nG0 X0 Y0 Z0.2\nG1 Z-0.05 F20\nX1\nG3 X2 Y1 R1\nG21 G1 X50.8 Y50.8\n");
  ASSERT_EQ(r.path.moves.size(), 4u);
  EXPECT_NEAR((r.path.moves[0].start - Vector3d(0, 0, 5.08)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((r.path.moves[0].end - Vector3d(0, 0, -1.27)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(r.path.moves[0].feed, 20 * 25.4, 1e-9);
  expect_on_circle(r.path.moves[2], Vector3d(25.4, 25.4, -1.27), kZ, 25.4, M_PI / 2, 0.0);
  EXPECT_NEAR((r.path.moves[3].end - Vector3d(50.8, 50.8, -1.27)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(r.path.moves[3].feed, 20.0, 1e-12);  // F20 is now read in mm/min
}

TEST(GcodeModes, MillimetreProgramIntoInchJob) {
  GcodeOptions options;
  options.job_units = morph::Units::Inch;
  const GcodeResult r = parse("G21 F100\nG0 X25.4 Y0 Z0\nG1 X50.8 F254\nG2 X25.4 Y0 I-12.7\n", options);
  ASSERT_EQ(r.path.moves.size(), 2u);
  EXPECT_NEAR((r.path.moves[0].end - Vector3d(2, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(r.path.moves[0].feed, 10.0, 1e-12);
  expect_on_circle(r.path.moves[1], Vector3d(1.5, 0, 0), kZ, 0.5, -M_PI, 0.0);
}

TEST(GcodeModes, ArcToleranceIsInTheProgramUnits) {
  // 0.002 inch (0.0508 mm) off on a 4-inch radius is accepted in an inch program ...
  EXPECT_EQ(error_of("G20 F10\nG0 X4 Y0 Z0\nG3 X0 Y4.002 I-4\n"), "");
  // ... while 0.04 mm is too much in a millimetre program even on a 100 mm radius,
  EXPECT_NE(error_of("G21 F100\nG0 X100 Y0 Z0\nG3 X0 Y100.04 I-100\n"), "");
  // and on a 10 mm radius the 0.1 % relative limit applies (0.02 mm > 0.01 mm).
  EXPECT_NE(error_of("G21 F100\nG0 X10 Y0 Z0\nG3 X0 Y10.02 I-10\n"), "");
  EXPECT_EQ(error_of("G21 F100\nG0 X10 Y0 Z0\nG3 X0 Y10.005 I-10\n"), "");
}

TEST(GcodeModes, PlaneAndMotionAreModal) {
  const GcodeResult r = parse("G21 F100 G18 G2\nG0 X10 Y0 Z0\nG3 X0 Z-10 I-10\nX-10 Z0 K10\n");
  ASSERT_EQ(r.path.moves.size(), 2u);
  expect_on_circle(r.path.moves[1], Vector3d::Zero(), kY, 10.0, M_PI / 2, 0.0);
}

// ---- lexical details, tools and counts ------------------------------------------------------------

TEST(GcodeLexing, CommentsLineNumbersSpacesAndCase) {
  const GcodeResult r = parse(
      "N10 G21 G0 X0 Y0 Z0 (comment with X99 and G41)\n"
      "n20 g1 x 1 0 . 5 f100 ; trailing comment X77\n"
      "(a comment line)\n"
      "\n"
      "\tN30 G1 Y-.5 (one) Z+2. (two)\r\n");
  ASSERT_EQ(r.path.moves.size(), 2u);
  EXPECT_EQ(r.path.moves[0].line, 2);
  EXPECT_EQ(r.path.moves[0].end, Vector3d(10.5, 0, 0));
  EXPECT_EQ(r.path.moves[1].line, 5);
  EXPECT_EQ(r.path.moves[1].end, Vector3d(10.5, -0.5, 2));
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.line_count, 5u);
}

TEST(GcodeLexing, PercentDelimitersAndProgramEnd) {
  const GcodeResult r = parse("%\nG21 F100 G0 X0 Y0 Z0\nG1 X1\n%\nG1 X2 garbage that is never read\n");
  ASSERT_EQ(r.path.moves.size(), 1u);
  EXPECT_TRUE(has_warning(r, 5, "ignored"));
  const GcodeResult m30 = parse("G21 F100 G0 X0 Y0 Z0\nG1 X1\nM30\nG1 X5\n");
  ASSERT_EQ(m30.path.moves.size(), 1u);
  EXPECT_TRUE(has_warning(m30, 4, "after the program end (M30)"));
}

TEST(GcodeLexing, BlockDeleteSkipsTheLineWithAWarning) {
  const GcodeResult r = parse("G21 F100 G0 X0 Y0 Z0\n/G1 X50\nG1 Y1\n");
  ASSERT_EQ(r.path.moves.size(), 1u);
  EXPECT_EQ(r.path.moves[0].end, Vector3d(0, 1, 0));
  EXPECT_TRUE(has_warning(r, 2, "block delete"));
}

TEST(GcodeLexing, WordCountsRecordCodesByNumber) {
  const GcodeResult r = parse("G21 F100 G90 G90.1\nG00 X0 Y0 Z0 S1000 M03\nG01 X1 F100\nG1 X2\nM5 M30\n");
  EXPECT_EQ(r.word_counts.at("G0"), 1);
  EXPECT_EQ(r.word_counts.at("G1"), 2);
  EXPECT_EQ(r.word_counts.at("G90.1"), 1);
  EXPECT_EQ(r.word_counts.at("M3"), 1);
  EXPECT_EQ(r.word_counts.at("M30"), 1);
  EXPECT_EQ(r.word_counts.at("X"), 3);
  EXPECT_EQ(r.word_counts.at("F"), 2);
  EXPECT_EQ(r.word_counts.at("S"), 1);
  EXPECT_EQ(r.path.moves[0].spindle, 1000.0);
}

TEST(GcodeTools, ToolChangesSetTheMoveTool) {
  GcodeOptions options;
  options.initial_tool = 7;
  const GcodeResult r =
      parse("G21 F100 G0 X0 Y0 Z0\nG1 X1\nT3\nG1 X2\nM6\nG1 X3\nT4 M6\nG1 X4\nM61 Q9\nG1 X5\n", options);
  ASSERT_EQ(r.path.moves.size(), 5u);
  EXPECT_EQ(r.path.moves[0].tool, 7);
  EXPECT_EQ(r.path.moves[1].tool, 7);  // T only selects; M6 changes
  EXPECT_EQ(r.path.moves[2].tool, 3);
  EXPECT_EQ(r.path.moves[3].tool, 4);
  EXPECT_EQ(r.path.moves[4].tool, 9);
  EXPECT_EQ(r.tools_used, (std::set<int>{3, 4, 7, 9}));
  // The initial tool counts only if it moved.
  EXPECT_EQ(parse("T2 M6\nG21 F100 G0 X0 Y0 Z0\nG1 X1\n", options).tools_used, (std::set<int>{2}));
}

TEST(GcodeModes, ComparisonsAreExactButEqualityIsWithinATenThousandth) {
  // As rs274 (LinuxCNC 2.9) evaluates them: [0.1 + 0.2] LE 0.3 is 0 (the sum is 0.30000000000000004),
  // 1 EQ 1.00009 is 1, 0 EQ 0.0001 is 0, 0.3 GE 0.30000001 is 0, 0.3 NE 0.30000001 is 0.
  const GcodeResult r = parse(
      "G21 F100 G0 X0 Y0 Z0\nG1 X[1 + [[0.1 + 0.2] LE 0.3]]\nG1 Y[1 + [1 EQ 1.00009]]\n"
      "G1 Z[1 + [0 EQ 0.0001]]\nG1 X[3 + [0.3 GE 0.30000001]]\nG1 Y[3 + [0.3 NE 0.30000001]]\n");
  ASSERT_EQ(r.path.moves.size(), 5u);
  EXPECT_EQ(r.path.moves[0].end, Vector3d(1, 0, 0));
  EXPECT_EQ(r.path.moves[1].end, Vector3d(1, 2, 0));
  EXPECT_EQ(r.path.moves[2].end, Vector3d(1, 2, 1));
  EXPECT_EQ(r.path.moves[3].end, Vector3d(3, 2, 1));
  EXPECT_EQ(r.path.moves[4].end, Vector3d(3, 3, 1));
}

TEST(GcodeModes, SpindleSynchronizedMotionIsAStraightFeed) {
  // G33 (LinuxCNC: K per spindle turn, spindle turning, no F needed): a straight line, modal.
  const GcodeResult r = parse("G21 G0 X0 Y0 Z0\nS500 M3\nG33 Z-5 K1.5\nX2 Z-6 K1.5\nG0 Z5\n");
  ASSERT_EQ(r.path.moves.size(), 3u);
  EXPECT_EQ(r.path.moves[0].kind, MoveKind::Linear);
  EXPECT_EQ(r.path.moves[0].end, Vector3d(0, 0, -5));
  EXPECT_EQ(r.path.moves[1].kind, MoveKind::Linear);
  EXPECT_EQ(r.path.moves[1].start, Vector3d(0, 0, -5));
  EXPECT_EQ(r.path.moves[1].end, Vector3d(2, 0, -6));
  EXPECT_EQ(r.path.moves[2].kind, MoveKind::Rapid);
  EXPECT_EQ(r.word_counts.at("G33"), 1);
}

TEST(GcodeStart, MovesStartOnceXyzAreKnown) {
  const GcodeResult r = parse("G21 F100\nG0 Z20\nG0 X1\nG0 Y2\nG1 Z0\n");
  ASSERT_EQ(r.path.moves.size(), 1u);
  EXPECT_EQ(r.path.moves[0].start, Vector3d(1, 2, 20));
  EXPECT_EQ(r.path.moves[0].line, 5);
  // Incremental moves from an unknown axis leave it unknown.
  EXPECT_TRUE(parse("G21 F100 G91\nG0 X1 Y1 Z1\nG0 X1\n").path.moves.empty());
}

TEST(GcodeStart, GivenStartPositionMakesTheFirstMotionAMove) {
  GcodeOptions options;
  options.start = Vector3d(0, 0, 50);
  const GcodeResult r = parse("G21 F100\nG0 X1\n", options);
  ASSERT_EQ(r.path.moves.size(), 1u);
  EXPECT_EQ(r.path.moves[0].start, Vector3d(0, 0, 50));
  EXPECT_EQ(r.path.moves[0].end, Vector3d(1, 0, 50));
  EXPECT_EQ(r.path.moves[0].kind, MoveKind::Rapid);
}

TEST(GcodeStart, HomeMakesItsAxesUnknownAgain) {
  const GcodeResult r = parse("G21 F100 G0 X0 Y0 Z5\nG1 X1\nG91 G28 Z0\nG90 G0 X5 Y5\nG0 Z1\nG1 X6\n");
  ASSERT_EQ(r.path.moves.size(), 2u);  // X1, then nothing until Z is programmed, then X6
  EXPECT_EQ(r.path.moves[1].start, Vector3d(5, 5, 1));
  EXPECT_TRUE(has_warning(r, 3, "G28"));
}

// ---- warnings ------------------------------------------------------------------------------------

TEST(GcodeWarnings, UserMCodesAndNormalOffsetsAreWarningsWithTheirLine) {
  const GcodeResult r =
      parse("G21 F100 G0 X0 Y0 Z0\nG1 X1\nM123\nG17 G2 X2 Y1 I0 J1 K2\nG43 H1 G54 G64 P0.1 G94\n");
  EXPECT_TRUE(has_warning(r, 3, "M123"));
  EXPECT_TRUE(has_warning(r, 4, "K2 ignored"));
  EXPECT_TRUE(has_warning(r, 5, "no tool table"));  // G43 H1 without a table applies 0
  for (const morph::Warning& w : r.warnings) EXPECT_EQ(w.file, "test.ngc");
  EXPECT_EQ(r.path.moves.size(), 2u);  // the warnings did not stop the moves
}

TEST(GcodeErrors, UnknownWordsCodesAndUnusedWordsAreRefusedWithTheirLine) {
  const std::string ok = "G21 F100 G0 X0 Y0 Z0\n";
  const struct {
    std::string line2;
    std::string fragment;
  } cases[] = {
      {"G1 X1 E5", "E5: nothing on this line uses it"},
      {"G12", "unsupported code G12"},
      {"M77", "unsupported code M77"},
      {"G1 X2 I4", "I4: nothing on this line uses it"},
      {"G0 X1 Q3", "Q3: nothing on this line uses it"},
      {"G4", "G4 (dwell) needs"},
  };
  for (const auto& c : cases) {
    const std::string message = error_of(ok + c.line2 + "\n");
    EXPECT_EQ(message.rfind("test.ngc:2: ", 0), 0u) << c.line2 << " -> " << message;
    EXPECT_NE(message.find(c.fragment), std::string::npos) << c.line2 << " -> " << message;
  }
}

TEST(GcodeWarnings, MissingUnitsIsNotedOnce) {
  const GcodeResult r = parse("G0 X0 Y0 Z0\nG1 X1 F100\nG1 X2\n");
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0].line, 1);
  EXPECT_NE(r.warnings[0].message.find("G20/G21"), std::string::npos);
}

TEST(GcodeTools, ToolTableLineDoesNotMove) {
  const GcodeResult r = parse("G21 F100 G0 X0 Y0 Z0\nG1 X1\nG10 L1 P1 Z1.5 R0.1\nG1 X2\n");
  ASSERT_EQ(r.path.moves.size(), 2u);
  EXPECT_EQ(r.path.moves[1].start, Vector3d(1, 0, 0));
  EXPECT_TRUE(r.warnings.empty());
}

// ---- errors --------------------------------------------------------------------------------------

TEST(GcodeErrors, EveryErrorNamesFileAndLine) {
  const std::string ok = "G21 F100 G0 X10 Y0 Z0\n";  // line 1
  const struct {
    std::string line2;
    std::string fragment;
  } cases[] = {
      {"G1 X", "the letter X has no number"},
      {"G1 X-", "malformed number after X"},
      {"G1 X1.2.3", "malformed number after X"},
      {"G1 X.", "malformed number after X"},
      {"G X1", "the letter G has no number"},
      {"G1.55 X1", "malformed code G1.55"},
      {"G1 X1 $", "unexpected character '$'"},
      {"G1 X1 X2", "two X words"},
      {"G0 G1 X1", "two motion codes"},
      {"G20 G21", "two units codes"},
      {"#1 = [2", "not closed with ']'"},
      {"G1 X[1+]", "has no number"},
      {"G1 X#<nope>", "#<nope> is not defined"},
      {"G1 X[1/0]", "division by zero"},
      {"o100 sub", "never closed"},
      {"o100 endwhile", "without a matching o100 while"},
      {"o100 call", "no o100 sub in this file"},
      {"o[#1] call", "computed O-word labels"},
      {"G2 X0 Y10", "neither an I/J/K centre nor an R radius"},
      {"G3 X0 Y10.5 I-10", "not on its circle"},
      {"G3 X10 Y0 R5", "ends where it starts"},
      {"G3 X-10 Y0 R4", "too small to reach"},
      {"G3 X0 Y10 R10 I-10", "both R and an I/J/K"},
      {"G3 X10 Y0 I0 J0", "zero-radius"},
      {"G90.1 G3 X0 Y10 I0", "needs both I and J"},
      {"G3 X0 Y10 I-10 P1.5", "positive integer"},
      {"G41 D1", "cutter radius compensation"},
      {"G42.1 D6", "cutter radius compensation"},
      {"G81 X1 Y1 Z-1", "needs R"},
      {"G81 X1 Y1 Z1 R0", "is below the bottom"},
      {"G88 X1 Y1 Z-1 R1", "G88"},
      {"G92", "needs at least one axis word"},
      {"G91 G53 G0 Z0", "G53"},
      {"G53 G2 X0 Y10 R5", "G53"},
      {"G5.1 X1 I1 J1", "spline"},
      {"G10 L2 P1 R10 X0", "rotation"},
      {"G10 L5 P1 X0", "G10 needs L1"},
      {"G43 H1.5", "H must be an integer"},
      {"G38.2 Z-5 F10", "probing"},
      {"G33 Z-1 K1", "spindle not turning"},
      {"M3 S100 G33 Z-1", "G33 needs K"},
      {"G33.1 Z-1 K1", "threading"},
      {"G68 X0 Y0 R45", "rotation"},
      {"G51 X2", "scaling"},
      {"G16", "polar"},
      {"G7", "diameter"},
      {"G70 P10 Q20", "lathe cycle (G70)"},
      {"G72 P10 Q20 D0.5", "lathe cycle (G72)"},
      {"G2 K5", "has only K"},
      {"G1 X1 A10", "axis A is not supported"},
      {"G1 X1 (unfinished comment", "not closed"},
      {"G1 X1 (nested (comment))", "nested"},
      {"G1 X1 )", "')' without"},
      {"G1 X1 / Y2", "block delete"},
      {"M98 P100", "subprogram"},
      {"M72", "no state saved"},
      {"G1 X1 @2", "cannot be used with polar"},
      {"G0 G1 G80 X1", "two motion codes"},
      {"T1.5 M6", "T must be an integer"},
  };
  for (const auto& c : cases) {
    const std::string message = error_of(ok + c.line2 + "\n");
    EXPECT_EQ(message.rfind("test.ngc:2: ", 0), 0u) << c.line2 << " -> " << message;
    EXPECT_NE(message.find(c.fragment), std::string::npos) << c.line2 << " -> " << message;
  }
  // After G80 cancels the motion mode, axis words have nothing to do.
  const std::string cancelled = error_of(ok + "G80\nX5\n");
  EXPECT_EQ(cancelled.rfind("test.ngc:3: ", 0), 0u) << cancelled;
  EXPECT_NE(cancelled.find("no motion mode"), std::string::npos) << cancelled;
}

TEST(GcodeErrors, ArcBeforeThePositionIsKnown) {
  const std::string message = error_of("G21 F100\nG0 X0 Y0\nG2 X1 Y1 I1\n");
  EXPECT_EQ(message.rfind("test.ngc:3: ", 0), 0u) << message;
  EXPECT_NE(message.find("unknown position"), std::string::npos) << message;
}

TEST(GcodeErrors, AxisWordsWithNoMotionModeAtTheStart) {
  const std::string message = error_of("G21 F100\nX1 Y2 Z3\n");
  EXPECT_EQ(message.rfind("test.ngc:2: ", 0), 0u) << message;
}

TEST(GcodeErrors, ArbitraryLinesEitherParseOrRaiseInputError) {
  // Lines of random G-code-ish characters: each program must either parse into finite moves or
  // throw InputError (any other exception fails the test), never crash.
  std::mt19937 random(20261122);
  const std::string alphabet = "GGXYZIJKRPMFTNAE0123456789.-+ ()%;/#[";
  std::uniform_int_distribution<std::size_t> pick(0, alphabet.size() - 1), length(0, 24);
  int parsed = 0, rejected = 0;
  for (int k = 0; k < 3000; ++k) {
    std::string line;
    for (std::size_t n = length(random); n > 0; --n) line += alphabet[pick(random)];
    try {
      const GcodeResult r = parse("G21 F100 G0 X1 Y2 Z3\nG1 X4\n" + line + "\nG1 X5\n");
      ++parsed;
      for (const Move& m : r.path.moves) {
        ASSERT_TRUE(m.start.allFinite() && m.end.allFinite() && m.center.allFinite() &&
                    std::isfinite(m.sweep))
            << line;
      }
    } catch (const morph::InputError& e) {
      ++rejected;
      EXPECT_EQ(std::string(e.what()).rfind("test.ngc:3: ", 0), 0u) << line << " -> " << e.what();
    }
  }
  EXPECT_GT(parsed, 100);
  EXPECT_GT(rejected, 100);
}

TEST(GcodeErrors, MissingFileIsAnIoError) {
  EXPECT_THROW(morph::read_gcode(data_file("does_not_exist.ngc")), morph::IoError);
}

// ---- the bundled hand-made programs (never skipped) --------------------------------------------------

TEST(GcodeDataFiles, ArcsInThreePlanes) {
  const GcodeResult r = morph::read_gcode(data_file("arcs_three_planes.ngc"));
  ASSERT_EQ(r.path.moves.size(), 11u);
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.path.source, data_file("arcs_three_planes.ngc"));
  const auto& m = r.path.moves;
  expect_on_circle(m[0], Vector3d::Zero(), kZ, 10, M_PI / 2, 0);
  EXPECT_EQ(m[0].line, 5);
  expect_on_circle(m[1], Vector3d::Zero(), kZ, 10, -M_PI / 2, 0);
  expect_on_circle(m[2], Vector3d::Zero(), kY, 10, M_PI / 2, 0);
  EXPECT_EQ(m[2].end, Vector3d(0, 0, -10));
  expect_on_circle(m[3], Vector3d::Zero(), kY, 10, -M_PI / 2, 0);
  EXPECT_EQ(m[4].kind, MoveKind::Rapid);
  expect_on_circle(m[5], Vector3d::Zero(), kX, 10, M_PI / 2, 0);
  EXPECT_EQ(m[5].end, Vector3d(0, 0, 10));
  expect_on_circle(m[6], Vector3d::Zero(), kX, 10, -M_PI / 2, 0);
  expect_on_circle(m[7], Vector3d::Zero(), kZ, 10, -2 * M_PI, 0);
  expect_on_circle(m[8], Vector3d::Zero(), kZ, 10, M_PI / 2, 0);
  expect_on_circle(m[9], Vector3d::Zero(), kZ, 10, 3 * M_PI / 2, 0);
  expect_on_circle(m[10], Vector3d::Zero(), kZ, 10, -M_PI, 0);
  EXPECT_NEAR((morph::point_at(m[10], 0.5) - Vector3d(10, 0, 0)).norm(), 0.0, 1e-9);
  for (const Move& move : m) EXPECT_DOUBLE_EQ(move.feed, 200.0);
}

TEST(GcodeDataFiles, Helix) {
  const GcodeResult r = morph::read_gcode(data_file("helix.ngc"));
  ASSERT_EQ(r.path.moves.size(), 5u);
  const auto& m = r.path.moves;
  EXPECT_EQ(m[0].kind, MoveKind::Linear);
  expect_on_circle(m[1], Vector3d::Zero(), kZ, 5, 6 * M_PI, -3);
  expect_on_circle(m[2], Vector3d(0, 0, -3), kZ, 5, 2 * M_PI, -1);
  expect_on_circle(m[3], Vector3d(0, 0, -4), kY, 5, -M_PI, 4);
  EXPECT_NEAR((morph::point_at(m[3], 0.5) - Vector3d(0, 2, 1)).norm(), 0.0, 1e-12);
  EXPECT_EQ(m[4].end, Vector3d(-5, 4, 5));
}

TEST(GcodeDataFiles, Incremental) {
  const GcodeResult r = morph::read_gcode(data_file("incremental.ngc"));
  ASSERT_EQ(r.path.moves.size(), 7u);
  const auto& m = r.path.moves;
  expect_on_circle(m[2], Vector3d(0, 10, 5), kZ, 10, M_PI / 2, 0);
  expect_on_circle(m[4], Vector3d(0, 10, 3), kZ, 10, -M_PI / 2, 0);
  expect_on_circle(m[5], Vector3d(0, 10, 3), kZ, 10, -M_PI / 2, 0);
  EXPECT_EQ(m[6].end, Vector3d(0, 0, 5));
}

TEST(GcodeDataFiles, InchIntoBothJobUnits) {
  const GcodeResult mm = morph::read_gcode(data_file("inch.ngc"));
  GcodeOptions options;
  options.job_units = morph::Units::Inch;
  const GcodeResult inch = morph::read_gcode(data_file("inch.ngc"), options);
  ASSERT_EQ(mm.path.moves.size(), 4u);
  ASSERT_EQ(inch.path.moves.size(), 4u);
  expect_on_circle(inch.path.moves[2], Vector3d(1, 1, -0.05), kZ, 1.0, M_PI / 2, 0.0);
  expect_on_circle(mm.path.moves[2], Vector3d(25.4, 25.4, -1.27), kZ, 25.4, M_PI / 2, 0.0);
  for (std::size_t i = 0; i < 4; ++i)
    EXPECT_NEAR((mm.path.moves[i].end - 25.4 * inch.path.moves[i].end).norm(), 0.0, 1e-12);
  EXPECT_NEAR((inch.path.moves[3].end - Vector3d(2, 2, -0.05)).norm(), 0.0, 1e-12);
}

TEST(GcodeDataFiles, TruncatedInsideACommentNamesFileAndLine) {
  const std::string path = data_file("truncated_comment.ngc");
  try {
    morph::read_gcode(path);
    FAIL() << "no error";
  } catch (const morph::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ":4: ", 0), 0u) << e.what();
    EXPECT_NE(std::string(e.what()).find("not closed"), std::string::npos) << e.what();
  }
}

TEST(GcodeDataFiles, RadiusMismatchNamesFileAndLine) {
  const std::string path = data_file("radius_mismatch.ngc");
  try {
    morph::read_gcode(path);
    FAIL() << "no error";
  } catch (const morph::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ":3: ", 0), 0u) << e.what();
  }
}

TEST(GcodeDataFiles, Bundled3DChipsMatchesItsStock) {
  const GcodeResult r = morph::read_gcode(data_file("3D_Chips.ngc"));
  EXPECT_EQ(r.line_count, 4701u);
  // 4,695 N-numbered lines; the first motions only establish the position.
  EXPECT_EQ(r.path.moves.size(), 4682u);
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.tools_used, (std::set<int>{1}));
}

// ---- the real programs in ../shared/gcode (skipped if absent) ----------------------------------------

namespace {

struct Bounds {
  Vector3d lo = Vector3d::Constant(1e300), hi = Vector3d::Constant(-1e300);
  void add(const Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
};

GcodeResult read_shared(const std::string& name) {
  const std::string path = std::string(MORPHMILL_SHARED_DIR) + "/gcode/" + name;
  if (!std::ifstream(path)) return {};
  return morph::read_gcode(path);
}

}  // namespace

TEST(GcodeRealFiles, Bear) {
  const GcodeResult r = read_shared("bear.nc");
  if (r.line_count == 0) GTEST_SKIP() << "shared gcode not found at " << MORPHMILL_SHARED_DIR;
  EXPECT_EQ(r.line_count, 15163u);
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(r.tools_used, (std::set<int>{1}));
  std::size_t linear = 0;
  Bounds cut;
  for (const Move& m : r.path.moves) {
    EXPECT_NE(m.kind, MoveKind::Arc);
    if (m.kind != MoveKind::Linear) continue;
    ++linear;
    cut.add(m.start);
    cut.add(m.end);
    EXPECT_DOUBLE_EQ(m.feed, 6000.0);
  }
  EXPECT_EQ(linear, 15152u);
  EXPECT_EQ(r.path.moves.size(), 15155u);
  // Stock (0,0,-20)-(80,80,0): the cutting moves stay inside it in x, y; the only G1 above
  // the top is the first plunge from the z=10 approach.
  EXPECT_GE(cut.lo.x(), 0.0);
  EXPECT_LE(cut.hi.x(), 80.0);
  EXPECT_GE(cut.lo.y(), 0.0);
  EXPECT_LE(cut.hi.y(), 80.0);
  EXPECT_NEAR(cut.lo.z(), -17.368, 1e-12);
  EXPECT_NEAR(cut.hi.z(), 10.0, 1e-12);
}

TEST(GcodeRealFiles, Cameo) {
  const GcodeResult r = read_shared("cameo.nc");
  if (r.line_count == 0) GTEST_SKIP() << "shared gcode not found at " << MORPHMILL_SHARED_DIR;
  EXPECT_EQ(r.line_count, 35288u);
  EXPECT_EQ(r.path.moves.size(), 35280u);
  EXPECT_EQ(r.tools_used, (std::set<int>{1}));
  EXPECT_EQ(r.word_counts.at("G43"), 1);
  // The closing '%' after M30 is not content; G43 H1 without a tool table applies offset 0.
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_NE(r.warnings[0].message.find("G43 H1: no tool table"), std::string::npos);
  Bounds all;
  for (const Move& m : r.path.moves) {
    all.add(m.start);
    all.add(m.end);
  }
  // Stock (-83.6,-104.153,-7)-(83.6,103.747,0); the moves reach 2 mm above it.
  EXPECT_NEAR((all.lo - Vector3d(-75, -93.703, -6)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((all.hi - Vector3d(75, 93.297, 2)).norm(), 0.0, 1e-12);
}

TEST(GcodeRealFiles, ThreeDChips) {
  const GcodeResult r = read_shared("3D_Chips.ngc");
  if (r.line_count == 0) GTEST_SKIP() << "shared gcode not found at " << MORPHMILL_SHARED_DIR;
  EXPECT_EQ(r.path.moves.size(), 4682u);
  Bounds cut;
  for (const Move& m : r.path.moves)
    if (m.kind == MoveKind::Linear) {
      cut.add(m.start);
      cut.add(m.end);
    }
  // Stock (-50,-50,-50)-(50,50,0) with a 10 mm ball: the tip path runs up to 3 mm (x) and
  // 6.128 mm (y) outside the block so the ball finishes its sides, and no deeper than -30.5.
  EXPECT_NEAR((cut.lo - Vector3d(-52, -56.128, -30.5)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((cut.hi - Vector3d(53, 56.128, 10)).norm(), 0.0, 1e-12);
}

// ---- the LinuxCNC dialect: bounds, tools, machine set-up -------------------------------------

TEST(GcodeControlFlow, EndlessLoopsAndRecursionAreBoundedWithAClearError) {
  GcodeOptions options;
  options.max_loop_iterations = 1000;
  const std::string endless = error_of("G21 F100\no1 while [1]\no1 endwhile\nM2\n", options);
  EXPECT_EQ(endless.rfind("test.ngc:3: ", 0), 0u) << endless;
  EXPECT_NE(endless.find("loop ran 1000 times"), std::string::npos) << endless;
  options.max_blocks = 500;
  options.max_loop_iterations = 1'000'000;
  const std::string long_run =
      error_of("G21 F100\n#1=0\no1 while [#1 LT 1000]\n#1=[#1+1]\no1 endwhile\nM2\n", options);
  EXPECT_NE(long_run.find("max_blocks"), std::string::npos) << long_run;
  // Lines run once do not count: a straight program longer than the bound is read whole (the G0
  // only sets the start, each G1 is a move).
  std::string straight = "G21 F100\nG0 X0 Y0 Z0\n";
  for (int i = 0; i < 600; ++i) straight += i % 2 ? "\n" : "G1 X" + std::to_string(i + 1) + "\n";
  std::istringstream straight_in(straight + "M2\n");
  EXPECT_EQ(morph::parse_gcode(straight_in, "straight.ngc", options).path.moves.size(), 300u);
  const std::string recursion = error_of("o<r> sub\no<r> call\no<r> endsub\no<r> call\nM2\n");
  EXPECT_EQ(recursion.rfind("test.ngc:2: ", 0), 0u) << recursion;
  EXPECT_NE(recursion.find("nested deeper than 10"), std::string::npos) << recursion;
}

TEST(GcodeTools, BareTOnlyPreparesAndIsWarnedWhenItNeverReachesTheSpindle) {
  GcodeOptions options;
  options.initial_tool = 1;
  options.tools = {{1, {}}, {2, {}}};
  const GcodeResult r = parse("G21 F100 G0 X0 Y0 Z0\nT2\nG1 X1\nT7 M6\nG1 X2\n", options);
  ASSERT_EQ(r.path.moves.size(), 2u);
  EXPECT_EQ(r.path.moves[0].tool, 1);  // T2 alone does not change the tool
  EXPECT_EQ(r.path.moves[1].tool, 7);
  EXPECT_TRUE(has_warning(r, 2, "T2 is selected but never put in the spindle"));
  EXPECT_TRUE(has_warning(r, 4, "T7 selects a tool that is not in the tool table"));
  // A controller that changes tools on T.
  options.tool_change_on_t = true;
  const GcodeResult t = parse("G21 F100 G0 X0 Y0 Z0\nT2\nG1 X1\n", options);
  ASSERT_EQ(t.path.moves.size(), 1u);
  EXPECT_EQ(t.path.moves[0].tool, 2);
  EXPECT_TRUE(t.warnings.empty());
}

TEST(GcodeTools, ToolLengthOffsetsFromTheTableMoveTheTipAsOnTheMachine) {
  GcodeOptions options;
  options.initial_tool = 1;
  options.tools[1].length_offset = 50.0;  // the tool is 50 long: without G43 its tip is 50 lower
  const GcodeResult r = parse("G21 F100 G0 X0 Y0 Z100\nG1 Z60\nG43 H1\nG1 Z5\nG49\nG1 X1\nG1 Z5\n", options);
  ASSERT_EQ(r.path.moves.size(), 4u);
  EXPECT_EQ(r.path.moves[0].end, Vector3d(0, 0, 10));    // Z60 less the 50 long tool
  EXPECT_EQ(r.path.moves[1].start, Vector3d(0, 0, 10));  // G43 did not move the machine
  EXPECT_EQ(r.path.moves[1].end, Vector3d(0, 0, 5));     // with G43 H1, Z5 is the tip
  EXPECT_EQ(r.path.moves[2].end, Vector3d(1, 0, 5));     // G49 does not move it either
  EXPECT_EQ(r.path.moves[3].end, Vector3d(1, 0, -45));   // but Z5 is the gauge line again
  EXPECT_TRUE(has_warning(r, 2, "no G43"));
  EXPECT_EQ(r.path.moves[0].line, 2);
  EXPECT_NE(error_of("G21 F100\nG43 H3\n", options).find("tool 3 is not in the tool table"),
            std::string::npos);
}

TEST(GcodeTools, AProgramThatNeverUsesG43IsTouchedOffWithTheToolThatCutsFirst) {
  GcodeOptions options;
  options.initial_tool = 1;
  options.tools[1].length_offset = 50.0;
  options.tools[2].length_offset = 30.0;
  // One tool, no G43: its tip is at the programmed point, not 50 lower.
  const GcodeResult one = parse("G21 F100 G0 X0 Y0 Z10\nG1 Z-1\nG1 X5\n", options);
  ASSERT_EQ(one.path.moves.size(), 2u);
  EXPECT_EQ(one.path.moves[0].start, Vector3d(0, 0, 10));
  EXPECT_EQ(one.path.moves[0].end, Vector3d(0, 0, -1));
  EXPECT_EQ(one.path.moves[1].end, Vector3d(5, 0, -1));
  EXPECT_TRUE(one.warnings.empty());
  // A second tool 20 shorter, still no G43: the same gauge line puts its tip 20 higher, as on the
  // machine; warned where it starts to move.
  const GcodeResult two = parse("G21 F100 G0 X0 Y0 Z10\nG1 Z-1\nT2 M6\nG1 X5\nG0 Z10\n", options);
  ASSERT_EQ(two.path.moves.size(), 3u);
  EXPECT_EQ(two.path.moves[0].end, Vector3d(0, 0, -1));
  EXPECT_EQ(two.path.moves[1].start, Vector3d(0, 0, 19));
  EXPECT_EQ(two.path.moves[1].end, Vector3d(5, 0, 19));
  EXPECT_EQ(two.path.moves[2].end, Vector3d(5, 0, 30));
  EXPECT_TRUE(has_warning(two, 4, "its tip runs 20 above the programmed point"));
  EXPECT_FALSE(has_warning(two, 2, "tip runs"));
  // Rapids before the first cut do not choose the tool: tool 0 (length 0) rapids, tool 1 cuts.
  options.initial_tool = 0;
  const GcodeResult first = parse("G21 F100 G0 X0 Y0 Z10\nG0 Z5\nT1 M6\nG1 Z-1\n", options);
  ASSERT_EQ(first.path.moves.size(), 2u);
  EXPECT_EQ(first.path.moves[0].end, Vector3d(0, 0, 55));  // tool 0's "tip" is the gauge line
  EXPECT_EQ(first.path.moves[1].end, Vector3d(0, 0, -1));
  // The same cut with G43 H1: the work offsets are from the gauge line and the tip is at Z-1.
  const GcodeResult compensated = parse("G21 F100 G0 X0 Y0 Z10\nT1 M6\nG43 H1\nG1 Z-1\n", options);
  ASSERT_EQ(compensated.path.moves.size(), 1u);
  EXPECT_EQ(compensated.path.moves[0].start, Vector3d(0, 0, -40));  // gauge at 10, tip 50 below
  EXPECT_EQ(compensated.path.moves[0].end, Vector3d(0, 0, -1));
  // G43.1 with the tool's own length is the same offset; G43.1 with less leaves the tip lower.
  const GcodeResult dynamic = parse("G21 F100 G0 X0 Y0 Z10\nT1 M6\nG43.1 Z45\nG1 Z-1\n", options);
  ASSERT_EQ(dynamic.path.moves.size(), 1u);
  EXPECT_EQ(dynamic.path.moves[0].end, Vector3d(0, 0, -6));
}

TEST(GcodeMachineSetup, WorkOffsetsAndVarFile) {
  const std::string var = testing::TempDir() + "gcode_setup.var";
  {
    std::ofstream out(var);
    out << "5220\t2.000000\n5241\t5.000000\n5242\t6.000000\n5243\t7.000000\n5161\t1.0\n5162\t2.0\n5163\t3."
           "0\n";
  }
  GcodeOptions options;
  options.var_file = var;
  options.start = Vector3d::Zero();
  // The var file makes G55 active, with its offsets, and gives the G28 position.
  const GcodeResult r = parse("G21 F100\nG0 X0 Y0 Z0\nG28\n", options);
  ASSERT_EQ(r.path.moves.size(), 2u);
  EXPECT_EQ(r.path.moves[0].end, Vector3d(5, 6, 7));
  EXPECT_EQ(r.path.moves[1].end, Vector3d(1, 2, 3));
  // The job's work offsets override the var file's.
  options.work_offsets[2] = Vector3d(-1, -1, -1);
  EXPECT_EQ(parse("G21 F100\nG0 X0 Y0 Z0\n", options).path.moves[0].end, Vector3d(-1, -1, -1));
  options.var_file = testing::TempDir() + "no_such.var";
  EXPECT_THROW(parse("G21\n", options), morph::IoError);
}

TEST(GcodeErrors, DeepExpressionsAreRefusedNotACrash) {
  const std::string deep =
      "G21 F100 G0 X0 Y0 Z0\nG1 X" + std::string(100000, '[') + "1" + std::string(100000, ']') + "\n";
  EXPECT_NE(error_of(deep).find("test.ngc:2: expression nested more than 256 deep"), std::string::npos);
  const std::string minus = "G21 F100 G0 X0 Y0 Z0\nG1 X" + std::string(100000, '-') + "#1\n";
  EXPECT_NE(error_of(minus).find("nested more than 256 deep"), std::string::npos);
}

TEST(GcodeErrors, CutterCompensationIsRefusedNamingTheLine) {
  for (const std::string code : {"G41", "G42", "G41.1 D2", "G42.1 D2"}) {
    const std::string message = error_of("G21 F100 G0 X0 Y0 Z0\nG1 X1\n" + code + "\nG1 X5\n");
    EXPECT_EQ(message.rfind("test.ngc:3: ", 0), 0u) << code << " -> " << message;
    EXPECT_NE(message.find("cutter radius compensation"), std::string::npos) << message;
  }
}
