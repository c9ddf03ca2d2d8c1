// SPDX-License-Identifier: Apache-2.0
#include <morph/quantize.h>
#include <morph/sweep_segments.h>

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

bool goes_on_straight(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                      int grid_exponent) {
  SweepSegment first, second;
  first.from = snap_to_grid(a, grid_exponent);
  first.to = second.from = snap_to_grid(b, grid_exponent);
  second.to = snap_to_grid(c, grid_exponent);
  return first.from != first.to && continues_straight(first, second, grid_exponent);
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
