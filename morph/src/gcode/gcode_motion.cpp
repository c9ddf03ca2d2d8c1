// SPDX-License-Identifier: Apache-2.0
// Motion: programmed targets through the coordinate systems, straight moves, arcs and helices,
// G28/G30 and their stored positions, and the emitted moves (tool tip in job units).
#include <algorithm>
#include <cmath>

#include "gcode/gcode_interpreter.h"

namespace morph::gcode {
namespace {
constexpr double kTwoPi = 2.0 * M_PI;
}

Eigen::Vector3d Interpreter::target(std::array<bool, 3>& known_after, bool machine) const {
  Eigen::Vector3d end = position_;
  known_after = known_;
  if (block_.polar_present != 0) return polar_target(known_after, machine);
  for (int a = 0; a < 3; ++a) {
    if (!block_.has(kAxisLetters[a])) continue;
    const double v = block_.get(kAxisLetters[a]) * scale_;
    if (machine) {
      end[a] = v - length_offset_[a];  // G53: the machine position itself
      known_after[a] = true;
    } else if (incremental_) {
      end[a] += v;  // stays unknown if it was unknown
    } else {
      end[a] = v + work_offset_[a] + axis_offset_[a];
      known_after[a] = true;
    }
  }
  return end;
}

/// LinuxCNC's polar words: @ the distance and ^ the angle (degrees from +X) of the XY end point
/// from the origin of the program's coordinates (G90), or changes to them (G91).
Eigen::Vector3d Interpreter::polar_target(std::array<bool, 3>& known_after, bool machine) const {
  if (machine) fail("polar coordinates (@, ^) cannot be used with G53");
  if (block_.has('x') || block_.has('y')) fail("X or Y words cannot be used with polar coordinates (@, ^)");
  if (!known_[0] || !known_[1])
    fail("polar coordinates (@, ^) from an unknown X or Y: program X and Y first");
  const bool has_radius = (block_.polar_present & 1u) != 0, has_angle = (block_.polar_present & 2u) != 0;
  const double x = program_coordinate(0), y = program_coordinate(1);
  double radius = std::hypot(x, y), angle = std::atan2(y, x);
  if ((!has_angle || incremental_) && x == 0.0 && y == 0.0)
    fail("polar coordinates at the origin need an angle (^) and G90: the direction is undefined");
  if (incremental_) {
    if (has_radius) radius += block_.polar[0];
    if (has_angle) angle += block_.polar[1] * M_PI / 180.0;
  } else {
    if (has_radius) radius = block_.polar[0];
    if (has_angle) angle = block_.polar[1] * M_PI / 180.0;
  }
  Eigen::Vector3d end = position_;
  end[0] = radius * std::cos(angle) * scale_ + work_offset_[0] + axis_offset_[0];
  end[1] = radius * std::sin(angle) * scale_ + work_offset_[1] + axis_offset_[1];
  if (block_.has('z')) {
    const double v = block_.get('z') * scale_;
    end[2] = incremental_ ? end[2] + v : v + work_offset_[2] + axis_offset_[2];
    if (!incremental_) known_after[2] = true;
  }
  return end;
}

Move Interpreter::make_move(MoveKind kind, const Eigen::Vector3d& end) const {
  Move move;
  move.kind = kind;
  move.start = position_ + tip_shift_;
  move.end = end + tip_shift_;
  move.tool = current_tool_;
  move.line = line_;
  move.feed = feed_mode_ == FeedMode::PerMinute ? feed_program_ * scale_ : 0.0;
  move.spindle = spindle_;
  return move;
}

void Interpreter::emit(Move move) {
  if (result_.path.moves.size() >= options_.max_moves)
    fail("the program has made " + std::to_string(options_.max_moves) + " moves (GcodeOptions::max_moves)");
  if (move.tool == options_.initial_tool) result_.tools_used.insert(move.tool);
  if (length_offset_.isZero() && (uncompensated_.empty() || uncompensated_.back().tool != move.tool))
    uncompensated_.push_back({move.line, move.tool, physical_length_});
  result_.path.moves.push_back(std::move(move));
}

void Interpreter::move_to(MoveKind kind, const Eigen::Vector3d& end, const std::array<bool, 3>& known_after) {
  // Start-position rule: until X, Y and Z are all known, motions only establish the position.
  if (all_known() && end != position_) emit(make_move(kind, end));
  position_ = end;
  known_ = known_after;
}

void Interpreter::straight(MoveKind kind, bool machine) {
  std::array<bool, 3> known_after;
  const Eigen::Vector3d end = target(known_after, machine);
  move_to(kind, end, known_after);
}

void Interpreter::require_feed(const char* what) {
  // LinuxCNC refuses the program here. The path does not depend on the feed, so it is read as
  // programmed and said once, with the line; --strict (warnings are errors) refuses it as LinuxCNC does.
  if (feed_mode_ == FeedMode::PerMinute && feed_program_ <= 0.0 && !feed_missing_warned_) {
    feed_missing_warned_ = true;
    warn(std::string(what) +
         " with no feed rate: F is 0 or was never set; LinuxCNC refuses this program (read here as "
         "programmed; the first such move is named, later ones are not)");
  }
  if (feed_mode_ == FeedMode::InverseTime && !block_.has('f'))
    fail(std::string(what) + " in inverse-time feed mode (G93) needs an F word on its line");
}

void Interpreter::note_missing_units() {
  if (feed_mode_ != FeedMode::PerMinute && !feed_mode_warned_) {
    feed_mode_warned_ = true;
    warn(std::string(feed_mode_ == FeedMode::InverseTime ? "G93" : "G95") +
         ": feed is not in units per minute; moves record feed 0");
  }
  if (units_declared_ || units_warned_) return;
  units_warned_ = true;
  warn(std::string("no G20/G21 before the first move: coordinates taken in the job's units (") +
       to_string(options_.job_units) + ")");
}

void Interpreter::go_home(int code10) {
  const int which = code10 == 280 ? 0 : 1;
  const int base = which == 0 ? param::kG28 : param::kG30;
  const std::string name = code_name('G', code10);
  used_ |= kAxisBits;
  const bool named = (block_.present & kAxisBits) != 0;
  if (named) straight(MoveKind::Rapid, false);  // the intermediate point, as G0 would reach it
  Eigen::Vector3d end = position_;
  std::array<bool, 3> known_after = known_;
  std::string unknown;
  for (int a = 0; a < 3; ++a) {
    if (named && !block_.has(kAxisLetters[a])) continue;
    if (home_known_[static_cast<std::size_t>(which)]) {
      end[a] = parameters_.numbered(base + a) - length_offset_[a];
      known_after[a] = true;
    } else {
      known_after[a] = false;
      unknown += static_cast<char>(kAxisLetters[a] - 32);
    }
  }
  move_to(MoveKind::Rapid, end, known_after);
  if (!unknown.empty())
    warn(name + " goes to the machine's stored position, which the program does not give: " + unknown +
         " unknown until programmed again (no move is made until X, Y and Z are known; give #" +
         std::to_string(base) + "-#" + std::to_string(base + 2) + " in a var file to make it known)");
}

void Interpreter::store_home(int code10) {
  if (!all_known()) fail(code_name('G', code10) + " at an unknown position: program X, Y and Z first");
  const int which = code10 == 281 ? 0 : 1;
  const int base = which == 0 ? param::kG28 : param::kG30;
  for (int a = 0; a < 3; ++a) parameters_.set_numbered(base + a, position_[a] + length_offset_[a]);
  home_known_[static_cast<std::size_t>(which)] = true;
}

void Interpreter::arc(bool clockwise) {
  used_ |= kAxisBits | bit('i') | bit('j') | bit('k') | bit('r') | bit('p');
  const PlaneAxes axes = axes_of(plane_);
  if (!all_known()) fail("arc from an unknown position: program X, Y and Z with G0/G1 before the first arc");
  std::array<bool, 3> known_after;
  const Eigen::Vector3d end = target(known_after, false);
  const Eigen::Vector3d start = position_;

  int turns = 1;
  if (block_.has('p')) {
    const double p = block_.get('p');
    if (p < 1.0 || p != std::floor(p) || p > 1e6) fail("arc P (number of turns) must be a positive integer");
    turns = static_cast<int>(p);
  }
  const char first_offset = kOffsetLetters[axes.first], second_offset = kOffsetLetters[axes.second];
  const bool has_radius = block_.has('r');
  const bool has_first_offset = block_.has(first_offset);
  const bool has_second_offset = block_.has(second_offset);
  const char normal_offset = kOffsetLetters[axes.normal];
  const char normal_upper = static_cast<char>(normal_offset - 32);
  if (has_radius && (has_first_offset || has_second_offset))
    fail("arc with both R and an I/J/K centre: give one or the other");
  if (!has_radius && !has_first_offset && !has_second_offset) {
    if (block_.has(normal_offset))
      fail(std::string("arc in ") + axes.code + " has only " + normal_upper +
           ", which is not an offset in this plane");
    fail("arc with neither an I/J/K centre nor an R radius");
  }
  if (block_.has(normal_offset))
    warn(std::string(1, normal_upper) + format_number(block_.get(normal_offset)) +
         " ignored: not an offset in " + axes.code);

  const double s1 = start[axes.first], s2 = start[axes.second];
  const double e1 = end[axes.first], e2 = end[axes.second];
  double c1 = 0.0, c2 = 0.0;
  if (has_radius) {
    const double radius = block_.get('r') * scale_;
    if (!block_.has(kAxisLetters[axes.first]) && !block_.has(kAxisLetters[axes.second]))
      fail(std::string("R-format arc needs an end point in ") + axes.code);
    const double d1 = e1 - s1, d2 = e2 - s2;
    const double chord = std::hypot(d1, d2);
    if (chord == 0.0) fail("R-format arc ends where it starts: a full circle needs an I/J/K centre");
    const double abs_radius = std::abs(radius);
    double half = chord / 2.0;
    if (half - abs_radius > tolerances_.radius_reach)
      fail("arc radius R" + format_number(block_.get('r')) +
           " is too small to reach the end point (half chord " + format_number(half / scale_) + ")");
    half = std::min(half, abs_radius);
    const double offset = std::sqrt(std::max(0.0, abs_radius * abs_radius - half * half));
    // Centre to the right of the chord for a short clockwise or long counter-clockwise arc.
    const bool right = clockwise == (radius > 0.0);
    const double side = right ? -1.0 : 1.0;
    c1 = (s1 + e1) / 2.0 + side * offset * (-d2 / chord);
    c2 = (s2 + e2) / 2.0 + side * offset * (d1 / chord);
  } else {
    const double i1 = has_first_offset ? block_.get(first_offset) * scale_ : 0.0;
    const double i2 = has_second_offset ? block_.get(second_offset) * scale_ : 0.0;
    if (incremental_centre_) {
      c1 = s1 + i1;
      c2 = s2 + i2;
    } else {
      if (!has_first_offset || !has_second_offset)
        fail(std::string("absolute arc centre (G90.1) needs both ") + static_cast<char>(first_offset - 32) +
             " and " + static_cast<char>(second_offset - 32));
      c1 = i1 + work_offset_[axes.first] + axis_offset_[axes.first];
      c2 = i2 + work_offset_[axes.second] + axis_offset_[axes.second];
    }
    const double r_start = std::hypot(s1 - c1, s2 - c2);
    const double r_end = std::hypot(e1 - c1, e2 - c2);
    if (r_start < tolerances_.radius_reach || r_end < tolerances_.radius_reach)
      fail("zero-radius arc (start or end on the centre)");
    const double mismatch = std::abs(r_start - r_end);
    const double relative = mismatch / std::max(r_start, r_end);
    if (mismatch > tolerances_.radius_mismatch ||
        (relative > 0.001 &&
         mismatch > tolerances_.radius_mismatch_min))  // LinuxCNC's SPIRAL_RELATIVE_TOLERANCE
      fail("arc end is not on its circle: radius to start " + format_number(r_start / scale_) +
           ", radius to end " + format_number(r_end / scale_) + " (" + to_string(program_units_) + ")");
  }

  const double u1 = s1 - c1, u2 = s2 - c2, v1 = e1 - c1, v2 = e2 - c2;
  const double radius = std::hypot(u1, u2);
  // Turn through (0, 2 pi] in the arc's direction; P adds whole turns.
  double turn;
  if (std::hypot(e1 - s1, e2 - s2) <= 1e-9 * radius) {
    turn = kTwoPi;  // end on start: a full circle
  } else {
    const double ccw = std::atan2(u1 * v2 - u2 * v1, u1 * v1 + u2 * v2);  // in (-pi, pi]
    turn = clockwise ? (ccw < 0.0 ? -ccw : kTwoPi - ccw) : (ccw > 0.0 ? ccw : kTwoPi + ccw);
  }
  turn += kTwoPi * (turns - 1);

  Move move = make_move(MoveKind::Arc, end);
  Eigen::Vector3d center = start;
  center[axes.first] = c1;
  center[axes.second] = c2;
  move.center = center + tip_shift_;
  move.axis = Eigen::Vector3d::Unit(axes.normal);
  move.sweep = clockwise ? -turn : turn;
  emit(std::move(move));
  position_ = end;
  known_ = known_after;
}

}  // namespace morph::gcode
