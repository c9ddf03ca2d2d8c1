// SPDX-License-Identifier: Apache-2.0
#include <morph/quantize.h>
#include <morph/sweep_segments.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>

namespace morph {
namespace {

std::optional<GridPoint> difference(const GridPoint& to, const GridPoint& from) {
  constexpr __int128 kLimit = __int128{1} << 61;  // integer_cross() is exact below 2^62
  GridPoint out{};
  for (int i = 0; i < 3; ++i) {
    const __int128 d = static_cast<__int128>(to[i]) - from[i];
    if (d >= kLimit || d <= -kLimit) return std::nullopt;
    out[i] = static_cast<std::int64_t>(d);
  }
  return out;
}

// The joining rules of the file comment, applied one segment at a time, over a list that keeps
// either every segment (sweep_segments) or only counts (sweep_segment_counts).
class SegmentJoiner {
 public:
  explicit SegmentJoiner(int grid_exponent) : grid_(grid_exponent) {}

  /// A line's segment: joined to the last, dropped, replacing it or added. Returns what the list
  /// does: Join (the last now ends at s.to), Drop (s adds nothing), Replace (the last is
  /// replaced by s), Add.
  enum class Action { Join, Drop, Replace, Add };
  Action line(const SweepSegment& s) {
    Action action = Action::Add;
    if (last_is_line_ && last_.tool == s.tool && last_.to == s.from) {
      if (s.from == s.to)
        action = Action::Drop;
      else if (last_.from == last_.to)
        action = Action::Replace;
      else if (continues_straight(last_, s, grid_))
        action = Action::Join;
    }
    switch (action) {
      case Action::Join:
        last_.to = s.to;
        break;
      case Action::Drop:
        break;
      case Action::Replace:
      case Action::Add:
        last_ = s;
        break;
    }
    last_is_line_ = true;
    return action;
  }

  /// An arc's chord: never joined or dropped (chords of one arc are not collinear, and a short
  /// arc is still an arc).
  void chord(const SweepSegment& s) {
    last_ = s;
    last_is_line_ = false;
  }

