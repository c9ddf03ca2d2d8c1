// SPDX-License-Identifier: Apache-2.0
// Codes that set modes and machine state: LinuxCNC's modal groups, units, tools and tool length
// offsets, coordinate systems (G54..G59.3, G10 L2/L20), G92/G52 offsets, M codes, and the live
// parameters (#5400.., #<_x>, ...) that read this state.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "gcode/gcode_interpreter.h"

namespace morph::gcode {
namespace {

int whole(double value, const std::string& word, double low = 0.0) {
  if (value < low || std::abs(value - std::round(value)) > 1e-6 || value > 1e9)
    fail(word + " must be an integer of at least " + format_number(low) + ", not " + format_number(value));
  return static_cast<int>(std::round(value));
}

}  // namespace

PlaneAxes axes_of(Plane plane) {
  switch (plane) {
    case Plane::XZ:
      return {2, 0, 1, "G18 (ZX plane)"};
    case Plane::YZ:
      return {1, 2, 0, "G19 (YZ plane)"};
    case Plane::XY:
      break;
  }
  return {0, 1, 2, "G17 (XY plane)"};
}

LineCodes Interpreter::sort_g_codes() {
  LineCodes c;
  auto set_once = [&](int& slot, int code10, const char* group) {
    if (slot >= 0 && slot != code10)
      fail(std::string("two ") + group + " codes (" + code_name('G', slot) + ", " + code_name('G', code10) +
           ") on one line");
    slot = code10;
  };
  for (int k = 0; k < block_.g_count; ++k) {
    const int g = block_.g_codes[static_cast<std::size_t>(k)];
    switch (g) {
      case 800:
        if (c.motion < 0) c.motion = g;  // with another motion code on the line, G80 is ignored (LinuxCNC)
        break;
      case 0:
      case 10:
      case 20:
      case 30:
      case 330:
      case 730:
      case 740:
      case 810:
      case 820:
      case 830:
      case 840:
      case 850:
      case 860:
      case 870:
      case 880:
      case 890:
        if (c.motion == 800) c.motion = -1;
        set_once(c.motion, g, "motion");
        break;
      case 40:
      case 100:
      case 280:
      case 281:
      case 300:
      case 301:
      case 520:
      case 920:
      case 921:
      case 922:
      case 923:
        set_once(c.non_modal, g, "non-modal (group 0)");
        break;
      case 530:
        c.g53 = true;
        break;
      case 170:
      case 180:
      case 190:
        set_once(c.plane, g, "plane");
        break;
      case 200:
      case 210:
        set_once(c.units, g, "units");
        break;
      case 400:
      case 410:
      case 411:
      case 420:
      case 421:
        set_once(c.cutter, g, "cutter compensation");
        break;
      case 430:
      case 431:
      case 432:
      case 490:
        set_once(c.length, g, "tool length offset");
        break;
      case 540:
      case 550:
      case 560:
      case 570:
      case 580:
      case 590:
      case 591:
      case 592:
      case 593:
        set_once(c.system, g, "coordinate system");
        break;
      case 610:
      case 611:
      case 640:
        set_once(c.path, g, "path control");
        break;
      case 900:
      case 910:
        set_once(c.distance, g, "distance mode");
        break;
      case 901:
      case 911:
        set_once(c.arc_distance, g, "arc distance mode");
        break;
      case 930:
      case 940:
      case 950:
        set_once(c.feed_mode, g, "feed mode");
        break;
      case 980:
      case 990:
        set_once(c.retract, g, "canned-cycle return");
        break;
      case 80:
      case 960:
      case 970:
        used_ |= bit('d');
        break;  // radius mode (the mill default), spindle speed modes: no effect on the path
      case 50:
      case 51:
      case 52:
      case 53:
        fail("spline motion (" + code_name('G', g) + ") is not supported");
      case 70:
        fail("lathe diameter mode (G7) is not supported");
      case 700:
      case 710:
      case 711:
      case 720:
      case 721:
        fail("lathe cycle (" + code_name('G', g) + ") is not supported: MorphMill verifies milling");
      case 160:
        fail("polar coordinates (G16) are not supported");
      case 331:
      case 760:
        fail("threading (" + code_name('G', g) + ") is not supported");
      case 382:
      case 383:
      case 384:
      case 385:
        fail("probing (" + code_name('G', g) + ") is not supported: its motion depends on the part");
      case 510:
        fail("scaling (G51) is not supported");
      case 680:
        fail("coordinate rotation (G68) is not supported");
      case 171:
      case 181:
      case 191:
        fail("the UVW planes (" + code_name('G', g) + ") are not supported (3-axis X, Y, Z reader)");
      default:
        fail("unsupported code " + code_name('G', g));
    }
  }
  return c;
}

void Interpreter::select_and_change_tools() {
  if (block_.has('t')) {
    const int t = whole(block_.get('t'), "T");
    used_ |= bit('t');
    if (selected_tool_ && !selection_reached_spindle_ && *selected_tool_ != t &&
        *selected_tool_ != current_tool_)
      result_.warnings.push_back(
          Warning{name_, selected_line_,
                  "T" + std::to_string(*selected_tool_) +
                      " is selected but never put in the spindle (no M6 before the next T)"});
    selected_tool_ = t;
    selected_line_ = line_;
    selection_reached_spindle_ = false;
    if (!options_.tools.empty() && !options_.tools.count(t))
      warn("T" + std::to_string(t) + " selects a tool that is not in the tool table");
  }
  bool change = block_.has('t') && options_.tool_change_on_t;
  for (int k = 0; k < block_.m_count; ++k) {
    const int m = block_.m_codes[static_cast<std::size_t>(k)] / 10;
    if (m == 6) {
      if (!selected_tool_) {
        warn("M6 with no T selected: tool " + std::to_string(current_tool_) + " stays in the spindle");
        continue;
      }
      change = true;
    } else if (m == 61) {
      if (!block_.has('q')) fail("M61 needs a Q word (the tool number)");
      current_tool_ = whole(block_.get('q'), "M61 Q");
      used_ |= bit('q');
      result_.tools_used.insert(current_tool_);
      update_tip_shift();
    }
  }
  if (change && selected_tool_) {
    current_tool_ = *selected_tool_;
    selection_reached_spindle_ = true;
    result_.tools_used.insert(current_tool_);
    update_tip_shift();
  }
}

void Interpreter::execute_m_codes(bool& stop) {
  std::array<int, 5> group{-1, -1, -1, -1, -1};  // stop, tool change, spindle, coolant, overrides
  auto in_group = [&](int g, int code10) {
    if (group[static_cast<std::size_t>(g)] >= 0 && g != 3)
      fail("two M codes of one modal group (" + code_name('M', group[static_cast<std::size_t>(g)]) + ", " +
           code_name('M', code10) + ") on one line");
    group[static_cast<std::size_t>(g)] = code10;
  };
  for (int k = 0; k < block_.m_count; ++k) {
    const int code10 = block_.m_codes[static_cast<std::size_t>(k)];
    const int m = code10 / 10;
    switch (m) {
      case 0:
      case 1:
      case 60:
        in_group(0, code10);
        break;  // pauses: no motion
      case 2:
      case 30:
        in_group(0, code10);
        stop = true;
        end_code_ = code_name('M', code10);
        break;
      case 6:
      case 61:
        in_group(1, code10);
        break;  // done by select_and_change_tools
      case 3:
      case 4:
      case 5:
        in_group(2, code10);
        spindle_direction_ = m == 3 ? 1 : m == 4 ? -1 : 0;
        break;
      case 19:
        used_ |= bit('r') | bit('q') | bit('p');
        break;  // spindle orientation
      case 7:
      case 8:
      case 9:
        in_group(3, code10);
        if (m == 7) coolant_mist_ = true;
        if (m == 8) coolant_flood_ = true;
        if (m == 9) coolant_mist_ = coolant_flood_ = false;
        break;
      case 48:
      case 49:
      case 50:
      case 51:
      case 52:
      case 53:
        in_group(4, code10);
        used_ |= bit('p');
        break;  // overrides: the commanded path is unchanged
      case 62:
      case 63:
      case 64:
      case 65:
      case 66:
      case 67:
      case 68:
        used_ |= bit('p') | bit('e') | bit('l') | bit('q');
        break;  // digital and analog I/O
      case 70:
      case 71:
      case 72:
      case 73:
        modal_state(m);
        break;
      case 98:
      case 99:
        fail("subprogram calls (M98/M99) are not supported: use O-word subroutines (o<name> call)");
      default:
        if (m >= 100 && m <= 199) {
          used_ |= bit('p') | bit('q');
          warn("user M code " + code_name('M', code10) + " ignored (it runs a program on the controller)");
          break;
        }
        fail("unsupported code " + code_name('M', code10));
    }
  }
}

void Interpreter::set_units(Units units) {
  program_units_ = units;
  scale_ = millimetres_per_unit(units) / millimetres_per_unit(options_.job_units);
  // Arc checks in the program's own units, as LinuxCNC's interpreter does them (its defaults).
  if (units == Units::Inch)
    tolerances_ = {2 * 0.001 * M_SQRT2 * scale_, 0.00004 * scale_, 0.00005 * scale_};
  else
    tolerances_ = {2 * 0.01 * M_SQRT2 * scale_, 0.001 * scale_, 0.00005 * 25.4 * scale_};
}

double Interpreter::length_of(int tool, const char* word) const {
  if (tool == 0) return 0.0;
  const auto it = table_.find(tool);
  if (it != table_.end()) return it->second.length_offset;
  if (options_.tools.empty()) return 0.0;  // no table at all: warned by the caller
  fail(std::string(word) + std::to_string(tool) + ": tool " + std::to_string(tool) +
       " is not in the tool table");
}

void Interpreter::set_length_offset(int code10) {
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  if (code10 == 430 || code10 == 432) {
    const int h = block_.has('h') ? whole(block_.get('h'), "H") : current_tool_;
    used_ |= bit('h');
    if (options_.tools.empty() && h != 0 && !table_.count(h))
      warn(code_name('G', code10) + " H" + std::to_string(h) + ": no tool table was given, offset 0 applied");
    if (code10 == 432) offset = length_offset_;
    offset.z() += length_of(h, "H");
  } else if (code10 == 431) {
    for (int a = 0; a < 3; ++a)
      if (block_.has(kAxisLetters[a])) offset[a] = block_.get(kAxisLetters[a]) * scale_;
    used_ |= kAxisBits;
  }
  if (code10 != 490) length_compensation_used_ = true;
  // The machine does not move: the same machine position now has other program coordinates.
  position_ += length_offset_ - offset;
  length_offset_ = offset;
  update_tip_shift();
}

void Interpreter::update_tip_shift() {
  const auto it = options_.tools.find(current_tool_);
  const double physical = it == options_.tools.end() ? 0.0 : it->second.length_offset;
  tip_shift_ = length_offset_ - Eigen::Vector3d(0.0, 0.0, physical);
  physical_length_ = physical;
}

void Interpreter::settle_touch_off() {
  const std::vector<Move>& moves = result_.path.moves;
  if (moves.empty()) return;
  // LinuxCNC moves the gauge line; the tip is the physical tool's length below it. A program that
  // uses G43 expects the work offsets measured from the gauge line, and gets the tip there. One
  // that never does was set up as shops without tool length offsets do: Z touched off with the
  // tool that cuts first, so its tip is at the programmed point. Another tool of another length
  // is then that much lower or higher, as on the machine.
  double reference = 0.0;
  int reference_tool = 0;
  if (!length_compensation_used_) {
    const auto cutting =
        std::find_if(moves.begin(), moves.end(), [](const Move& m) { return m.kind != MoveKind::Rapid; });
    reference_tool = (cutting == moves.end() ? moves.front() : *cutting).tool;
    const auto it = options_.tools.find(reference_tool);
    reference = it == options_.tools.end() ? 0.0 : it->second.length_offset;
  }
  if (reference != 0.0)
    for (Move& move : result_.path.moves) {
      move.start.z() += reference;
      move.end.z() += reference;
      move.center.z() += reference;
    }
  for (const UncompensatedTool& u : uncompensated_) {
    const double lower = u.length - reference;
    if (lower == 0.0) continue;
    std::string message =
        "tool " + std::to_string(u.tool) + " is " + format_number(u.length) + " long in the tool table";
    if (length_compensation_used_)
      message += " but no G43 is in effect";
    else
      message += ", tool " + std::to_string(reference_tool) +
                 " (the first to cut, taken as the tool Z was touched off with) " + format_number(reference) +
                 ", and the program never uses G43";
    message += ": its tip runs " + format_number(std::abs(lower)) + (lower > 0 ? " below" : " above") +
               " the programmed point";
    result_.warnings.push_back(Warning{name_, u.line, message});
    if (length_compensation_used_) break;  // once, at the first such move
  }
}

void Interpreter::select_system(int index) {
  if (index == system_) return;
  const int base = param::system_base(index);
  if (parameters_.numbered(base + 9) != 0.0)
    fail("coordinate system " + std::to_string(index) + " is rotated (#" + std::to_string(base + 9) +
         "): rotation is not supported");
  for (int a = 0; a < 3; ++a) work_offset_[a] = parameters_.numbered(base + a);
  system_ = index;
  parameters_.set_numbered(param::kCoordSystem, index);
}

void Interpreter::set_offsets(int code10) {
  if (code10 == 920 || code10 == 520) {
    if ((block_.present & kAxisBits) == 0) fail(code_name('G', code10) + " needs at least one axis word");
    used_ |= kAxisBits;
    for (int a = 0; a < 3; ++a) {
      if (!block_.has(kAxisLetters[a])) continue;
      const double v = block_.get(kAxisLetters[a]) * scale_;
      if (code10 == 520) {
        axis_offset_[a] = v;
      } else if (!known_[a]) {
        warn(std::string("G92 at an unknown ") + static_cast<char>(kAxisLetters[a] - 32) +
             ": the program's coordinates are taken as the job's there (offset 0)");
        axis_offset_[a] = 0.0;
        position_[a] = work_offset_[a] + v;
        known_[a] = true;
      } else {
        axis_offset_[a] = position_[a] - work_offset_[a] - v;
      }
    }
    parameters_.set_numbered(param::kG92Applied, 1.0);
    for (int a = 0; a < 3; ++a) parameters_.set_numbered(param::kG92 + a, axis_offset_[a]);
    return;
  }
  if (code10 == 923) {
    for (int a = 0; a < 3; ++a) axis_offset_[a] = parameters_.numbered(param::kG92 + a);
    parameters_.set_numbered(param::kG92Applied, 1.0);
    return;
  }
  axis_offset_.setZero();  // G92.1 and G92.2
  parameters_.set_numbered(param::kG92Applied, 0.0);
  if (code10 == 921)
    for (int a = 0; a < 3; ++a) parameters_.set_numbered(param::kG92 + a, 0.0);
}

void Interpreter::set_tool_table() {
  const double l = block_.get('l');
  used_ |= bit('p') | bit('r') | bit('i') | bit('j') | bit('q') | kAxisBits;
  if (!block_.has('p')) fail("G10 L" + format_number(l) + " needs P (the tool number)");
  const int tool = whole(block_.get('p'), "G10 L" + format_number(l) + " P", 1.0);
  GcodeTool& entry = table_[tool];
  if (block_.has('r')) entry.diameter = 2.0 * block_.get('r') * scale_;
  if (!block_.has('z')) return;
  const double z = block_.get('z') * scale_;
  if (l == 1.0) {
    entry.length_offset = z;
    return;
  }
  if (!known_[2]) fail("G10 L" + format_number(l) + " at an unknown Z: program Z first");
  const double machine = position_.z() + length_offset_.z();
  if (l == 10.0) {
    entry.length_offset = machine - work_offset_.z() - axis_offset_.z() - z;
  } else {
    entry.length_offset = machine - parameters_.numbered(param::system_base(9) + 2) - z;
  }
}

void Interpreter::set_work_offsets(int l) {
  used_ |= bit('p') | bit('r') | kAxisBits;
  if (!block_.has('p'))
    fail("G10 L" + std::to_string(l) + " needs P (0 for the active system, 1-9 for G54-G59.3)");
  int p = whole(block_.get('p'), "G10 L" + std::to_string(l) + " P");
  if (p > 9) fail("G10 L" + std::to_string(l) + " P must be 0 to 9");
  if (p == 0) p = system_;
  if (block_.has('r') && block_.get('r') != 0.0)
    fail("G10 L" + std::to_string(l) + " R (coordinate system rotation) is not supported");
  const int base = param::system_base(p);
  for (int a = 0; a < 3; ++a) {
    if (!block_.has(kAxisLetters[a])) continue;
    const double v = block_.get(kAxisLetters[a]) * scale_;
    double offset = v;
    if (l == 20) {
      if (!known_[a])
        fail(std::string("G10 L20 at an unknown ") + static_cast<char>(kAxisLetters[a] - 32) +
             ": program X, Y and Z first (or give the job a start position)");
      offset = position_[a] - axis_offset_[a] - v;
    }
    parameters_.set_numbered(base + a, offset);
    if (p == system_) work_offset_[a] = offset;
  }
}

/// M70 saves the modal state, M71 forgets it, M72 restores it, M73 saves it and restores it when
/// the current subroutine returns (LinuxCNC's set: units, distance modes, plane, feed mode and
/// rate, spindle, coolant, coordinate system, G98/G99).
void Interpreter::modal_state(int m) {
  const std::size_t level = calls_.size();
  if (saved_.size() <= level) saved_.resize(level + 1);
  std::optional<ModalState>& slot = saved_[level];
  if (m == 71) {
    slot.reset();
    return;
  }
  if (m == 72) {
    if (!slot) fail("M72 with no state saved by M70 or M73 at this call level");
    restore(*slot);
    return;
  }
  slot = ModalState{
      program_units_,     incremental_,  incremental_centre_, plane_,  feed_mode_,    feed_program_, spindle_,
      spindle_direction_, coolant_mist_, coolant_flood_,      system_, retract_to_r_, m == 73};
  if (m == 73 && level == 0) fail("M73 (restore on return) outside a subroutine");
}

void Interpreter::restore(const ModalState& s) {
  set_units(s.units);
  incremental_ = s.incremental;
  incremental_centre_ = s.incremental_centre;
  plane_ = s.plane;
  feed_mode_ = s.feed_mode;
  feed_program_ = s.feed;
  spindle_ = s.spindle;
  spindle_direction_ = s.spindle_direction;
  coolant_mist_ = s.mist;
  coolant_flood_ = s.flood;
  select_system(s.system);
  retract_to_r_ = s.retract_to_r;
}

double Interpreter::program_coordinate(int axis) const {
  return (position_[axis] - work_offset_[axis] - axis_offset_[axis]) / scale_;
}

std::optional<double> Interpreter::live_parameter(int number, std::string_view name) const {
  auto flag = [](bool b) { return b ? 1.0 : 0.0; };
  if (number != 0) {
    if (number == 5400) return current_tool_;
    if (number >= 5401 && number <= 5403) return length_offset_[number - 5401] / scale_;
    if (number == 5410) {
      const auto it = table_.find(current_tool_);
      return it == table_.end() ? 0.0 : it->second.diameter / scale_;
    }
    if (number >= 5420 && number <= 5422) return program_coordinate(number - 5420);
    return 0.0;  // other axes, angles and orientation of this 3-axis reader
  }
  static constexpr const char* kAxes[3] = {"_x", "_y", "_z"};
  static constexpr const char* kAbs[3] = {"_abs_x", "_abs_y", "_abs_z"};
  for (int a = 0; a < 3; ++a) {
    if (name == kAxes[a]) return program_coordinate(a);
    if (name == kAbs[a]) return (position_[a] + length_offset_[a]) / scale_;
  }
  for (const char* other :
       {"_a", "_b", "_c", "_u", "_v", "_w", "_abs_a", "_abs_b", "_abs_c", "_abs_u", "_abs_v", "_abs_w"})
    if (name == other) return 0.0;  // the axes this 3-axis reader does not have
  const int motion_code = motion_ == Motion::Rapid                 ? 0
                          : motion_ == Motion::Linear              ? 10
                          : motion_ == Motion::ArcClockwise        ? 20
                          : motion_ == Motion::ArcCounterClockwise ? 30
                          : motion_ == Motion::Synchronized        ? 330
                          : motion_ == Motion::Cycle               ? cycle_code_
                                                                   : 800;
  const std::pair<const char*, double> values[] = {
      {"_line", line_},
      {"_motion_mode", motion_code},
      {"_plane", plane_ == Plane::XY   ? 170
                 : plane_ == Plane::XZ ? 180
                                       : 190},
      {"_ccomp", 400},
      {"_metric", flag(program_units_ == Units::Millimetre)},
      {"_imperial", flag(program_units_ == Units::Inch)},
      {"_absolute", flag(!incremental_)},
      {"_incremental", flag(incremental_)},
      {"_inverse_time", flag(feed_mode_ == FeedMode::InverseTime)},
      {"_units_per_minute", flag(feed_mode_ == FeedMode::PerMinute)},
      {"_units_per_rev", flag(feed_mode_ == FeedMode::PerRevolution)},
      {"_coord_system", system_ <= 6 ? 530 + 10 * system_ : 584 + system_},
      {"_tool_offset", flag(!length_offset_.isZero())},
      {"_retract_r_plane", flag(retract_to_r_)},
      {"_retract_old_z", flag(!retract_to_r_)},
      {"_spindle_rpm_mode", 1},
      {"_spindle_css_mode", 0},
      {"_ijk_absolute_mode", flag(!incremental_centre_)},
      {"_lathe_diameter_mode", 0},
      {"_lathe_radius_mode", 0},
      {"_spindle_on", flag(spindle_direction_ != 0)},
      {"_spindle_cw", flag(spindle_direction_ == 1)},
      {"_mist", flag(coolant_mist_)},
      {"_flood", flag(coolant_flood_)},
      {"_speed_override", 1},
      {"_feed_override", 1},
      {"_adaptive_feed", 0},
      {"_feed_hold", 0},
      {"_feed", feed_program_},
      {"_rpm", spindle_},
      {"_current_tool", current_tool_},
      {"_current_pocket", current_tool_},
      {"_selected_tool", selected_tool_ ? *selected_tool_ : -1},
      {"_selected_pocket", selected_tool_ ? *selected_tool_ : -1},
      {"_value", return_value_},
      {"_value_returned", flag(returned_value_)},
      {"_call_level", static_cast<double>(calls_.size())},
      {"_remap_level", 0},
      {"_task", 0},
  };
  for (const auto& [n, v] : values)
    if (name == n) return v;
  return std::nullopt;
}

}  // namespace morph::gcode
