// SPDX-License-Identifier: Apache-2.0
// RS-274/NGC reader, LinuxCNC's interpreter being the reference for meaning. This file is the
// line loop: reading lines, the program end, O-word control flow, and the order in which one
// block's words take effect. What is supported and where MorphMill differs: docs/gcode.md.
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <morph/gcode.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <istream>
#include <iterator>

#include "gcode/gcode_interpreter.h"

namespace morph::gcode {
namespace {

bool is_blank_char(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}
bool is_blank(std::string_view line) {
  return std::all_of(line.begin(), line.end(), is_blank_char);
}
bool is_percent_line(std::string_view line) {
  bool percent = false;
  for (char c : line) {
    if (c == '%' && !percent)
      percent = true;
    else if (!is_blank_char(c))
      return false;
  }
  return percent;
}

}  // namespace

Interpreter::Interpreter(const std::string& name, const GcodeOptions& options)
    : name_(name),
      options_(options),
      parameters_([this](int number, std::string_view n) { return live_parameter(number, n); }),
      reader_(parameters_),
      table_(options.tools) {
  result_.path.source = name;
  current_tool_ = options.initial_tool;
  if (options.start) {
    position_ = *options.start;
    known_ = {true, true, true};
  }
  set_units(options.job_units);
  // Machine set-up: var file, then explicit parameters, then the job's work offsets.
  std::map<int, double> initial;
  if (!options.var_file.empty()) initial = read_var_file(options.var_file);
  for (const auto& [number, value] : options.parameters) initial[number] = value;
  for (const auto& [index, offset] : options.work_offsets) {
    if (index < 1 || index > 9)
      throw InputError("work offset index " + std::to_string(index) + " is not 1 (G54) .. 9 (G59.3)");
    for (int a = 0; a < 3; ++a) initial[param::system_base(index) + a] = offset[a];
  }
  for (const auto& [number, value] : initial) {
    if (number < 1 || number > param::kLast || (number >= 5399 && number <= 5428))
      throw InputError("initial parameter #" + std::to_string(number) + " cannot be set");
    parameters_.set_numbered(number, value);
    if (number >= param::kG28 && number <= param::kG28 + 2) home_known_[0] = true;
    if (number >= param::kG30 && number <= param::kG30 + 2) home_known_[1] = true;
  }
  const double active = parameters_.numbered(param::kCoordSystem);
  try {
    system_ = 0;  // nothing loaded yet
    select_system((active >= 1.0 && active <= 9.0 && active == std::floor(active)) ? static_cast<int>(active)
                                                                                   : 1);
    if (parameters_.numbered(param::kG92Applied) == 1.0)
      for (int a = 0; a < 3; ++a) axis_offset_[a] = parameters_.numbered(param::kG92 + a);
  } catch (const BlockError& e) {
    throw InputError(name + ": machine set-up: " + e.what());
  }
  update_tip_shift();
}

/// Lines holding at least one digit: a bound on the moves a program can hold.
std::size_t lines_with_digits(std::string_view text) {
  std::size_t lines = 0;
  bool digit = false;
  for (const char c : text) {
    if (c == '\n') {
      lines += digit;
      digit = false;
    } else if (c >= '0' && c <= '9') {
      digit = true;
    }
  }
  return lines + digit;
}

GcodeResult Interpreter::run(std::string_view text) {
  text_ = text;
  const ProgramIndex index(text);
  index_ = &index;
  // A move needs a line with a number on it: blank and comment-only lines reserve nothing.
  result_.path.moves.reserve(std::min(lines_with_digits(text), options_.max_moves));
  bool seen_content = false;  // an opening '%' may only come before any content
  while (pos_offset_ < text.size()) {
    const std::size_t begin = pos_offset_;
    const char* newline =
        static_cast<const char*>(std::memchr(text.data() + begin, '\n', text.size() - begin));
    const std::size_t end = newline ? static_cast<std::size_t>(newline - text.data()) : text.size();
    std::string_view line = text.substr(begin, end - begin);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    line_ = next_line_;
    pos_offset_ = end + 1;
    ++next_line_;
    const bool o_line = next_o_ < index.lines().size() && index[next_o_].begin == begin;
    const std::size_t o_index = next_o_;
    if (o_line) ++next_o_;
    if (ended_) {
      if (ended_after_line_ == 0 && !is_blank(line) && !is_percent_line(line)) ended_after_line_ = line_;
      continue;
    }
    if (!o_line && is_percent_line(line)) {
      if (!seen_content) {
        seen_content = true;
        continue;
      }
      ended_ = true;  // the closing tape mark (also accepted without an opening one)
      end_code_ = "%";
      continue;
    }
    if (!is_blank(line)) seen_content = true;
    try {
      // Only control flow can run a line again, so only lines run again count towards the bound:
      // a long straight program (or a file of blank lines) is bounded by its size already.
      if (line_ <= furthest_line_) {
        if (++blocks_repeated_ > options_.max_blocks)
          fail("the program has run lines again " + std::to_string(options_.max_blocks) +
               " times (GcodeOptions::max_blocks): an endless loop?");
      } else {
        furthest_line_ = line_;
      }
      if (o_line)
        execute_o_word(o_index);
      else
        execute_line(line);
    } catch (const BlockError& e) {
      throw InputError(name_ + ":" + std::to_string(line_) + ": " + e.what());
    }
  }
  result_.line_count = static_cast<std::size_t>(next_line_ - 1);
  settle_touch_off();
  if (ended_after_line_ != 0)
    result_.warnings.push_back(
        Warning{name_, ended_after_line_, "lines after the program end (" + end_code_ + ") are ignored"});
  if (selected_tool_ && !selection_reached_spindle_ && *selected_tool_ != current_tool_)
    result_.warnings.push_back(Warning{
        name_, selected_line_,
        "T" + std::to_string(*selected_tool_) + " is selected but never put in the spindle (no M6 follows)"});
  auto& counts = result_.word_counts;
  for (int k = 0; k < 26; ++k)
    if (letter_counts_[static_cast<std::size_t>(k)] != 0)
      counts[std::string(1, static_cast<char>('A' + k))] = letter_counts_[static_cast<std::size_t>(k)];
  for (const auto& [code10, n] : g_counts_) counts[code_name('G', code10)] += n;
  for (const auto& [code10, n] : m_counts_) counts[code_name('M', code10)] += n;
  return std::move(result_);
}

void Interpreter::warn(std::string message) {
  result_.warnings.push_back(Warning{name_, line_, std::move(message)});
}

void Interpreter::execute_line(std::string_view line) {
  reader_.read(line, block_);
  if (block_.block_delete && options_.block_delete) {
    warn("block delete '/': line skipped, as with the block-delete switch on");
    return;
  }
  if (block_.o_kind != OKind::None) fail("an O-word must be the first word of its line");
  for (const Assignment& a : block_.assignments) {
    if (a.number != 0) {
      parameters_.set_numbered(a.number, a.value);
      if (a.number >= param::kG28 && a.number <= param::kG28 + 2) home_known_[0] = true;
      if (a.number >= param::kG30 && a.number <= param::kG30 + 2) home_known_[1] = true;
    } else {
      parameters_.set_named(a.name, a.value);
    }
  }
  if (block_.note != Note::None) result_.messages.push_back(Warning{name_, line_, block_.note_text});
  if (block_.empty()) return;
  execute_block();
}

void Interpreter::jump_to(std::size_t k, bool past) {
  const OLine& o = (*index_)[k];
  pos_offset_ = past ? o.end + 1 : o.begin;
  next_line_ = past ? o.line + 1 : o.line;
  next_o_ = past ? k + 1 : k;
}

void Interpreter::execute_o_word(std::size_t k) {
  const ProgramIndex& index = *index_;
  const OLine& o = index[k];
  if (!o.problem.empty()) fail(o.problem);
  auto read_o_line = [&](const OLine& l) {
    line_ = l.line;
    std::string_view text = text_.substr(l.begin, l.end - l.begin);
    if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
    reader_.read(text, block_);
    if (!l.problem.empty()) fail(l.problem);
    if (block_.note != Note::None) result_.messages.push_back(Warning{name_, line_, block_.note_text});
  };
  read_o_line(o);
  if (block_.block_delete && options_.block_delete) {
    warn("block delete '/': line skipped, as with the block-delete switch on");
    return;
  }
  ++letter_counts_[static_cast<std::size_t>('O' - 'A')];
  auto value = [&] { return block_.o_args.empty() ? 0.0 : block_.o_args[0]; };
  auto iterate = [&](Loop& loop) {
    if (++loop.iterations > options_.max_loop_iterations)
      fail("o" + index[loop.start].label + " loop ran " + std::to_string(options_.max_loop_iterations) +
           " times without ending (GcodeOptions::max_loop_iterations)");
  };
  auto loop_end = [&](std::size_t start) { return index[start].partner; };
  switch (o.kind) {
    case OKind::ProgramNumber:
      warn("program number O-word ignored");
      return;
    case OKind::Sub:
      jump_to(o.partner, true);  // a definition: run only when called
      return;
    case OKind::EndSub:
    case OKind::Return: {
      if (calls_.empty()) fail("o" + o.label + " " + to_string(o.kind) + " reached without a call");
      returned_value_ = !block_.o_args.empty();
      if (returned_value_) return_value_ = value();
      const Call call = calls_.back();
      if (saved_.size() > calls_.size()) {
        const std::optional<ModalState> state = saved_[calls_.size()];
        saved_.resize(calls_.size());
        if (state && state->restore_on_return) restore(*state);
      }
      calls_.pop_back();
      loops_.resize(call.loops);
      parameters_.pop_call();
      pos_offset_ = call.return_offset;
      next_line_ = call.return_line;
      next_o_ = index.first_at_or_after(pos_offset_);
      return;
    }
    case OKind::Call: {
      const std::size_t sub = index.sub(o.label);
      if (sub == kNone)
        fail("o" + o.label + " call: there is no o" + o.label +
             " sub in this file (subroutines in separate files are not supported)");
      if (static_cast<int>(calls_.size()) >= options_.max_call_depth)
        fail("o" + o.label + " call: calls nested deeper than " + std::to_string(options_.max_call_depth) +
             " (LinuxCNC's limit; a recursion without end?)");
      if (!index[sub].problem.empty()) fail(index[sub].problem);
      calls_.push_back(Call{pos_offset_, next_line_, loops_.size()});
      parameters_.push_call(block_.o_args);
      returned_value_ = false;
      return_value_ = 0.0;
      jump_to(sub, true);
      return;
    }
    case OKind::If: {
      std::size_t branch = k;
      bool taken = value() != 0.0;
      while (!taken) {
        branch = index[branch].next_branch;
        const OLine& b = index[branch];
        if (b.kind != OKind::ElseIf) {
          jump_to(branch, true);  // else: its body; endif: past the block
          return;
        }
        read_o_line(b);
        taken = value() != 0.0;
      }
      if (branch != k) jump_to(branch, true);
      return;
    }
    case OKind::ElseIf:
    case OKind::Else:
      jump_to(o.partner, true);  // the end of a branch that ran
      return;
    case OKind::EndIf:
      return;
    case OKind::Do:
      loops_.push_back(Loop{k});
      return;
    case OKind::While: {
      const bool go_on = value() != 0.0;
      if (o.closes_do) {
        if (loops_.empty() || loops_.back().start != o.partner) fail("o" + o.label + " while without its do");
        if (go_on) {
          iterate(loops_.back());
          jump_to(o.partner, true);
        } else {
          loops_.pop_back();
        }
        return;
      }
      const bool resumed = !loops_.empty() && loops_.back().start == k;
      if (go_on) {
        if (!resumed) loops_.push_back(Loop{k});
        return;
      }
      if (resumed) loops_.pop_back();
      jump_to(o.partner, true);
      return;
    }
    case OKind::EndWhile:
      if (loops_.empty() || loops_.back().start != o.partner)
        fail("o" + o.label + " endwhile without its while");
      iterate(loops_.back());
      jump_to(o.partner, false);  // evaluate the condition again
      return;
    case OKind::Repeat: {
      const double count = std::round(value());
      if (count <= 0.0) {
        jump_to(o.partner, true);
        return;
      }
      if (count > static_cast<double>(options_.max_loop_iterations))
        fail("o" + o.label + " repeat [" + format_number(count) + "] exceeds " +
             std::to_string(options_.max_loop_iterations) +
             " iterations (GcodeOptions::max_loop_iterations)");
      loops_.push_back(Loop{k, 0, static_cast<long>(count)});
      return;
    }
    case OKind::EndRepeat: {
      if (loops_.empty() || loops_.back().start != o.partner)
        fail("o" + o.label + " endrepeat without its repeat");
      Loop& loop = loops_.back();
      iterate(loop);
      if (--loop.remaining > 0)
        jump_to(o.partner, true);
      else
        loops_.pop_back();
      return;
    }
    case OKind::Break:
    case OKind::Continue: {
      while (!loops_.empty() && loops_.back().start != o.loop) loops_.pop_back();
      if (loops_.empty()) fail("o" + o.label + " " + to_string(o.kind) + " outside its running loop");
      if (o.kind == OKind::Break) {
        loops_.pop_back();
        jump_to(loop_end(o.loop), true);
      } else {
        jump_to(loop_end(o.loop), false);  // the loop's end decides whether it goes on
      }
      return;
    }
    case OKind::None:
      break;
  }
}

void Interpreter::execute_block() {
  used_ = 0;
  count_words();
  const LineCodes codes = sort_g_codes();
  if (codes.feed_mode >= 0)
    feed_mode_ = codes.feed_mode == 940   ? FeedMode::PerMinute
                 : codes.feed_mode == 930 ? FeedMode::InverseTime
                                          : FeedMode::PerRevolution;
  if (block_.has('f')) {
    if (block_.get('f') < 0.0) fail("negative feed rate F" + format_number(block_.get('f')));
    feed_program_ = block_.get('f');
    used_ |= bit('f');
  }
  if (block_.has('s')) {
    if (block_.get('s') < 0.0) fail("negative spindle speed S" + format_number(block_.get('s')));
    spindle_ = block_.get('s');
    used_ |= bit('s');
  }
  select_and_change_tools();
  bool stop = false;
  execute_m_codes(stop);
  if (codes.non_modal == 40) {
    if (!block_.has('p') || block_.get('p') < 0.0) fail("G4 (dwell) needs a non-negative P (seconds)");
    used_ |= bit('p');
  }
  if (codes.plane >= 0) plane_ = codes.plane == 170 ? Plane::XY : codes.plane == 180 ? Plane::XZ : Plane::YZ;
  if (codes.units >= 0) {
    set_units(codes.units == 200 ? Units::Inch : Units::Millimetre);
    units_declared_ = true;
  }
  if (codes.cutter > 400)
    fail("cutter radius compensation (" + code_name('G', codes.cutter) +
         ") is not supported: the path would be offset by the tool radius");
  if (codes.length >= 0) set_length_offset(codes.length);
  if (codes.system >= 0)
    select_system(codes.system == 540 ? 1 : codes.system < 591 ? codes.system / 10 - 53 : codes.system - 584);
  if (codes.path >= 0) used_ |= bit('p') | bit('q');
  if (codes.distance >= 0) incremental_ = codes.distance == 910;
  if (codes.arc_distance >= 0) incremental_centre_ = codes.arc_distance == 911;
  if (codes.retract >= 0) retract_to_r_ = codes.retract == 990;

  const bool axis_words = (block_.present & kAxisBits) != 0 || block_.polar_present != 0;
  bool axes_taken = false;  // a non-modal code used the axis words
  switch (codes.non_modal) {
    case 100: {
      const double l = block_.has('l') ? block_.get('l') : -1.0;
      used_ |= bit('l');
      if (l == 1.0 || l == 10.0 || l == 11.0)
        set_tool_table();
      else if (l == 2.0 || l == 20.0)
        set_work_offsets(static_cast<int>(l));
      else
        fail("G10 needs L1, L10, L11 (tool table), L2 or L20 (work offsets), not " +
             (l < 0.0 ? std::string("no L") : "L" + format_number(l)));
      axes_taken = true;
      break;
    }
    case 280:
    case 300:
      go_home(codes.non_modal);
      axes_taken = true;
      break;
    case 281:
    case 301:
      store_home(codes.non_modal);
      break;
    case 520:
    case 920:
    case 921:
    case 922:
    case 923:
      set_offsets(codes.non_modal);
      axes_taken = codes.non_modal == 520 || codes.non_modal == 920;
      break;
    default:
      break;
  }
  if (codes.length == 431) axes_taken = true;
  if (axes_taken && block_.polar_present != 0)
    fail("polar coordinates (@, ^) cannot give the values of this line's G10/G28/G30/G52/G92");
  if (axes_taken && codes.motion >= 0 && codes.motion != 800 && axis_words)
    fail(code_name('G', codes.non_modal >= 0 ? codes.non_modal : codes.length) + " and " +
         code_name('G', codes.motion) + " both use the axis words");

  previous_cycle_ = motion_ == Motion::Cycle ? cycle_code_ : 0;
  if (codes.motion >= 0) {
    if (codes.motion == 800) {
      motion_ = Motion::None;
      if (axis_words && !axes_taken) fail("axis words with G80 (cancel canned cycle), which has no motion");
    } else if (codes.motion == 330) {
      motion_ = Motion::Synchronized;
    } else if (codes.motion <= 30) {
      motion_ = codes.motion == 0    ? Motion::Rapid
                : codes.motion == 10 ? Motion::Linear
                : codes.motion == 20 ? Motion::ArcClockwise
                                     : Motion::ArcCounterClockwise;
    } else {
      motion_ = Motion::Cycle;
      cycle_code_ = codes.motion;
    }
  }
  if (codes.g53 && !(motion_ == Motion::Rapid || motion_ == Motion::Linear))
    fail("G53 (machine coordinates) needs G0 or G1 in effect");
  if (codes.g53 && incremental_) fail("G53 (machine coordinates) cannot be used in G91 (incremental) mode");
  for (char letter : {'a', 'b', 'c', 'u', 'v', 'w'}) {
    if (!block_.has(letter)) continue;
    used_ |= bit(letter);
    if (block_.get(letter) != 0.0)
      fail(std::string("axis ") + static_cast<char>(letter - 32) +
           " is not supported (3-axis X, Y, Z reader)");
    warn(std::string(1, static_cast<char>(letter - 32)) + "0 ignored (3-axis reader)");
  }
  const bool moves = axis_words && !axes_taken;
  if (motion_ != Motion::Cycle && (moves || codes.motion >= 0)) cycle_initial_set_ = false;
  switch (motion_) {
    case Motion::Rapid:
    case Motion::Linear:
      used_ |= kAxisBits;
      if (moves) {
        note_missing_units();
        if (motion_ == Motion::Linear) require_feed("G1");
        straight(motion_ == Motion::Rapid ? MoveKind::Rapid : MoveKind::Linear, codes.g53);
      }
      break;
    case Motion::Synchronized:
      // G33: a straight feed whose speed follows the spindle, K per turn (LinuxCNC needs both).
      used_ |= kAxisBits | bit('k');
      if (moves) {
        note_missing_units();
        if (!block_.has('k')) fail("G33 needs K (the distance per spindle turn)");
        if (spindle_direction_ == 0) fail("G33 with the spindle not turning (M3 or M4 first)");
        straight(MoveKind::Linear, false);
      }
      break;
    case Motion::ArcClockwise:
    case Motion::ArcCounterClockwise: {
      const std::uint32_t arc_words = kAxisBits | bit('i') | bit('j') | bit('k') | bit('r');
      if (((block_.present & arc_words) != 0 || block_.polar_present != 0) && !axes_taken) {
        note_missing_units();
        require_feed(motion_ == Motion::ArcClockwise ? "G2" : "G3");
        arc(motion_ == Motion::ArcClockwise);
      } else if (codes.motion >= 0 && block_.has('p')) {
        fail("arc with P but no end point or centre");
      }
      break;
    }
    case Motion::Cycle:
      if (moves) {
        note_missing_units();
        canned_cycle();
      } else if (codes.motion >= 0 && !axes_taken) {
        used_ |=
            bit('r') | bit('l') | bit('p') | bit('q') | bit('i') | bit('j') | bit('k');  // stored for later
      }
      break;
    case Motion::None:
      if (moves) fail("axis words with no motion mode (G0/G1/G2/G3 or a canned cycle) in effect");
      break;
  }
  const std::uint32_t unused = block_.present & ~used_ & ~(bit('n'));
  for (int k = 0; unused != 0 && k < 26; ++k) {
    if ((unused & (std::uint32_t{1} << k)) == 0) continue;
    const char letter = static_cast<char>('A' + k);
    const std::string word = letter + format_number(block_.value[static_cast<std::size_t>(k)]);
    if (std::strchr("IJKRPQLHDEXYZ", letter))
      fail(word + ": nothing on this line uses it (LinuxCNC refuses it too)");
    fail("unsupported word " + word);
  }
  if (stop) ended_ = true;
}

void Interpreter::count_words() {
  for (std::uint32_t bits = block_.present; bits != 0; bits &= bits - 1)
    ++letter_counts_[static_cast<std::size_t>(__builtin_ctz(bits))];
  if (block_.line_number) ++letter_counts_[static_cast<std::size_t>('N' - 'A')];
  for (int k = 0; k < block_.g_count; ++k) ++g_counts_[block_.g_codes[static_cast<std::size_t>(k)]];
  for (int k = 0; k < block_.m_count; ++k) ++m_counts_[block_.m_codes[static_cast<std::size_t>(k)]];
}

}  // namespace morph::gcode

namespace morph {

GcodeResult parse_gcode(std::istream& in, const std::string& name, const GcodeOptions& options) {
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw IoError(name + ": read error");
  gcode::Interpreter interpreter(name, options);
  return interpreter.run(text);
}

GcodeResult read_gcode(const std::string& path, const GcodeOptions& options) {
  const std::string text = read_regular_file(path, "G-code file");
  gcode::Interpreter interpreter(path, options);
  return interpreter.run(text);
}

}  // namespace morph
