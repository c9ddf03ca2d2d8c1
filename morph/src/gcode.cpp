// RS-274/NGC reader for the subset CAM post-processors emit for 3-axis milling. The supported
// subset, the start-position rule and which problems are warnings or errors are in docs/gcode.md.
#include <morph/exceptions.h>
#include <morph/file_io.h>
#include <morph/gcode.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <istream>
#include <iterator>
#include <string_view>
#include <unordered_map>

namespace morph {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

/// Arc checks, in the program's own units, as LinuxCNC's interpreter does them (its defaults:
/// CENTER_ARC_RADIUS_TOLERANCE_*, MIN_CENTER_ARC_RADIUS_TOLERANCE_*, RADIUS_TOLERANCE_* and
/// SPIRAL_RELATIVE_TOLERANCE in rs274ngc's interp_internal.hh).
struct ArcTolerances {
  double radius_mismatch;      ///< |r_start - r_end| above this is an error
  double radius_mismatch_min;  ///< below this the relative check is not applied either
  double radius_reach;         ///< an R word may fall short of half the chord by this much
};
constexpr double kRadiusMismatchRelative = 0.001;

ArcTolerances tolerances_for(Units program_units) {
  if (program_units == Units::Inch) return {2 * 0.001 * M_SQRT2, 0.00004, 0.00005};
  return {2 * 0.01 * M_SQRT2, 0.001, 0.00005 * 25.4};
}

enum class Plane { XY, XZ, YZ };

/// The arc plane as the RS-274 (first, second) axis pair and the right-handed normal: G3
/// (counter-clockwise) turns from `first` towards `second`, i.e. positively about `normal`.
/// G18 is (Z, X) with normal +Y, as in LinuxCNC's canonical ARC_FEED.
struct PlaneAxes {
  int first, second, normal;
  const char* code;
};

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

enum class Motion { None, Rapid, Linear, ArcClockwise, ArcCounterClockwise };

constexpr int letter_index(char upper) {
  return upper - 'A';
}
constexpr std::uint32_t bit(char upper) {
  return std::uint32_t{1} << letter_index(upper);
}
constexpr char kAxisLetters[3] = {'X', 'Y', 'Z'};
constexpr char kOffsetLetters[3] = {'I', 'J', 'K'};

/// G and M codes are kept as ten times their number, so G90.1 is 901.
std::string code_name(char letter, int code10) {
  std::string name(1, letter);
  name += std::to_string(code10 / 10);
  if (code10 % 10 != 0) {
    name += '.';
    name += static_cast<char>('0' + code10 % 10);
  }
  return name;
}

std::string format_number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value);
  return buffer;
}

/// One line's words after lexing. Letters other than G, M (and N, which is only counted) hold at
/// most one value each.
struct Block {
  std::array<double, 26> value{};
  std::uint32_t present = 0;
  std::array<int, 16> g_codes{};
  int g_count = 0;
  std::array<int, 8> m_codes{};
  int m_count = 0;

  bool has(char upper) const { return (present & bit(upper)) != 0; }
  double get(char upper) const { return value[letter_index(upper)]; }
};

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

class Reader {
 public:
  Reader(const std::string& name, const GcodeOptions& options) : name_(name), options_(options) {
    result_.path.source = name;
    current_tool_ = options.initial_tool;
    if (options.start) {
      position_ = *options.start;
      known_ = {true, true, true};
    }
    set_program_units(options.job_units);
  }

