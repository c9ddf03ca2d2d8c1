// SPDX-License-Identifier: Apache-2.0
// Lexing one line into a Block (numbers and expressions are in gcode_expression.cpp).
#include "gcode/gcode_block.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <optional>

namespace morph::gcode {
namespace {

bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

struct Keyword {
  const char* text;
  OKind kind;
};
constexpr Keyword kKeywords[] = {
    {"endsub", OKind::EndSub}, {"sub", OKind::Sub},       {"call", OKind::Call},
    {"return", OKind::Return}, {"elseif", OKind::ElseIf}, {"else", OKind::Else},
    {"endif", OKind::EndIf},   {"if", OKind::If},         {"endwhile", OKind::EndWhile},
    {"while", OKind::While},   {"do", OKind::Do},         {"endrepeat", OKind::EndRepeat},
    {"repeat", OKind::Repeat}, {"break", OKind::Break},   {"continue", OKind::Continue},
};

/// Reads an O-word label at `i` (just after the 'o') of a normalized line.
std::string read_label(std::string_view s, std::size_t& i) {
  if (i < s.size() && s[i] == '<') {
    const std::size_t close = s.find('>', i);
    if (close == std::string_view::npos) fail("O-word label '<' is not closed with '>'");
    std::string label(s.substr(i, close + 1 - i));
    i = close + 1;
    return label;
  }
  if (i < s.size() && (s[i] == '[' || s[i] == '#'))
    fail("computed O-word labels (o[...] or o#) are not supported: write o<name> or o<number>");
  const std::size_t begin = i;
  while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
  if (i == begin) fail("the letter O has no number or <name>");
  long number = 0;
  std::from_chars(s.data() + begin, s.data() + i, number);  // canonical: o0100 is o100
  return std::to_string(number);
}

OKind read_keyword(std::string_view s, std::size_t& i) {
  for (const Keyword& k : kKeywords) {
    const std::string_view text(k.text);
    if (s.substr(i, text.size()) == text) {
      i += text.size();
      return k.kind;
    }
  }
  return OKind::ProgramNumber;
}

/// Lower case without blanks outside comments (LinuxCNC ignores both outside comments).
void normalize_into(std::string_view line, std::string& s) {
  s.resize(line.size());
  char* out = s.data();
  bool comment = false;
  for (std::size_t k = 0; k < line.size(); ++k) {
    const char c = line[k];
    if (!comment && c > ' ' && c != ';' && c != '(') {  // the common case: a word character
      *out++ = (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
      continue;
    }
    if (comment) {
      *out++ = c;
      if (c == ')') comment = false;
      continue;
    }
    if (c == ';') {
      std::memcpy(out, line.data() + k, line.size() - k);
      out += line.size() - k;
      break;
    }
    if (is_blank(c)) continue;
    if (c == '(') comment = true;
    *out++ = (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
  }
  s.resize(static_cast<std::size_t>(out - s.data()));
}

}  // namespace

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

const char* to_string(OKind kind) {
  for (const Keyword& k : kKeywords)
    if (k.kind == kind) return k.text;
  return kind == OKind::ProgramNumber ? "program number" : "";
}

void BlockReader::normalize(std::string_view line) {
  normalize_into(line, s_);
}

void BlockReader::read(std::string_view line, Block& block) {
  block.present = 0;
  block.g_count = 0;
  block.m_count = 0;
  block.line_number = false;
  block.polar_present = 0;
  block.block_delete = false;
  block.assignments.clear();
  block.o_kind = OKind::None;
  block.note = Note::None;
  depth_ = 0;
  normalize(line);
  std::size_t i = 0;
  if (at(0) == '/') {
    block.block_delete = true;
    i = 1;
  }
  bool first_word = true;
  while (i < s_.size()) {
    const char c = s_[i];
    if (c == '(') {
      read_comment(i, block);
      continue;
    }
    if (c == ';') break;
    if (c == ')') fail("')' without an opening '('");
    if (c == '/') fail("'/' (block delete) is only allowed at the start of a line");
    if (c == '#') {
      ++i;
      Assignment a;
      if (at(i) == '<')
        a.name = parameter_name(i);
      else
        a.number = parameter_number(i);
      if (at(i) != '=') fail("expected '=' after the parameter in an assignment");
      ++i;
      a.value = real_value(i, '=');
      block.assignments.push_back(std::move(a));
      first_word = false;
      continue;
    }
    if (c == '@' || c == '^') {  // polar radius and angle (LinuxCNC)
      const unsigned which = c == '@' ? 0 : 1;
      ++i;
      if (block.polar_present & (1u << which)) fail(std::string("two ") + c + " words on one line");
      block.polar[which] = real_value(i, c);
      block.polar_present |= 1u << which;
      first_word = false;
      continue;
    }
    if (c < 'a' || c > 'z') fail(std::string("unexpected character '") + c + "'");
    ++i;
    if (c == 'n' && first_word) {
      block.line_number = true;
      while (at(i) >= '0' && at(i) <= '9') ++i;
      if (at(i) == '.') fail("malformed line number after N");
      continue;
    }
    first_word = false;
    if (c == 'o') {
      read_o_word(i, block);
      return;
    }
    read_word(c, i, block);
  }
}

void BlockReader::read_comment(std::size_t& i, Block& block) {
  const std::size_t close = s_.find(')', i + 1);
  const std::size_t nested = s_.find('(', i + 1);
  if (close == std::string::npos) fail("comment '(' is not closed on its line (comments cannot span lines)");
  if (nested < close) fail("nested '(' inside a comment");
  std::string_view text = std::string_view(s_).substr(i + 1, close - i - 1);
  i = close + 1;
  std::size_t k = 0;
  while (k < text.size() && is_blank(text[k])) ++k;
  text.remove_prefix(k);
  auto starts = [&](std::string_view word) {
    if (text.size() <= word.size() || text[word.size()] != ',') return false;
    for (std::size_t n = 0; n < word.size(); ++n)
      if ((text[n] | 0x20) != word[n]) return false;
    return true;
  };
  Note note = Note::None;
  std::size_t skip = 0;
  if (starts("msg")) {
    note = Note::Message;
    skip = 4;
  } else if (starts("debug")) {
    note = Note::Debug;
    skip = 6;
  } else if (starts("print")) {
    note = Note::Print;
    skip = 6;
  }
  if (note == Note::None) return;
  block.note = note;
  block.note_text = note == Note::Message ? std::string(text.substr(skip)) : substitute(text.substr(skip));
}

/// DEBUG and PRINT texts show parameter values as LinuxCNC does ("%lf").
std::string BlockReader::substitute(std::string_view text) const {
  std::string out;
  for (std::size_t k = 0; k < text.size(); ++k) {
    if (text[k] != '#') {
      out += text[k];
      continue;
    }
    std::optional<double> value;
    std::size_t end = k + 1;
    if (end < text.size() && text[end] == '<') {
      const std::size_t close = text.find('>', end);
      if (close != std::string_view::npos) {
        std::string name;
        for (std::size_t n = end + 1; n < close; ++n)
          if (!is_blank(text[n]))
            name += static_cast<char>(text[n] >= 'A' && text[n] <= 'Z' ? text[n] + 32 : text[n]);
        value = parameters_.named(name);
        end = close + 1;
      }
    } else {
      int number = 0;
      const auto parsed = std::from_chars(text.data() + end, text.data() + text.size(), number);
      if (parsed.ec == std::errc() && number >= 1 && number <= param::kLast) {
        value = parameters_.numbered(number);
        end = static_cast<std::size_t>(parsed.ptr - text.data());
      }
    }
    if (!value) {
      out += text[k];
      continue;
    }
    char buffer[64];
    std::snprintf(buffer, sizeof buffer, "%f", *value);
    out += buffer;
    k = end - 1;
  }
  return out;
}

void BlockReader::read_o_word(std::size_t& i, Block& block) {
  block.o_label = read_label(s_, i);
  block.o_kind = read_keyword(s_, i);
  block.o_args.clear();
  const OKind kind = block.o_kind;
  const bool takes_value = kind == OKind::Call || kind == OKind::If || kind == OKind::ElseIf ||
                           kind == OKind::While || kind == OKind::Repeat || kind == OKind::Return ||
                           kind == OKind::EndSub;
  while (i < s_.size() && s_[i] == '[' && takes_value) {
    block.o_args.push_back(bracketed(i));
    if (kind != OKind::Call) break;
  }
  const bool needs_value =
      kind == OKind::If || kind == OKind::ElseIf || kind == OKind::While || kind == OKind::Repeat;
  if (needs_value && block.o_args.empty())
    fail("o" + block.o_label + " " + to_string(kind) + " needs a condition or count in [...]");
  // Only comments may follow an O-word (LinuxCNC allows no other words on its line).
  while (i < s_.size()) {
    if (s_[i] == '(') {
      read_comment(i, block);
      continue;
    }
    if (s_[i] == ';') break;
    if (kind == OKind::ProgramNumber)
      fail("O-word o" + block.o_label +
           " with an unknown keyword: expected sub, endsub, call, return, if, "
           "elseif, else, endif, while, endwhile, do, repeat, endrepeat, break or continue");
    fail("unexpected '" + s_.substr(i) + "' after o" + block.o_label + " " + to_string(kind) +
         " (an O-word line holds nothing else)");
  }
}

void BlockReader::read_word(char letter, std::size_t& i, Block& block) {
  const char upper = static_cast<char>(letter - 'a' + 'A');
  const double value = real_value(i, upper);
  if (letter == 'g' || letter == 'm') {
    const double tenths = value * 10.0;
    const double rounded = std::round(tenths);
    if (value < 0.0 || std::abs(tenths - rounded) > 1e-6 || rounded > 1e7)
      fail("malformed code " + std::string(1, upper) + format_number(value));
    const int code10 = static_cast<int>(rounded);
    if (letter == 'm' && code10 % 10 != 0) fail("malformed code M" + format_number(value));
    if (letter == 'g') {
      if (block.g_count == static_cast<int>(block.g_codes.size())) fail("too many G codes on one line");
      block.g_codes[static_cast<std::size_t>(block.g_count++)] = code10;
    } else {
      if (block.m_count == static_cast<int>(block.m_codes.size())) fail("too many M codes on one line");
      block.m_codes[static_cast<std::size_t>(block.m_count++)] = code10;
    }
    return;
  }
  if (block.has(letter)) fail(std::string("two ") + upper + " words on one line");
  block.present |= bit(letter);
  block.value[static_cast<std::size_t>(letter_index(letter))] = value;
}

std::optional<OWordHead> o_word_head(std::string_view line) {
  std::string s;
  normalize_into(line, s);
  std::size_t i = 0;
  if (i < s.size() && s[i] == '/') ++i;
  while (i < s.size() && s[i] == '(') {
    const std::size_t close = s.find(')', i);
    if (close == std::string::npos) return std::nullopt;
    i = close + 1;
  }
  if (i < s.size() && s[i] == 'n') {
    ++i;
    while (i < s.size() && s[i] >= '0' && s[i] <= '9') ++i;
  }
  if (i >= s.size() || s[i] != 'o') return std::nullopt;
  ++i;
  OWordHead head;
  head.label = read_label(s, i);
  head.kind = read_keyword(s, i);
  return head;
}

}  // namespace morph::gcode
