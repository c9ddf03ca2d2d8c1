// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reading one line of G-code into a Block: lexing, numbers, expressions `[...]`, parameter
// references and assignments, O-words and comments. Values are evaluated while the line is read,
// with the parameter values from before the line (LinuxCNC: assignments take effect after it).
#include "gcode/gcode_parameters.h"

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace morph::gcode {

constexpr int letter_index(char lower) {
  return lower - 'a';
}
constexpr std::uint32_t bit(char lower) {
  return std::uint32_t{1} << letter_index(lower);
}

/// G and M codes are kept as ten times their number, so G90.1 is 901.
std::string code_name(char letter, int code10);
std::string format_number(double value);

enum class OKind {
  None,
  ProgramNumber,
  Sub,
  EndSub,
  Call,
  Return,
  If,
  ElseIf,
  Else,
  EndIf,
  While,
  EndWhile,
  Do,
  Repeat,
  EndRepeat,
  Break,
  Continue
};
const char* to_string(OKind kind);

enum class Note { None, Message, Debug, Print };

struct Assignment {
  int number = 0;    ///< numbered parameter, or 0 for a named one
  std::string name;  ///< lower case, no spaces
  double value = 0.0;
};

/// One line's words. Letters other than G and M hold at most one value each.
struct Block {
  std::array<double, 26> value{};
  std::uint32_t present = 0;
  std::array<int, 16> g_codes{};
  int g_count = 0;
  std::array<int, 8> m_codes{};
  int m_count = 0;
  std::array<double, 2> polar{};  ///< @ (polar radius) and ^ (polar angle, degrees)
  unsigned polar_present = 0;     ///< bit 0: @, bit 1: ^
  bool line_number = false;       ///< an N word was read
  bool block_delete = false;      ///< the line starts with '/'
  std::vector<Assignment> assignments;
  OKind o_kind = OKind::None;
  std::string o_label;         ///< "100" for o100, "<name>" for o<name>
  std::vector<double> o_args;  ///< call arguments, or the one value of if/while/repeat/return
  Note note = Note::None;
  std::string note_text;  ///< message text, parameters substituted for DEBUG/PRINT

  bool has(char lower) const { return (present & bit(lower)) != 0; }
  double get(char lower) const { return value[static_cast<std::size_t>(letter_index(lower))]; }
  bool empty() const {
    return present == 0 && polar_present == 0 && g_count == 0 && m_count == 0 && !line_number;
  }
};

/// Reads lines into blocks, evaluating expressions against `parameters`.
class BlockReader {
 public:
  explicit BlockReader(const Parameters& parameters) : parameters_(parameters) {}
  /// Reads `line` (without its newline) into `block`. Throws BlockError.
  void read(std::string_view line, Block& block);

 private:
  void normalize(std::string_view line);
  void read_comment(std::size_t& i, Block& block);
  void read_o_word(std::size_t& i, Block& block);
  void read_word(char letter, std::size_t& i, Block& block);
  std::string substitute(std::string_view text) const;

  // Expressions (gcode_expression.cpp).
  double real_value(std::size_t& i, char letter);
  double bracketed(std::size_t& i);
  double binary(std::size_t& i, int min_precedence);
  double unary_function(std::size_t& i, char letter);
  double parameter(std::size_t& i);
  int parameter_number(std::size_t& i);
  std::string parameter_name(std::size_t& i);
  double number(std::size_t& i, char letter);
  char at(std::size_t i) const { return i < s_.size() ? s_[i] : '\0'; }

  const Parameters& parameters_;
  int depth_ = 0;  ///< nesting of values being read
  std::string s_;  ///< the line in lower case without blanks, comments kept as written
};

/// The O-word of a line without evaluating anything, for the program index: nullopt if the
/// line's first word is not an O-word.
struct OWordHead {
  OKind kind = OKind::None;
  std::string label;
};
std::optional<OWordHead> o_word_head(std::string_view line);

}  // namespace morph::gcode
