// SPDX-License-Identifier: Apache-2.0
// Canned cycles G73, G74, G81-G87, G89 expanded into the straight moves LinuxCNC's interpreter
// makes (its convert_cycle_*): the preliminary moves to the R plane, L repeats (stepping by X/Y
// in G91), G98/G99 retract, in all three planes. Cycle arithmetic is in program units and the
// program's coordinates, like LinuxCNC's; G88 (manual retract) is refused.
#include <cmath>

#include "gcode/gcode_interpreter.h"

namespace morph::gcode {

void Interpreter::canned_cycle() {
  const int code = cycle_code_;
  const std::string name = code_name('G', code);
  const PlaneAxes ax = axes_of(plane_);
  const char depth_letter = kAxisLetters[ax.normal];
  const char depth_upper = static_cast<char>(depth_letter - 32);
  used_ |= kAxisBits | bit('r') | bit('l') | bit('p') | bit('q') | bit('i') | bit('j') | bit('k') | bit('d');
  const bool polar = block_.polar_present != 0;
  if (polar && plane_ != Plane::XY) fail(name + " with polar coordinates (@, ^) needs the G17 plane");
  if (polar && (block_.has('x') || block_.has('y')))
    fail("X or Y words cannot be used with polar coordinates (@, ^)");
  if (code == 880)
    fail(
        "G88 (boring with a manual retract) is not supported: the path after its stop is not in the program");
  if (feed_mode_ == FeedMode::InverseTime)
    fail(name + ": canned cycles cannot be used in inverse-time mode (G93)");
  require_feed(name.c_str());
  if (!all_known()) fail(name + " from an unknown position: program X, Y and Z first");
  const bool same = previous_cycle_ == code;

  double r_word;
  if (block_.has('r'))
    r_word = block_.get('r');
  else if (same)
    r_word = cycle_r_;
  else
    fail(name + " needs R (the retract plane) the first time");
  double z_word;
  if (block_.has(depth_letter))
    z_word = block_.get(depth_letter);
  else if (same)
    z_word = cycle_depth_;
  else
    fail(name + " needs " + depth_upper + " (the bottom) the first time");
  int repeats = 1;
  if (block_.has('l')) {
    const double l = block_.get('l');
    if (l != std::floor(l) || l < 0.0 || l > 1e6) fail(name + " L (repeats) must be a whole number");
    if (l == 0.0) fail(name + " L0: cannot do zero repeats of a cycle");
    repeats = static_cast<int>(l);
  }
  auto sticky = [&](char letter, double& memory, const char* what) {
    if (block_.has(letter))
      memory = block_.get(letter);
    else if (!same)
      fail(name + " needs " + static_cast<char>(letter - 32) + " (" + what + ") the first time");
    return memory;
  };
  double dwell = 0.0, delta = 0.0;
  if (code == 820 || code == 860 || code == 890) dwell = sticky('p', cycle_p_, "the dwell");
  if (code == 740 || code == 840) dwell = block_.has('p') ? block_.get('p') : 0.0;
  if (code == 730 || code == 830) {
    delta = sticky('q', cycle_q_, "the peck depth");
    if (delta <= 0.0) fail(name + " Q (the peck depth) must be positive");
  }
  (void)dwell;  // dwells do not move the tool
  if ((code == 740 || code == 840 || code == 860 || code == 870) && spindle_direction_ == 0)
    fail(name + " with the spindle not turning (M3 or M4 first)");

  double cur[3];
  for (int a = 0; a < 3; ++a) cur[a] = program_coordinate(a);
  if (!cycle_initial_set_) {
    cycle_initial_ = cur[ax.normal];
    cycle_initial_set_ = true;
  }
  double old_cc = cycle_initial_;
  double aa, bb, aa_step = 0.0, bb_step = 0.0, r, cc;
  if (!incremental_) {
    aa = block_.has(kAxisLetters[ax.first]) ? block_.get(kAxisLetters[ax.first]) : cur[ax.first];
    bb = block_.has(kAxisLetters[ax.second]) ? block_.get(kAxisLetters[ax.second]) : cur[ax.second];
    r = r_word;
    cc = z_word;
    if (polar) {
      const double radius = (block_.polar_present & 1u) ? block_.polar[0] : std::hypot(cur[0], cur[1]);
      const double angle =
          (block_.polar_present & 2u) ? block_.polar[1] * M_PI / 180.0 : std::atan2(cur[1], cur[0]);
      aa = radius * std::cos(angle);
      bb = radius * std::sin(angle);
    }
  } else {
    if (block_.has(kAxisLetters[ax.first])) aa_step = block_.get(kAxisLetters[ax.first]);
    if (block_.has(kAxisLetters[ax.second])) bb_step = block_.get(kAxisLetters[ax.second]);
    r = r_word + old_cc;
    cc = r + z_word;
    aa = cur[ax.first];
    bb = cur[ax.second];
  }
  if (r < cc)
    fail(name + ": R (" + format_number(r) + ") is below the bottom " + depth_upper + " (" +
         format_number(cc) + ")");

  // Straight moves given in the plane's (first, second, normal) program coordinates.
  auto go = [&](MoveKind kind, double a1, double a2, double a3) {
    Eigen::Vector3d end;
    const double p[3] = {a1, a2, a3};
    const int axis[3] = {ax.first, ax.second, ax.normal};
    for (int k = 0; k < 3; ++k) end[axis[k]] = p[k] * scale_ + work_offset_[axis[k]] + axis_offset_[axis[k]];
    move_to(kind, end, {true, true, true});
  };
  auto traverse = [&](double a1, double a2, double a3) { go(MoveKind::Rapid, a1, a2, a3); };
  auto feed = [&](double a1, double a2, double a3) { go(MoveKind::Linear, a1, a2, a3); };

  double current_cc = cur[ax.normal];
  if (old_cc < r) {  // below the R plane: straight up to it first
    traverse(cur[ax.first], cur[ax.second], r);
    old_cc = r;
    current_cc = old_cc;
  }
  const double clear_cc = retract_to_r_ ? r : old_cc;
  // The G73/G83 retract between pecks: 0.010 inch, in the program's units, as the LinuxCNC of
  // Debian 12 does it (later versions make it an ini setting, 1 mm / 0.05 inch by default).
  const double rapid_delta = block_.has('d')                 ? block_.get('d')
                             : program_units_ == Units::Inch ? 0.010
                                                             : 0.254;
  double i = 0.0, j = 0.0, k = 0.0;
  if (code == 870) {
    i = sticky('i', cycle_i_, "the X offset");
    j = sticky('j', cycle_j_, "the Y offset");
    k = sticky('k', cycle_k_, "the top of the back bore");
    if (incremental_) k += cc;
  }

  const double radius_step = incremental_ && (block_.polar_present & 1u) ? block_.polar[0] : 0.0;
  const double angle_step =
      incremental_ && (block_.polar_present & 2u) ? block_.polar[1] * M_PI / 180.0 : 0.0;
  for (int repeat = repeats; repeat > 0; --repeat) {
    aa += aa_step;
    bb += bb_step;
    if (radius_step != 0.0 || angle_step != 0.0) {  // G91 polar: step the radius and angle
      if (aa == 0.0 && bb == 0.0) fail(name + ": incremental polar motion at the origin is indeterminate");
      const double radius = std::hypot(aa, bb) + radius_step, angle = std::atan2(bb, aa) + angle_step;
      aa = radius * std::cos(angle);
      bb = radius * std::sin(angle);
    }
    if (repeat == repeats && current_cc > r) {
      traverse(aa, bb, current_cc);
      traverse(aa, bb, r);
    } else {
      traverse(aa, bb, clear_cc);
      if (clear_cc > r) traverse(aa, bb, r);
    }
    switch (code) {
      case 810:
      case 820:
        feed(aa, bb, cc);
        traverse(aa, bb, clear_cc);
        break;
      case 730:
      case 830:
        for (double depth = r - delta; depth > cc; depth -= delta) {
          feed(aa, bb, depth);
          if (code == 830) traverse(aa, bb, r);
          traverse(aa, bb, depth + rapid_delta);
        }
        feed(aa, bb, cc);
        traverse(aa, bb, clear_cc);
        break;
      case 740:
      case 840:
      case 890:
        feed(aa, bb, cc);
        feed(aa, bb, clear_cc);
        break;
      case 850:
        feed(aa, bb, cc);
        feed(aa, bb, r);
        traverse(aa, bb, clear_cc);
        break;
      case 860:
        feed(aa, bb, cc);
        traverse(aa, bb, clear_cc);
        break;
      case 870:
        traverse(aa + i, bb + j, r);
        traverse(aa + i, bb + j, cc);
        traverse(aa, bb, cc);
        feed(aa, bb, k);
        feed(aa, bb, cc);
        traverse(aa + i, bb + j, cc);
        traverse(aa + i, bb + j, clear_cc);
        traverse(aa, bb, clear_cc);
        break;
      default:
        fail("unsupported canned cycle " + name);
    }
  }
  cycle_r_ = r_word;
  cycle_depth_ = z_word;
}

}  // namespace morph::gcode