  GcodeResult run(std::string_view text) {
    // At most one move per line with a number on it: reserving avoids re-copying a large move
    // vector while it grows, and blank or comment-only lines reserve nothing.
    result_.path.moves.reserve(lines_with_digits(text));
    std::size_t begin = 0;
    int line_number = 0;
    bool seen_content = false;  // an opening '%' may only come before any content
    while (begin < text.size()) {
      const char* newline =
          static_cast<const char*>(std::memchr(text.data() + begin, '\n', text.size() - begin));
      const std::size_t end = newline ? static_cast<std::size_t>(newline - text.data()) : text.size();
      std::string_view line = text.substr(begin, end - begin);
      begin = end + 1;
      ++line_number;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      line_ = line_number;
      if (ended_) {
        if (ended_after_line_ == 0 && !is_blank(line) && !is_percent_line(line))
          ended_after_line_ = line_number;
        continue;
      }
      if (is_percent_line(line)) {
        if (!seen_content) {
          seen_content = true;
          continue;
        }
        end_program("%");  // the closing tape mark (also accepted without an opening one)
        continue;
      }
      if (!is_blank(line)) seen_content = true;
      process_line(line);
    }
    result_.line_count = static_cast<std::size_t>(line_number);
    if (ended_after_line_ != 0)
      warn(ended_after_line_, "lines after the program end (" + end_code_ + ") are ignored");
    finish_word_counts();
    return std::move(result_);
  }

