// SPDX-License-Identifier: Apache-2.0
#pragma once
// The program as lines, and where its O-words are: one pass over the text finds every O-word
// line and pairs sub/endsub, if/elseif/else/endif, while/endwhile, do/while, repeat/endrepeat,
// so that control flow jumps to known byte offsets. Structural mistakes are kept on their line
// and raised only if that line is executed (text after the program end is never judged).
#include "gcode/gcode_block.h"

#include <cstddef>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace morph::gcode {

constexpr std::size_t kNone = static_cast<std::size_t>(-1);

struct OLine {
  std::size_t begin = 0, end = 0;  ///< byte range of the line in the text (end at its '\n')
  int line = 0;                    ///< 1-based line number
  OKind kind = OKind::None;
  std::string label;
  std::size_t partner = kNone;      ///< sub<->endsub, loop start<->loop end, if/elseif/else -> endif
  std::size_t next_branch = kNone;  ///< if/elseif -> the next elseif, else or endif
  std::size_t loop = kNone;         ///< break/continue -> their loop's start; return -> its sub
  bool closes_do = false;           ///< a `while` that ends a do-loop
  std::string problem;              ///< a structural error, raised when the line runs
};

class ProgramIndex {
 public:
  explicit ProgramIndex(std::string_view text);

  const std::vector<OLine>& lines() const { return lines_; }
  const OLine& operator[](std::size_t k) const { return lines_[k]; }
  /// Index of the sub definition with `label`, or kNone.
  std::size_t sub(const std::string& label) const;
  /// Index of the first O-line that begins at or after `offset`.
  std::size_t first_at_or_after(std::size_t offset) const;

 private:
  void add(OLine line);
  void close_open();

  std::vector<OLine> lines_;
  std::vector<std::size_t> open_;         // stack of unclosed block starts
  std::vector<std::size_t> last_branch_;  // per open if: its latest if/elseif/else
  std::map<std::string, std::size_t> subs_;
};

}  // namespace morph::gcode
