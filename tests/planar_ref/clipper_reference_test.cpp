// SPDX-License-Identifier: Apache-2.0
// The Clipper reference against the exact planar erosion: agreement within the chord tolerance,
// and convergence as the tolerance shrinks.
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/planar_deviation.h>
#include <morph/planar_erosion.h>
#include <planar_ref/clipper_reference.h>

#include <cmath>
#include <random>

#include "common/planar_shapes.h"

using morph::planar::Origin;
using morph::planar::Region;
using morph::planar::Trajectory;
using morph::planar::Vec2;
using namespace morphmill_test;

namespace {

struct Case {
  const char* name;
  Region stock;
  Trajectory moves;
  double radius;
};

std::vector<Case> cases() {
  std::vector<Case> out;
  out.push_back({"slot", rectangle(0, 0, 10, 4), polyline({{-5, 2}, {5, 2}}), 1.0});
  out.push_back({"l_slot", rectangle(0, 0, 10, 10), polyline({{2, 8}, {2, 2}, {8, 2}}), 1.0});
  Trajectory pocket{circle_move({5, 5}, 2.5, 0), circle_move({5, 5}, 1.0, 1)};
  out.push_back({"pocket", morph::planar::make_region({circle({5, 5}, 4.6)}), pocket, 1.5});
  std::vector<Vec2> zigzag;
  for (int i = 0; i <= 12; ++i) zigzag.emplace_back(i % 2 ? 9.5 : 0.5, 0.8 * i + 0.2);
  out.push_back({"zigzag", rectangle(0, 0, 10, 10), polyline(zigzag), 0.7});
  // Random chains across a plate with a round hole.
  std::mt19937 random(23);
  std::uniform_real_distribution<double> coordinate(-1.0, 11.0);
  std::vector<Vec2> walk;
  for (int i = 0; i < 40; ++i) walk.emplace_back(coordinate(random), coordinate(random));
  out.push_back(
      {"random",
       morph::planar::make_region({polygon({{0, 0}, {10, 0}, {10, 10}, {0, 10}}), circle({5, 5}, 2)}),
       polyline(walk), 0.3});
  return out;
}

}  // namespace

TEST(ClipperReference, AgreesWithTheExactErosionWithinItsChordTolerance) {
  for (const Case& c : cases()) {
    const auto exact = morph::planar::erode(c.stock, c.moves, c.radius);
    for (const double tolerance : {0.05, 0.005}) {
      planar_ref::ReferenceOptions options;
      options.chord_tolerance = tolerance;
      const auto reference = planar_ref::reference_erosion(c.stock, c.moves, c.radius, options);
      const auto deviation = morph::planar::planar_deviation(exact.region, reference.region);
      SCOPED_TRACE(std::string(c.name) + " at tolerance " + std::to_string(tolerance));
      if (std::string(c.name) != "random") {
        EXPECT_LE(deviation.hausdorff(), tolerance + 2.0 * reference.grid);
      } else {
        // Where the random walk's dilation meets the round hole at a shallow angle, displaced chords
        // move the meeting point along the boundary by up to the chord error over sin(angle / 2):
        // the boundary as a whole stays within the tolerance, those corners within a few times it.
        std::size_t beyond = 0;
        for (const auto* samples : {&deviation.a_to_b.samples, &deviation.b_to_a.samples})
          for (const auto& s : *samples) beyond += std::abs(s.distance) > tolerance + 2.0 * reference.grid;
        const std::size_t total = deviation.a_to_b.samples.size() + deviation.b_to_a.samples.size();
        EXPECT_LT(static_cast<double>(beyond), 0.002 * static_cast<double>(total));
        EXPECT_LE(deviation.hausdorff(), 2.0 * tolerance);
      }
      EXPECT_EQ(exact.region.pieces.size(), reference.region.pieces.size());
      EXPECT_EQ(morph::planar::hole_count(exact.region), morph::planar::hole_count(reference.region));
      // Inscribed chords remove less: the reference has at least the exact area, within the band.
      const double band = tolerance * morph::planar::perimeter(exact.region);
      EXPECT_NEAR(morph::planar::area(reference.region), morph::planar::area(exact.region), band);
    }
  }
}