 private:
  // ---- messages -------------------------------------------------------------------------------
  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(name_ + ":" + std::to_string(line_) + ": " + problem);
  }
  void warn(int line, std::string message) {
    result_.warnings.push_back(Warning{name_, line, std::move(message)});
  }
  void warn(std::string message) { warn(line_, std::move(message)); }

  // ---- lexing ---------------------------------------------------------------------------------
  static bool is_blank_char(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
  static bool is_blank(std::string_view line) {
    for (char c : line)
      if (!is_blank_char(c)) return false;
    return true;
  }
  static bool is_percent_line(std::string_view line) {
    bool percent = false;
    for (char c : line) {
      if (c == '%' && !percent)
        percent = true;
      else if (!is_blank_char(c))
        return false;
    }
    return percent;
  }

  /// Reads the number after a word's letter starting at `i`; RS-274 allows spaces inside it.
  double read_number(std::string_view line, std::size_t& i, char letter) const {
    char digits[64];
    std::size_t n = 0;
    bool negative = false, sign_allowed = true, seen_digit = false, seen_point = false;
    for (; i < line.size(); ++i) {
      const char c = line[i];
      if (is_blank_char(c)) continue;
      if ((c == '+' || c == '-') && sign_allowed) {
        negative = c == '-';
        sign_allowed = false;
        continue;
      }
      if (c >= '0' && c <= '9') {
        seen_digit = true;
      } else if (c == '.' && !seen_point) {
        seen_point = true;
      } else {
        break;
      }
      sign_allowed = false;
      if (n == sizeof digits) fail(std::string("number after ") + letter + " is too long");
      digits[n++] = c;
    }
    if (!seen_digit) {
      const char next = i < line.size() ? line[i] : '\0';
      if (next == '#' || next == '[')
        fail(std::string("parameters (#) and expressions ([...]) are not supported (after ") + letter + ")");
      if (n > 0 || !sign_allowed) fail(std::string("malformed number after ") + letter);
      fail(std::string("the letter ") + letter + " has no number");
    }
    if (i < line.size() && line[i] == '.')
      fail(std::string("malformed number after ") + letter + " (two '.')");
    double value = 0.0;
    const auto parsed = std::from_chars(digits, digits + n, value);
    if (parsed.ec != std::errc() || parsed.ptr != digits + n)
      fail(std::string("malformed number after ") + letter);
    return negative ? -value : value;
  }

  int code_of(char letter, double value) const {
    const double tenths = value * 10.0;
    const double rounded = std::round(tenths);
    if (value < 0.0 || std::abs(tenths - rounded) > 1e-6 || rounded > 1e7)
      fail("malformed code " + std::string(1, letter) + format_number(value));
    const int code10 = static_cast<int>(rounded);
    if (letter == 'M' && code10 % 10 != 0) fail("malformed code M" + format_number(value));
    return code10;
  }

  /// Splits one line into words; comments and N numbers are dropped here.
  bool lex(std::string_view line, Block& block) {
    block.present = 0;
    block.g_count = 0;
    block.m_count = 0;
    bool first = true;
    std::size_t i = 0;
    while (i < line.size()) {
      const char c = line[i];
      if (is_blank_char(c)) {
        ++i;
        continue;
      }
      if (c == '(') {
        const std::size_t close = line.find(')', i + 1);
        const std::size_t nested = line.find('(', i + 1);
        if (close == std::string_view::npos)
          fail("comment '(' is not closed on its line (comments cannot span lines)");
        if (nested < close) fail("nested '(' inside a comment");
        i = close + 1;
        continue;
      }
      if (c == ';') break;
      if (c == ')') fail("')' without an opening '('");
      if (c == '/') {
        if (!first) fail("'/' (block delete) is only allowed at the start of a line");
        warn("block delete '/': line skipped, as with the block-delete switch on");
        return false;
      }
      first = false;
      char letter = c;
      if (letter >= 'a' && letter <= 'z') letter = static_cast<char>(letter - 'a' + 'A');
      if (letter < 'A' || letter > 'Z') {
        if (c == '#' || c == '[') fail("parameters (#) and expressions ([...]) are not supported");
        fail(std::string("unexpected character '") + c + "'");
      }
      ++i;
      if (letter == 'O') {
        // A Fanuc-style program number ("O1234" alone) is harmless; LinuxCNC O-words are control flow.
        read_number(line, i, letter);
        if (!is_blank(strip_comments_view(line.substr(i))))
          fail("O-word subroutines and control flow are not supported");
        warn("program number O-word ignored");
        ++letter_counts_[letter_index('O')];
        return block.present != 0 || block.g_count != 0 || block.m_count != 0;
      }
      const double number = read_number(line, i, letter);
      if (letter == 'G' || letter == 'M') {
        const int code10 = code_of(letter, number);
        if (letter == 'G') {
          if (block.g_count == static_cast<int>(block.g_codes.size())) fail("too many G codes on one line");
          block.g_codes[block.g_count++] = code10;
          ++g_counts_[code10];
        } else {
          if (block.m_count == static_cast<int>(block.m_codes.size())) fail("too many M codes on one line");
          block.m_codes[block.m_count++] = code10;
          ++m_counts_[code10];
        }
        continue;
      }
      ++letter_counts_[letter_index(letter)];
      if (letter == 'N') continue;
      if (block.has(letter)) fail(std::string("two ") + letter + " words on one line");
      block.present |= bit(letter);
      block.value[letter_index(letter)] = number;
    }
    return true;
  }

  /// The part of `rest` that is not comments (only used for the rare O-word check).
  std::string strip_comments_view(std::string_view rest) const {
    std::string out;
    bool in_comment = false;
    for (char c : rest) {
      if (in_comment) {
        if (c == ')') in_comment = false;
      } else if (c == '(') {
        in_comment = true;
      } else if (c == ';') {
        break;
      } else {
        out += c;
      }
    }
    return out;
  }

  // ---- execution ------------------------------------------------------------------------------
  void set_program_units(Units units) {
    program_units_ = units;
    scale_ = millimetres_per_unit(units) / millimetres_per_unit(options_.job_units);
    const ArcTolerances t = tolerances_for(units);
    tolerances_ = {t.radius_mismatch * scale_, t.radius_mismatch_min * scale_, t.radius_reach * scale_};
  }

  void process_line(std::string_view line) {
    Block& block = block_;
    if (!lex(line, block)) return;
    if (block.present == 0 && block.g_count == 0 && block.m_count == 0) return;
    std::uint32_t used = 0;  // letters a code on this line consumed

    // Order of execution within a block follows RS-274/NGC: feed, spindle, tool, M codes,
    // then the modal G codes, then motion, then program stop.
    if (block.has('F')) {
      if (block.get('F') < 0.0) fail("negative feed rate F" + format_number(block.get('F')));
      feed_program_ = block.get('F');
      used |= bit('F');
    }
    if (block.has('S')) {
      spindle_ = block.get('S');
      used |= bit('S');
    }
    if (block.has('T')) {
      const double t = block.get('T');
      if (t < 0.0 || t != std::floor(t) || t > 1e9)
        fail("T must be a non-negative integer, not T" + format_number(t));
      selected_tool_ = static_cast<int>(t);
      used |= bit('T');
    }
    bool end_of_program = false;
    for (int k = 0; k < block.m_count; ++k) execute_m(block.m_codes[k], block, used, end_of_program);

    Motion motion = motion_;
    bool motion_given = false;
    int home_code = 0;
    bool tool_table_line = false;  // G10 L1: its axis words are tool data, not a motion
    apply_g_codes(block, used, motion, motion_given, home_code, tool_table_line);
    motion_ = motion;

    const bool axis_words = (block.present & (bit('X') | bit('Y') | bit('Z'))) != 0;
    check_other_axes(block, used);
    if (tool_table_line) {
      // nothing moves
    } else if (home_code != 0) {
      go_home(block, home_code);
      used |= bit('X') | bit('Y') | bit('Z');
    } else if (motion == Motion::Rapid || motion == Motion::Linear) {
      if (axis_words) {
        note_missing_units();
        straight(block, motion == Motion::Rapid ? MoveKind::Rapid : MoveKind::Linear);
      }
      used |= bit('X') | bit('Y') | bit('Z');
    } else if (motion == Motion::ArcClockwise || motion == Motion::ArcCounterClockwise) {
      const std::uint32_t arc_words =
          bit('X') | bit('Y') | bit('Z') | bit('I') | bit('J') | bit('K') | bit('R');
      if ((block.present & arc_words) != 0) {
        note_missing_units();
        arc(block, motion == Motion::ArcClockwise, used);
      } else if (motion_given && block.has('P')) {
        fail("arc with P but no end point or centre");
      }
    } else if (axis_words) {
      fail("axis words with no motion mode (G0/G1/G2/G3) in effect");
    }
    warn_unused(block, used);
    if (end_of_program) end_program(end_code_);
  }

  void note_missing_units() {
    if (units_declared_ || units_warned_) return;
    units_warned_ = true;
    warn(std::string("no G20/G21 before the first move: coordinates taken in the job's units (") +
         to_string(options_.job_units) + ")");
  }

  void execute_m(int code10, const Block& block, std::uint32_t& used, bool& end_of_program) {
    const int m = code10 / 10;
    switch (m) {
      case 0:
      case 1:
      case 60:
        return;  // pauses: no motion
      case 2:
      case 30:
        end_of_program = true;
        end_code_ = code_name('M', code10);
        return;
      case 3:
      case 4:
      case 5:
      case 7:
      case 8:
      case 9:
      case 48:
      case 49:
      case 50:
      case 51:
      case 52:
      case 53:
        return;  // spindle, coolant, overrides: recorded in word_counts only
      case 6:
        if (selected_tool_) {
          current_tool_ = *selected_tool_;
          result_.tools_used.insert(current_tool_);
        } else {
          warn("M6 with no T selected: tool " + std::to_string(current_tool_) + " stays in the spindle");
        }
        return;
      case 61: {
        if (!block.has('Q')) fail("M61 needs a Q word (the tool number)");
        const double q = block.get('Q');
        if (q < 0.0 || q != std::floor(q)) fail("M61 Q must be a non-negative integer");
        current_tool_ = static_cast<int>(q);
        result_.tools_used.insert(current_tool_);
        used |= bit('Q');
        return;
      }
      case 62:
      case 63:
      case 64:
      case 65:
      case 66:
      case 67:
      case 68:
        used |= bit('P') | bit('E') | bit('L') | bit('Q');
        return;  // digital/analog I/O
      case 98:
      case 99:
        fail("subprogram calls (M98/M99) are not supported");
      default:
        break;
    }
    if (m >= 100 && m <= 199)
      warn("user M code " + code_name('M', code10) + " ignored");
    else
      warn("unknown code " + code_name('M', code10) + " ignored");
  }

  /// Applies the line's modal G codes and refuses the unsupported ones; `motion` becomes the
  /// motion mode after this line, `home_code` the G28/G30 on it (0 if none), and
  /// `tool_table_line` tells whether a G10 tool-table line took the axis words.
  void apply_g_codes(const Block& block, std::uint32_t& used, Motion& motion, bool& motion_given,
                     int& home_code, bool& tool_table_line) {
    int motion_code = -1, plane_code = -1, units_code = -1, distance_code = -1, arc_distance_code = -1;
    bool cancel_cycle = false;
    auto set_once = [&](int& slot, int code10, const char* group) {
      if (slot >= 0 && slot != code10)
        fail(std::string("two ") + group + " codes (" + code_name('G', slot) + ", " + code_name('G', code10) +
             ") on one line");
      slot = code10;
    };
    for (int k = 0; k < block.g_count; ++k) {
      const int g = block.g_codes[k];
      switch (g) {
        case 0:
        case 10:
        case 20:
        case 30:
          set_once(motion_code, g, "motion");
          break;
        case 800:
          cancel_cycle = true;
          break;
        case 170:
        case 180:
        case 190:
          set_once(plane_code, g, "plane");
          break;
        case 200:
        case 210:
          set_once(units_code, g, "units");
          break;
        case 900:
        case 910:
          set_once(distance_code, g, "distance mode");
          break;
        case 901:
        case 911:
          set_once(arc_distance_code, g, "arc distance mode");
          break;
        case 40:
          used |= bit('P');
          break;  // dwell
        case 400:
          break;  // cutter compensation off
        case 410:
        case 411:
        case 420:
        case 421:
          fail("cutter radius compensation (" + code_name('G', g) +
               ") is not supported: the path would be offset by the tool radius");
        case 430:
        case 431:
        case 432:
        case 490:
          used |= bit('H');
          break;  // tool length offsets: programmed points stay the tool tip
        case 540:
        case 550:
        case 560:
        case 570:
        case 580:
        case 590:
        case 591:
        case 592:
        case 593:
          break;  // work coordinate systems: the program's coordinates are taken as the job's
        case 610:
        case 611:
        case 640:
          used |= bit('P') | bit('Q');
          break;  // path blending: the programmed path is used
        case 940:
          feed_per_minute_ = true;
          break;
        case 930:
        case 950:
          feed_per_minute_ = false;
          warn(code_name('G', g) + ": feed is not in units per minute; moves record feed 0");
          break;
        case 980:
        case 990:
          break;  // canned-cycle retract mode
        case 281:
        case 301:
          break;  // store the home position: no motion
        case 280:
        case 300:
          if (home_code != 0) fail("two home codes on one line");
          home_code = g;
          break;
        case 921:
        case 922:
          break;  // cancel G92 offsets (never set: G92 is refused)
        case 100: {
          const double l = block.has('L') ? block.get('L') : -1.0;
          if (l == 1.0 || l == 10.0 || l == 11.0) {
            used |= bit('L') | bit('P') | bit('R') | bit('I') | bit('J') | bit('Q') | bit('X') | bit('Y') |
                    bit('Z');
            warn("G10 L" + format_number(l) + " (tool table) ignored");
            tool_table_line = true;
            break;
          }
          fail("G10 (setting coordinate offsets) is not supported: it moves the program's origin");
        }
        case 50:
        case 51:
        case 52:
        case 53:
          fail("spline motion (" + code_name('G', g) + ") is not supported");
        case 70:
          fail("lathe diameter mode (G7) is not supported");
        case 160:
          fail("polar coordinates (G16) are not supported");
        case 330:
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
        case 520:
        case 920:
        case 923:
          fail("coordinate offsets (" + code_name('G', g) + ") are not supported: they move the origin");
        case 530:
          fail("machine-coordinate moves (G53) are not supported: the machine origin is unknown");
        case 680:
          fail("coordinate rotation (G68) is not supported");
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
          fail("canned cycles (" + code_name('G', g) + ") are not supported");
        default:
          warn("unknown code " + code_name('G', g) + " ignored");
          break;
      }
    }
    if (plane_code >= 0) plane_ = plane_code == 170 ? Plane::XY : plane_code == 180 ? Plane::XZ : Plane::YZ;
    if (units_code >= 0) {
      set_program_units(units_code == 200 ? Units::Inch : Units::Millimetre);
      units_declared_ = true;
    }
    if (distance_code >= 0) incremental_ = distance_code == 910;
    if (arc_distance_code >= 0) incremental_centre_ = arc_distance_code == 911;
    if (motion_code >= 0) {
      motion_given = true;
      motion = motion_code == 0    ? Motion::Rapid
               : motion_code == 10 ? Motion::Linear
               : motion_code == 20 ? Motion::ArcClockwise
                                   : Motion::ArcCounterClockwise;
    } else if (cancel_cycle) {
      motion = Motion::None;
    }
    if (home_code != 0 && motion_code >= 0 && (block.present & (bit('X') | bit('Y') | bit('Z'))) != 0)
      fail(code_name('G', home_code) + " and " + code_name('G', motion_code) + " both use the axis words");
  }

  void check_other_axes(const Block& block, std::uint32_t& used) {
    for (char letter : {'A', 'B', 'C', 'U', 'V', 'W'}) {
      if (!block.has(letter)) continue;
      used |= bit(letter);
      if (block.get(letter) != 0.0)
        fail(std::string("axis ") + letter + " is not supported (3-axis X, Y, Z reader)");
      warn(std::string(1, letter) + "0 ignored (3-axis reader)");
    }
  }

  void warn_unused(const Block& block, std::uint32_t used) {
    const std::uint32_t unused = block.present & ~used;
    if (unused == 0) return;
    for (int k = 0; k < 26; ++k) {
      if ((unused & (std::uint32_t{1} << k)) == 0) continue;
      const char letter = static_cast<char>('A' + k);
      const std::string word = letter + format_number(block.value[k]);
      if (std::strchr("IJKRPQLHDXYZ", letter))
        warn(word + " ignored: nothing on this line uses it");
      else
        warn("unknown word " + word + " ignored");
    }
  }

  /// Programmed target of the axis words in job units; axes whose value stays unknown are flagged.
  Eigen::Vector3d target(const Block& block, std::array<bool, 3>& known_after) const {
    Eigen::Vector3d end = position_;
    known_after = known_;
    for (int a = 0; a < 3; ++a) {
      if (!block.has(kAxisLetters[a])) continue;
      const double v = block.get(kAxisLetters[a]) * scale_;
      if (incremental_) {
        end[a] += v;  // stays unknown if it was unknown
      } else {
        end[a] = v;
        known_after[a] = true;
      }
    }
    return end;
  }

  bool all_known() const { return known_[0] && known_[1] && known_[2]; }

  Move make_move(MoveKind kind, const Eigen::Vector3d& end) const {
    Move move;
    move.kind = kind;
    move.start = position_;
    move.end = end;
    move.tool = current_tool_;
    move.line = line_;
    move.feed = feed_per_minute_ ? feed_program_ * scale_ : 0.0;
    move.spindle = spindle_;
    return move;
  }

  void emit(Move move) {
    if (move.tool == options_.initial_tool) result_.tools_used.insert(move.tool);
    result_.path.moves.push_back(std::move(move));
  }

  void straight(const Block& block, MoveKind kind) {
    std::array<bool, 3> known_after;
    const Eigen::Vector3d end = target(block, known_after);
    // Start-position rule: until X, Y and Z are all known, motions only establish the position.
    if (all_known() && end != position_) emit(make_move(kind, end));
    position_ = end;
    known_ = known_after;
  }

  void go_home(const Block& block, int code10) {
    const std::string name = code_name('G', code10);
    std::string homed;
    if ((block.present & (bit('X') | bit('Y') | bit('Z'))) != 0) {
      straight(block, MoveKind::Rapid);  // the intermediate point, as G0 would reach it
      for (int a = 0; a < 3; ++a)
        if (block.has(kAxisLetters[a])) {
          known_[a] = false;
          homed += kAxisLetters[a];
        }
    } else {
      known_ = {false, false, false};
      homed = "XYZ";
    }
    warn(name + " goes to the machine's stored position, which the program does not give: " + homed +
         " unknown until programmed again (no move is made until X, Y and Z are known)");
  }

  void arc(const Block& block, bool clockwise, std::uint32_t& used) {
    used |= bit('X') | bit('Y') | bit('Z') | bit('I') | bit('J') | bit('K') | bit('R') | bit('P');
    const PlaneAxes axes = axes_of(plane_);
    if (!all_known())
      fail("arc from an unknown position: program X, Y and Z with G0/G1 before the first arc");
    std::array<bool, 3> known_after;
    const Eigen::Vector3d end = target(block, known_after);
    const Eigen::Vector3d start = position_;

    int turns = 1;
    if (block.has('P')) {
      const double p = block.get('P');
      if (p < 1.0 || p != std::floor(p) || p > 1e6)
        fail("arc P (number of turns) must be a positive integer");
      turns = static_cast<int>(p);
    }
    const bool has_radius = block.has('R');
    const bool has_first_offset = block.has(kOffsetLetters[axes.first]);
    const bool has_second_offset = block.has(kOffsetLetters[axes.second]);
    const char normal_offset = kOffsetLetters[axes.normal];
    if (has_radius && (has_first_offset || has_second_offset))
      fail("arc with both R and an I/J/K centre: give one or the other");
    if (!has_radius && !has_first_offset && !has_second_offset) {
      if (block.has(normal_offset))
        fail(std::string("arc in ") + axes.code + " has only " + normal_offset +
             ", which is not an offset in this plane");
      fail("arc with neither an I/J/K centre nor an R radius");
    }
    if (block.has(normal_offset))
      warn(std::string(1, normal_offset) + format_number(block.get(normal_offset)) +
           " ignored: not an offset in " + axes.code);

    const double s1 = start[axes.first], s2 = start[axes.second];
    const double e1 = end[axes.first], e2 = end[axes.second];
    double c1 = 0.0, c2 = 0.0;
    if (has_radius) {
      const double radius = block.get('R') * scale_;
      if (!block.has(kAxisLetters[axes.first]) && !block.has(kAxisLetters[axes.second]))
        fail(std::string("R-format arc needs an end point in ") + axes.code);
      const double d1 = e1 - s1, d2 = e2 - s2;
      const double chord = std::hypot(d1, d2);
      if (chord == 0.0) fail("R-format arc ends where it starts: a full circle needs an I/J/K centre");
      const double abs_radius = std::abs(radius);
      double half = chord / 2.0;
      if (half - abs_radius > tolerances_.radius_reach)
        fail("arc radius R" + format_number(block.get('R')) +
             " is too small to reach the end point (half chord " + format_number(half / scale_) + ")");
      half = std::min(half, abs_radius);
      const double offset = std::sqrt(std::max(0.0, abs_radius * abs_radius - half * half));
      // Centre to the right of the chord for a short clockwise or long counter-clockwise arc.
      const bool right = clockwise == (radius > 0.0);
      const double side = right ? -1.0 : 1.0;
      c1 = (s1 + e1) / 2.0 + side * offset * (-d2 / chord);
      c2 = (s2 + e2) / 2.0 + side * offset * (d1 / chord);
    } else {
      const double i1 = has_first_offset ? block.get(kOffsetLetters[axes.first]) * scale_ : 0.0;
      const double i2 = has_second_offset ? block.get(kOffsetLetters[axes.second]) * scale_ : 0.0;
      if (incremental_centre_) {
        c1 = s1 + i1;
        c2 = s2 + i2;
      } else {
        if (!has_first_offset || !has_second_offset)
          fail(std::string("absolute arc centre (G90.1) needs both ") + kOffsetLetters[axes.first] + " and " +
               kOffsetLetters[axes.second]);
        c1 = i1;
        c2 = i2;
      }
      const double r_start = std::hypot(s1 - c1, s2 - c2);
      const double r_end = std::hypot(e1 - c1, e2 - c2);
      if (r_start < tolerances_.radius_reach || r_end < tolerances_.radius_reach)
        fail("zero-radius arc (start or end on the centre)");
      const double mismatch = std::abs(r_start - r_end);
      const double relative = mismatch / std::max(r_start, r_end);
      if (mismatch > tolerances_.radius_mismatch ||
          (relative > kRadiusMismatchRelative && mismatch > tolerances_.radius_mismatch_min))
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
    const double sweep = clockwise ? -turn : turn;

    Move move = make_move(MoveKind::Arc, end);
    move.center[axes.first] = c1;
    move.center[axes.second] = c2;
    move.center[axes.normal] = start[axes.normal];
    move.axis = Eigen::Vector3d::Unit(axes.normal);
    move.sweep = sweep;
    emit(std::move(move));
    position_ = end;
    known_ = known_after;
  }

  void end_program(const std::string& code) {
    ended_ = true;
    end_code_ = code;
  }

  void finish_word_counts() {
    auto& counts = result_.word_counts;
    for (int k = 0; k < 26; ++k)
      if (letter_counts_[k] != 0) counts[std::string(1, static_cast<char>('A' + k))] = letter_counts_[k];
    for (const auto& [code10, n] : g_counts_) counts[code_name('G', code10)] += n;
    for (const auto& [code10, n] : m_counts_) counts[code_name('M', code10)] += n;
  }

  const std::string& name_;
  const GcodeOptions& options_;
  GcodeResult result_;
  Block block_;
  int line_ = 0;

  // Machine state, positions in job units.
  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
  std::array<bool, 3> known_{false, false, false};
  Motion motion_ = Motion::None;
  Plane plane_ = Plane::XY;
  Units program_units_ = Units::Millimetre;
  double scale_ = 1.0;          ///< job units per program unit
  ArcTolerances tolerances_{};  ///< in job units
  bool units_declared_ = false, units_warned_ = false;
  bool incremental_ = false;
  bool incremental_centre_ = true;  // G91.1 is the RS-274/NGC default
  bool feed_per_minute_ = true;
  double feed_program_ = 0.0;  ///< F in program units per minute
  double spindle_ = 0.0;
  int current_tool_ = 0;
  std::optional<int> selected_tool_;

  bool ended_ = false;
  int ended_after_line_ = 0;
  std::string end_code_;

  std::array<int, 26> letter_counts_{};
  std::unordered_map<int, int> g_counts_, m_counts_;
};

}  // namespace

GcodeResult parse_gcode(std::istream& in, const std::string& name, const GcodeOptions& options) {
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw IoError(name + ": read error");
  Reader reader(name, options);
  return reader.run(text);
}

GcodeResult read_gcode(const std::string& path, const GcodeOptions& options) {
  const std::string text = read_regular_file(path, "G-code file");
  Reader reader(path, options);
  return reader.run(text);
}

}  // namespace morph