 private:
  int grid_;
  SweepSegment last_;
  bool last_is_line_ = false;
};

}  // namespace

bool continues_straight(const SweepSegment& previous, const SweepSegment& next, int grid_exponent) {
  if (previous.tool != next.tool || previous.to != next.from) return false;
  const std::optional<GridPoint> a = grid_point(previous.from, grid_exponent),
                                 b = grid_point(previous.to, grid_exponent),
                                 c = grid_point(next.to, grid_exponent);
  if (!a || !b || !c) return false;
  const std::optional<GridPoint> u = difference(*b, *a), v = difference(*c, *b);
  if (!u || !v) return false;
  const std::array<__int128, 3> cross = integer_cross(*u, *v);
  if (cross[0] != 0 || cross[1] != 0 || cross[2] != 0) return false;
  __int128 dot = 0;
  for (int i = 0; i < 3; ++i) dot += static_cast<__int128>((*u)[i]) * (*v)[i];
  return dot > 0;
}

std::vector<SweepSegment> sweep_segments(const Job& job, double chord_tolerance, int grid_exponent) {
  std::vector<SweepSegment> out;
  SegmentJoiner joiner(grid_exponent);
  const std::vector<const Move*> moves = job.moves();
  for (std::size_t m = 0; m < moves.size(); ++m) {
    const Move& move = *moves[m];
    const auto index = static_cast<std::int32_t>(m);
    if (!move.is_arc()) {
      const SweepSegment s{snap_to_grid(move.start, grid_exponent), snap_to_grid(move.end, grid_exponent),
                           index, move.line, move.tool};
      switch (joiner.line(s)) {
        case SegmentJoiner::Action::Join:
          out.back().to = s.to;
          break;
        case SegmentJoiner::Action::Drop:
          break;
        case SegmentJoiner::Action::Replace:
          out.back() = s;
          break;
        case SegmentJoiner::Action::Add:
          out.push_back(s);
          break;
      }
      continue;
    }
    const std::vector<double> t = chord_parameters(move, chord_tolerance);
    for (std::size_t k = 0; k + 1 < t.size(); ++k) {
      out.push_back(SweepSegment{snap_to_grid(point_at(move, t[k]), grid_exponent),
                                 snap_to_grid(point_at(move, t[k + 1]), grid_exponent), index, move.line,
                                 move.tool});
      joiner.chord(out.back());
    }
  }
  return out;
}

namespace {

Eigen::Vector3d point_of(const GridPoint& x, int grid_exponent) {
  return {std::ldexp(double(x[0]), grid_exponent), std::ldexp(double(x[1]), grid_exponent),
          std::ldexp(double(x[2]), grid_exponent)};
}

double grid_distance(const GridPoint& a, const GridPoint& b) {
  double sum = 0.0;
  for (int c = 0; c < 3; ++c) sum += std::pow(double(a[c]) - double(b[c]), 2);
  return std::sqrt(sum);
}

// The largest component of b - a reduced to coprime integers, and of b - a itself (0, 0 when the
// difference is out of range).
std::pair<std::int64_t, std::int64_t> motion_components(const GridPoint& a, const GridPoint& b) {
  const std::optional<GridPoint> motion = difference(b, a);
  if (!motion) return {0, 0};
  const GridPoint direction = reduced(*motion);
  std::int64_t longest_reduced = 0, longest = 0;
  for (int c = 0; c < 3; ++c) {
    longest_reduced = std::max(longest_reduced, std::abs(direction[c]));
    longest = std::max(longest, std::abs((*motion)[c]));
  }
  return {longest_reduced, longest};
}

// x rounded to the nearest multiple of `spacing` (a power of two), ties up.
GridPoint coarse(const GridPoint& x, std::int64_t spacing) {
  GridPoint out{};
  for (int c = 0; c < 3; ++c) {
    const std::int64_t low =
        x[c] >= 0 ? x[c] / spacing * spacing : -((-x[c] + spacing - 1) / spacing) * spacing;
    out[c] = x[c] - low >= spacing / 2 ? low + spacing : low;
  }
  return out;
}

}  // namespace

SettledEnds settle_segment_ends(std::vector<SweepSegment>& segments,
                                const std::map<int, std::int64_t>& largest_step, int grid_exponent,
                                double max_shift) {
  SettledEnds settled;
  // Each share of the shift in grid steps: half to join short segments' ends, half to the
  // coarser grid.
  const double half_share = 0.5 * std::ldexp(max_shift, -grid_exponent);
  std::vector<std::array<GridPoint, 2>> ends;
  ends.reserve(segments.size());
  for (const SweepSegment& s : segments) {
    const std::optional<GridPoint> a = grid_point(s.from, grid_exponent), b = grid_point(s.to, grid_exponent);
    if (!a || !b) return settled;  // off the grid (out of range): nothing is moved
    ends.push_back({*a, *b});
  }
  // A point is moved the same way wherever it occurs, so that a retrace, a closed loop or a second
  // lap still meets its first exactly.
  std::map<GridPoint, GridPoint> joined;  // point -> the earlier point it joins
  const auto image = [&](const GridPoint& x) {
    const auto found = joined.find(x);
    return found == joined.end() ? x : found->second;
  };
  for (const auto& [a, b] : ends) {
    if (a == b || joined.count(b)) continue;
    const GridPoint to = image(a);
    if (to != b && grid_distance(b, to) <= half_share) joined.emplace(b, to), ++settled.collapsed;
  }
  // When a long segment's planes would not be exact: every point to the coarser grid, the finest
  // power of two on which every segment's motion, divided by it and rounded, fits its tool's
  // limit (the motion between two points rounded to it is then within the limit); none when that
  // grid is coarser than the share allows. Every point, not only long segments' ends: a level
  // path stays level and an axis move on its axis (a level move between a moved end and one left
  // on the finer grid became a ramp of 1e-8, nearly parallel to its neighbours, and its needles
  // needed the rounding).
  const auto limit_of = [&](int tool) {
    const auto found = largest_step.find(tool);
    return found == largest_step.end() ? std::int64_t{0} : found->second;
  };
  bool needed = false;
  std::int64_t spacing = 1;
  for (std::size_t i = 0; i < ends.size(); ++i) {
    const std::int64_t limit = limit_of(segments[i].tool);
    if (limit <= 1) continue;
    const auto [longest_reduced, longest] = motion_components(image(ends[i][0]), image(ends[i][1]));
    needed = needed || longest_reduced > limit;
    while (spacing <= (std::int64_t{1} << 40) && longest / spacing > limit - 1) spacing *= 2;
  }
  if (!needed || 0.5 * std::sqrt(3.0) * double(spacing) > half_share) spacing = 1;
  const auto moved = [&](const GridPoint& x) { return spacing > 1 ? coarse(image(x), spacing) : image(x); };
  if (spacing > 1) {
    std::vector<GridPoint> points;
    points.reserve(2 * ends.size());
    for (const auto& [a, b] : ends) points.push_back(image(a)), points.push_back(image(b));
    std::sort(points.begin(), points.end());
    points.erase(std::unique(points.begin(), points.end()), points.end());
    for (const GridPoint& y : points) settled.aligned += coarse(y, spacing) != y;
  }
  if (joined.empty() && settled.aligned == 0) return settled;
  for (std::size_t i = 0; i < segments.size(); ++i) {
    segments[i].from = point_of(moved(ends[i][0]), grid_exponent);
    segments[i].to = point_of(moved(ends[i][1]), grid_exponent);
  }
  // A segment now of zero length goes where a neighbour of its tool covers its point, as
  // sweep_segments() drops one.
  std::vector<SweepSegment> kept;
  kept.reserve(segments.size());
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const SweepSegment& s = segments[i];
    const bool covered =
        s.from == s.to &&
        ((!kept.empty() && kept.back().tool == s.tool && kept.back().to == s.from) ||
         (i + 1 < segments.size() && segments[i + 1].tool == s.tool && segments[i + 1].from == s.to));
    if (!covered) kept.push_back(s);
  }
  segments = std::move(kept);
  return settled;
}

std::map<int, double> sweep_segment_counts(const Job& job, double chord_tolerance, int grid_exponent) {
  std::map<int, double> count;
  SegmentJoiner joiner(grid_exponent);
  for (const Move* move : job.moves()) {
    job.tool_of(*move);  // throws, naming the move, for a tool the job does not define
    if (move->is_arc()) {
      count[move->tool] += chord_count(*move, chord_tolerance);
      // Its last chord ends at the arc's end: all the joiner reads of it.
      joiner.chord(SweepSegment{snap_to_grid(move->end, grid_exponent),
                                snap_to_grid(move->end, grid_exponent), 0, 0, move->tool});
      continue;
    }
    const SweepSegment s{snap_to_grid(move->start, grid_exponent), snap_to_grid(move->end, grid_exponent), 0,
                         0, move->tool};
    if (joiner.line(s) == SegmentJoiner::Action::Add) count[move->tool] += 1.0;
  }
  return count;
}

}  // namespace morph