TEST(ClipperReference, ConvergesToTheExactResultLinearlyInTheTolerance) {
  const Case c = cases()[2];  // the pocket: arcs in the moves and in the stock
  const auto exact = morph::planar::erode(c.stock, c.moves, c.radius);
  std::vector<double> deviations;
  for (const double tolerance : {0.1, 0.01, 0.001}) {
    planar_ref::ReferenceOptions options;
    options.chord_tolerance = tolerance;
    const auto reference = planar_ref::reference_erosion(c.stock, c.moves, c.radius, options);
    deviations.push_back(morph::planar::planar_deviation(exact.region, reference.region).hausdorff());
    EXPECT_LE(deviations.back(), tolerance);
    EXPECT_GE(deviations.back(), 0.1 * tolerance);  // the chords are really there
  }
  // Chord errors shrink with the tolerance (Clipper's rounded step counts make it uneven).
  EXPECT_LT(deviations[1], 0.3 * deviations[0]);
  EXPECT_LT(deviations[2], 0.3 * deviations[1]);
}

TEST(ClipperReference, DilationAgrees) {
  const Trajectory moves = polyline({{2, 8}, {2, 2}, {8, 2}});
  planar_ref::ReferenceOptions options;
  options.chord_tolerance = 0.01;
  const auto reference = planar_ref::reference_dilation(moves, 1.0, options);
  EXPECT_NEAR(morph::planar::area(reference.region), 23.0 + 1.25 * M_PI, 0.01 * (22.0 + 2.5 * M_PI));
  const auto deviation =
      morph::planar::planar_deviation(morph::planar::dilate(moves, 1.0).region, reference.region);
  EXPECT_LE(deviation.hausdorff(), 0.01);
}

TEST(ClipperReference, BadParametersAreBadInput) {
  EXPECT_THROW(planar_ref::reference_erosion(rectangle(0, 0, 1, 1), {}, 0.0), morph::InputError);
  planar_ref::ReferenceOptions options;
  options.chord_tolerance = -1.0;
  EXPECT_THROW(planar_ref::reference_erosion(rectangle(0, 0, 1, 1), {}, 1.0, options), morph::InputError);
}

TEST(ClipperReference, RandomWalksWithArcsAgreeInAreaAndPieces) {
  // Twenty random walks of segments and arcs over a plate with a round hole.
  std::size_t piece_mismatches = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> coordinate(-1.0, 11.0), unit(0.0, 1.0);
    Trajectory moves;
    Vec2 at(coordinate(random), coordinate(random));
    for (int i = 0; i < 30; ++i) {
      const Origin sweep = Origin::Sweep;
      if (unit(random) < 0.4) {
        const double r = 0.5 + 2.0 * unit(random), a0 = 2.0 * M_PI * unit(random);
        const double turn = (unit(random) < 0.5 ? -1.0 : 1.0) * (0.3 + 2.5 * unit(random));
        const Vec2 center = at - r * Vec2(std::cos(a0), std::sin(a0));
        moves.push_back(morph::planar::make_arc(center, r, a0, turn, {sweep, i, i + 1}));
        moves.back().start = at;
      } else {
        moves.push_back(
            morph::planar::make_segment(at, {coordinate(random), coordinate(random)}, {sweep, i, i + 1}));
      }
      at = moves.back().end;
    }
    const Region stock =
        morph::planar::make_region({polygon({{0, 0}, {10, 0}, {10, 10}, {0, 10}}), circle({5, 5}, 2)});
    const double radius = 0.2 + 0.3 * unit(random);
    const auto exact = morph::planar::erode(stock, moves, radius);
    planar_ref::ReferenceOptions options;
    options.chord_tolerance = 0.002;
    const auto reference = planar_ref::reference_erosion(stock, moves, radius, options);
    SCOPED_TRACE("seed " + std::to_string(seed));
    const double band = options.chord_tolerance * morph::planar::perimeter(exact.region);
    EXPECT_NEAR(morph::planar::area(reference.region), morph::planar::area(exact.region), band);
    piece_mismatches += exact.region.pieces.size() != reference.region.pieces.size();
  }
  EXPECT_EQ(piece_mismatches, 0u);
}

