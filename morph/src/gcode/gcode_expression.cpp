// SPDX-License-Identifier: Apache-2.0
// Numbers, parameter references and expressions, with LinuxCNC's rules: binary operators of five
// precedence levels (** ; * / MOD ; + - ; EQ NE GT GE LT LE ; AND OR XOR), left to right within a
// level; EQ/NE compare within 1e-4, the others exactly; angles in degrees; MOD is never negative.
#include <charconv>
#include <cmath>

#include "gcode/gcode_block.h"

namespace morph::gcode {
namespace {

constexpr double kEqualTolerance = 1e-4;  // LinuxCNC's TOLERANCE_EQUAL (measured with rs274 2.9)
constexpr double kDegree = M_PI / 180.0;

enum class Op { None, Power, Times, Divide, Mod, Plus, Minus, Eq, Ne, Gt, Ge, Lt, Le, And, Or, Xor };

struct OpText {
  const char* text;
  Op op;
  int precedence;
};
constexpr OpText kOps[] = {
    {"**", Op::Power, 6}, {"*", Op::Times, 5}, {"/", Op::Divide, 5}, {"mod", Op::Mod, 5}, {"+", Op::Plus, 4},
    {"-", Op::Minus, 4},  {"eq", Op::Eq, 3},   {"ne", Op::Ne, 3},    {"gt", Op::Gt, 3},   {"ge", Op::Ge, 3},
    {"lt", Op::Lt, 3},    {"le", Op::Le, 3},   {"and", Op::And, 2},  {"or", Op::Or, 2},   {"xor", Op::Xor, 2},
};

const OpText* peek_op(std::string_view s, std::size_t i) {
  for (const OpText& o : kOps) {
    const std::string_view text(o.text);
    if (s.substr(i, text.size()) == text) return &o;
  }
  return nullptr;
}

double apply(Op op, double a, double b) {
  switch (op) {
    case Op::Power:
      if (a < 0.0 && std::floor(b) != b) fail("attempt to raise a negative number to a non-integer power");
      return std::pow(a, b);
    case Op::Times:
      return a * b;
    case Op::Divide:
      if (b == 0.0) fail("division by zero in an expression");
      return a / b;
    case Op::Mod: {
      if (b == 0.0) fail("MOD by zero in an expression");
      const double r = std::fmod(a, b);
      return r < 0.0 ? r + std::abs(b) : r;
    }
    case Op::Plus:
      return a + b;
    case Op::Minus:
      return a - b;
    case Op::Eq:
      return std::abs(a - b) < kEqualTolerance ? 1.0 : 0.0;
    case Op::Ne:
      return std::abs(a - b) >= kEqualTolerance ? 1.0 : 0.0;
    case Op::Gt:
      return a > b ? 1.0 : 0.0;
    case Op::Ge:
      return a >= b ? 1.0 : 0.0;
    case Op::Lt:
      return a < b ? 1.0 : 0.0;
    case Op::Le:
      return a <= b ? 1.0 : 0.0;
    case Op::And:
      return (a == 0.0 || b == 0.0) ? 0.0 : 1.0;
    case Op::Or:
      return (a != 0.0 || b != 0.0) ? 1.0 : 0.0;
    case Op::Xor:
      return ((a == 0.0) != (b == 0.0)) ? 1.0 : 0.0;
    case Op::None:
      break;
  }
  return a;
}

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

}  // namespace

double BlockReader::real_value(std::size_t& i, char letter) {
  // Nesting is recursion here: bound it so that a hostile line cannot exhaust the stack.
  struct Depth {
    int& depth;
    explicit Depth(int& d) : depth(d) {
      if (++depth > 256) fail("expression nested more than 256 deep");
    }
    ~Depth() { --depth; }
  } guard(depth_);
  const char c = at(i);
  double v;
  if (c == '[') {
    v = bracketed(i);
  } else if (c == '#') {
    v = parameter(i);
  } else if ((c == '+' || c == '-') && at(i + 1) != '\0' && !is_digit(at(i + 1)) && at(i + 1) != '.') {
    ++i;
    v = real_value(i, letter);
    if (c == '-') v = -v;
  } else if (c >= 'a' && c <= 'z') {
    v = unary_function(i, letter);
  } else {
    v = number(i, letter);
  }
  if (std::isnan(v)) fail("calculation resulted in 'not a number'");
  if (std::isinf(v)) fail("calculation resulted in 'infinity'");
  return v;
}

double BlockReader::bracketed(std::size_t& i) {
  ++i;  // '['
  const double v = binary(i, 1);
  if (at(i) != ']') {
    if (at(i) == '\0') fail("expression '[' is not closed with ']'");
    fail(std::string("unexpected '") + at(i) + "' in an expression (expected an operator or ']')");
  }
  ++i;
  return v;
}

double BlockReader::binary(std::size_t& i, int min_precedence) {
  double left = real_value(i, '[');
  while (const OpText* op = peek_op(s_, i)) {
    if (op->precedence < min_precedence) break;
    i += std::string_view(op->text).size();
    const double right = binary(i, op->precedence + 1);
    left = apply(op->op, left, right);
  }
  return left;
}

double BlockReader::unary_function(std::size_t& i, char letter) {
  static constexpr const char* kNames[] = {"abs", "acos", "asin", "atan",  "cos", "exists", "exp",
                                           "fix", "fup",  "ln",   "round", "sin", "sqrt",   "tan"};
  std::string_view name;
  for (const char* n : kNames) {
    const std::string_view text(n);
    if (std::string_view(s_).substr(i, text.size()) == text && at(i + text.size()) == '[') name = text;
  }
  if (name.empty()) fail(std::string("the letter ") + letter + " has no number");
  i += name.size();
  if (name == "exists") {
    ++i;
    if (at(i) != '#' || at(i + 1) != '<') fail("EXISTS needs a named parameter: EXISTS[#<name>]");
    ++i;
    const std::string n = parameter_name(i);
    if (at(i) != ']') fail("EXISTS[#<name>] is not closed with ']'");
    ++i;
    return parameters_.exists(n) ? 1.0 : 0.0;
  }
  const double x = bracketed(i);
  if (name == "atan") {
    if (at(i) != '/' || at(i + 1) != '[') fail("ATAN needs the form ATAN[y]/[x]");
    ++i;
    const double denominator = bracketed(i);
    return std::atan2(x, denominator) / kDegree;
  }
  if (name == "abs") return std::abs(x);
  if (name == "acos" || name == "asin") {
    if (x < -1.0 || x > 1.0) fail("argument to " + std::string(name) + " out of range [-1, 1]");
    return (name == "acos" ? std::acos(x) : std::asin(x)) / kDegree;
  }
  if (name == "cos") return std::cos(x * kDegree);
  if (name == "sin") return std::sin(x * kDegree);
  if (name == "tan") return std::tan(x * kDegree);
  if (name == "exp") return std::exp(x);
  if (name == "fix") return std::floor(x);
  if (name == "fup") return std::ceil(x);
  if (name == "round") return std::round(x);
  if (name == "ln") {
    if (x <= 0.0) fail("zero or negative argument to LN");
    return std::log(x);
  }
  if (x < 0.0) fail("negative argument to SQRT");
  return std::sqrt(x);
}

double BlockReader::parameter(std::size_t& i) {
  ++i;  // '#'
  if (at(i) == '<') {
    const std::string name = parameter_name(i);
    const std::optional<double> v = parameters_.named(name);
    if (!v) fail("named parameter #<" + name + "> is not defined");
    return *v;
  }
  return parameters_.numbered(parameter_number(i));
}

int BlockReader::parameter_number(std::size_t& i) {
  const double v = real_value(i, '#');
  const double rounded = std::round(v);
  if (std::abs(v - rounded) > 1e-6 || rounded < 1.0 || rounded > param::kLast)
    fail("parameter number #" + format_number(v) + " is not an integer from 1 to 5602");
  return static_cast<int>(rounded);
}

std::string BlockReader::parameter_name(std::size_t& i) {
  const std::size_t close = s_.find('>', i);
  if (close == std::string::npos) fail("parameter name '#<' is not closed with '>'");
  std::string name = s_.substr(i + 1, close - i - 1);
  if (name.empty()) fail("empty parameter name #<>");
  i = close + 1;
  return name;
}

double BlockReader::number(std::size_t& i, char letter) {
  const std::size_t begin = i;
  bool negative = false, signed_ = false, digit = false, point = false;
  if (at(i) == '+' || at(i) == '-') {
    negative = at(i) == '-';
    signed_ = true;
    ++i;
  }
  const std::size_t digits = i;
  for (;; ++i) {
    const char c = at(i);
    if (is_digit(c)) {
      digit = true;
    } else if (c == '.' && !point) {
      point = true;
    } else {
      break;
    }
  }
  if (!digit) {
    if (signed_ || point) fail(std::string("malformed number after ") + letter);
    fail(std::string("the letter ") + letter + " has no number");
  }
  if (at(i) == '.') fail(std::string("malformed number after ") + letter + " (two '.')");
  if (i - begin > 60) fail(std::string("number after ") + letter + " is too long");
  double value = 0.0;
  const auto parsed = std::from_chars(s_.data() + digits, s_.data() + i, value);
  if (parsed.ec != std::errc() || parsed.ptr != s_.data() + i)
    fail(std::string("malformed number after ") + letter);
  return negative ? -value : value;
}

}  // namespace morph::gcode
