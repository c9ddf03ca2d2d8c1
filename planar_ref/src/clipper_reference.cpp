// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <planar_ref/clipper_reference.h>

#include <algorithm>
#include <chrono>
#include <clipper.hpp>
#include <cmath>
#include <sstream>

namespace planar_ref {

namespace {

using morph::planar::Curve;
using morph::planar::Vec2;

/// Clipper works on integers: one unit is 1/1000 of the chord tolerance, unless the job's extent
/// would leave Clipper's range.
double choose_scale(const morph::planar::Box2& extent, double chord_tolerance) {
  const double reach = std::max(extent.min().cwiseAbs().maxCoeff(), extent.max().cwiseAbs().maxCoeff());
  return std::min(1000.0 / chord_tolerance, 1e15 / std::max(reach, 1e-300));
}

ClipperLib::IntPoint to_int(const Vec2& p, double scale) {
  return ClipperLib::IntPoint(static_cast<ClipperLib::cInt>(std::llround(p.x() * scale)),
                              static_cast<ClipperLib::cInt>(std::llround(p.y() * scale)));
}

/// Appends the curve's points after its start: inscribed chords within `tolerance` for an arc.
void flatten(const Curve& c, double tolerance, double scale, ClipperLib::Path& out) {
  if (c.is_arc()) {
    const double step = tolerance < c.radius ? 2.0 * std::acos(1.0 - tolerance / c.radius) : 2.0 * M_PI / 3.0;
    const int n = std::max(1, static_cast<int>(std::ceil(std::abs(c.sweep) / step)));
    for (int i = 1; i < n; ++i)
      out.push_back(to_int(morph::planar::point_at(c, static_cast<double>(i) / n), scale));
  }
  out.push_back(to_int(c.end, scale));
}

ClipperLib::Paths stock_polygons(const morph::planar::Region& stock, double tolerance, double scale) {
  ClipperLib::Paths paths;
  for (const auto& loop : stock.loops) {
    ClipperLib::Path path;
    for (const Curve& c : loop.curves) flatten(c, tolerance, scale, path);
    paths.push_back(std::move(path));
  }
  return paths;
}

/// The union of the moves' dilations: chains of connected moves offset with round joins and ends.
ClipperLib::Paths dilation_polygons(const morph::planar::Trajectory& moves, double radius, double tolerance,
                                    double scale) {
  ClipperLib::Paths chains;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    if (i == 0 || (moves[i].start - moves[i - 1].end).norm() * scale > 0.5) {
      chains.emplace_back();
      chains.back().push_back(to_int(moves[i].start, scale));
    }
    flatten(moves[i], 0.5 * tolerance, scale, chains.back());
  }
  for (ClipperLib::Path& chain : chains) chain.erase(std::unique(chain.begin(), chain.end()), chain.end());
  ClipperLib::ClipperOffset offset;
  // Clipper rounds the number of steps of each round join or end, which can make a chord's sagitta
  // up to 2.25 times its ArcTolerance: asking for 0.2 of this half keeps it within 0.45.
  offset.ArcTolerance = 0.2 * tolerance * scale;
  offset.AddPaths(chains, ClipperLib::jtRound, ClipperLib::etOpenRound);
  ClipperLib::Paths result;
  offset.Execute(result, radius * scale);
  return result;
}

/// Removes zero-width spikes (a vertex where the boundary folds back on itself), decided exactly on
/// Clipper's integers: where the tool's side runs exactly along a stock edge, the difference can
/// keep them, and the regularized result has none.
void remove_spikes(ClipperLib::Path& path) {
  for (bool changed = true; changed && path.size() >= 3;) {
    changed = false;
    for (std::size_t i = 0; i < path.size() && path.size() >= 3; ++i) {
      const ClipperLib::IntPoint& a = path[(i + path.size() - 1) % path.size()];
      const ClipperLib::IntPoint& b = path[i];
      const ClipperLib::IntPoint& c = path[(i + 1) % path.size()];
      const __int128 ux = b.X - a.X, uy = b.Y - a.Y, vx = c.X - b.X, vy = c.Y - b.Y;
      const bool fold = ux * vy - uy * vx == 0 && ux * vx + uy * vy <= 0;
      if (fold) {
        path.erase(path.begin() + static_cast<long>(i));
        changed = true;
      }
    }
  }
}

ReferenceResult to_result(ClipperLib::Paths paths, double scale) {
  for (ClipperLib::Path& path : paths) remove_spikes(path);
  ReferenceResult result;
  std::vector<morph::planar::Loop> loops;
  for (const ClipperLib::Path& path : paths) {
    if (path.size() < 3) continue;
    morph::planar::Loop loop;
    for (std::size_t i = 0; i < path.size(); ++i) {
      const ClipperLib::IntPoint& a = path[i];
      const ClipperLib::IntPoint& b = path[(i + 1) % path.size()];
      loop.curves.push_back(
          morph::planar::make_segment(Vec2(static_cast<double>(a.X), static_cast<double>(a.Y)) / scale,
                                      Vec2(static_cast<double>(b.X), static_cast<double>(b.Y)) / scale));
    }
    result.vertices += path.size();
    loops.push_back(std::move(loop));
  }
  result.region = morph::planar::group_pieces(std::move(loops));
  result.grid = 1.0 / scale;
  return result;
}

void check(double radius, const ReferenceOptions& options) {
  std::ostringstream message;
  if (!(radius > 0.0) || !std::isfinite(radius))
    message << "reference: the tool radius must be positive, got " << radius;
  if (!(options.chord_tolerance > 0.0) || !std::isfinite(options.chord_tolerance))
    message << "reference: the chord tolerance must be positive, got " << options.chord_tolerance;
  if (!message.str().empty()) throw morph::InputError(message.str());
}

}  // namespace

ReferenceResult reference_erosion(const morph::planar::Region& stock, const morph::planar::Trajectory& moves,
                                  double radius, const ReferenceOptions& options) {
  check(radius, options);
  const auto started = std::chrono::steady_clock::now();
  const double scale =
      choose_scale(morph::planar::bounds(stock).extend(Vec2::Zero()), options.chord_tolerance);
  ClipperLib::Clipper clipper;
  // Pieces touching at a point are separate pieces, as in the exact result.
  clipper.StrictlySimple(true);
  clipper.AddPaths(stock_polygons(stock, options.chord_tolerance, scale), ClipperLib::ptSubject, true);
  clipper.AddPaths(dilation_polygons(moves, radius, options.chord_tolerance, scale), ClipperLib::ptClip,
                   true);
  ClipperLib::Paths solution;
  clipper.Execute(ClipperLib::ctDifference, solution, ClipperLib::pftEvenOdd, ClipperLib::pftNonZero);
  ReferenceResult result = to_result(solution, scale);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

ReferenceResult reference_dilation(const morph::planar::Trajectory& moves, double radius,
                                   const ReferenceOptions& options) {
  check(radius, options);
  const auto started = std::chrono::steady_clock::now();
  morph::planar::Box2 extent(Vec2::Zero());
  for (const Curve& m : moves) extent.extend(morph::planar::dilation_bounds(m, radius));
  const double scale = choose_scale(extent, options.chord_tolerance);
  ClipperLib::Clipper clipper;
  clipper.StrictlySimple(true);
  clipper.AddPaths(dilation_polygons(moves, radius, options.chord_tolerance, scale), ClipperLib::ptSubject,
                   true);
  ClipperLib::Paths solution;
  clipper.Execute(ClipperLib::ctUnion, solution, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  ReferenceResult result = to_result(solution, scale);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return result;
}

}  // namespace planar_ref