TEST(ClipperReference, GridAlignedWalksFullOfTiesAgree) {
  // Moves between points of a unit grid with radius 1 or 0.5: passes exactly 2r apart, passes
  // touching, retraced and reversed moves, plunges, all decided by the ties rule. The stock's edges
  // are kept off the grid: where a pass runs exactly tangent to a stock edge from inside, Clipper's
  // integer difference can join two pieces by a zero-width bridge along the edge (the closed-form
  // tests in morph cover those ties).
  for (unsigned seed = 1; seed <= 40; ++seed) {
    std::mt19937 random(seed);
    std::uniform_int_distribution<int> coordinate(-1, 9), choice(0, 9);
    Trajectory moves;
    Vec2 at(coordinate(random), coordinate(random));
    for (int i = 0; i < 25; ++i) {
      Vec2 next = at;
      const int c = choice(random);
      if (c < 2 && !moves.empty())
        next = moves.back().start;  // retrace
      else if (c < 3)
        next = at;  // plunge
      else if (c < 6)
        next = Vec2(coordinate(random), at.y());
      else if (c < 9)
        next = Vec2(at.x(), coordinate(random));
      else
        next = Vec2(coordinate(random), coordinate(random));
      moves.push_back(morph::planar::make_segment(at, next, {Origin::Sweep, i, i + 1}));
      at = next;
    }
    const Region stock = rectangle(0.3, 0.3, 7.7, 7.7);
    const double radius = seed % 2 ? 1.0 : 0.5;
    SCOPED_TRACE("seed " + std::to_string(seed));
    morph::planar::PlanarResult exact;
    ASSERT_NO_THROW(exact = morph::planar::erode(stock, moves, radius));
    planar_ref::ReferenceOptions options;
    options.chord_tolerance = 0.001;
    const auto reference = planar_ref::reference_erosion(stock, moves, radius, options);
    EXPECT_NEAR(morph::planar::area(reference.region), morph::planar::area(exact.region),
                options.chord_tolerance * (morph::planar::perimeter(exact.region) + 1.0));
    const auto deviation = morph::planar::planar_deviation(exact.region, reference.region);
    // Discs exactly tangent to each other split the material at a point: the exact result has two
    // pieces touching there, while the reference's inscribed chords leave a neck of the chord error
    // and one piece. Every extra exact piece is such a touch.
    std::size_t touching = 0;
    const auto& loops = exact.region.loops;
    for (std::size_t i = 0; i < exact.region.pieces.size(); ++i)
      for (std::size_t j = i + 1; j < exact.region.pieces.size(); ++j) {
        bool touch = false;
        for (const auto& a : loops[exact.region.pieces[i].outer].curves)
          for (const auto& b : loops[exact.region.pieces[j].outer].curves)
            touch = touch || a.start == b.start;
        touching += touch;
      }
    EXPECT_GE(exact.region.pieces.size(), reference.region.pieces.size());
    EXPECT_LE(exact.region.pieces.size(), reference.region.pieces.size() + touching);
    EXPECT_LE(deviation.hausdorff(), 2.0 * options.chord_tolerance)
        << "exact -> reference worst at (" << deviation.a_to_b.worst.point.transpose() << ") "
        << deviation.a_to_b.worst.distance << ", reference -> exact worst at ("
        << deviation.b_to_a.worst.point.transpose() << ") " << deviation.b_to_a.worst.distance;
  }
}
