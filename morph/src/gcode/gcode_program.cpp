// SPDX-License-Identifier: Apache-2.0
// One pass over the program text: the O-word lines and how their blocks pair up.
#include "gcode/gcode_program.h"

#include <algorithm>
#include <cstring>

namespace morph::gcode {
namespace {

bool is_loop_start(const OLine& l) {
  return (l.kind == OKind::While && !l.closes_do) || l.kind == OKind::Do || l.kind == OKind::Repeat;
}

std::string name_of(const OLine& l) {
  return "o" + l.label + " " + to_string(l.kind);
}

}  // namespace

ProgramIndex::ProgramIndex(std::string_view text) {
  std::size_t begin = 0;
  int line_number = 0;
  while (begin < text.size()) {
    const char* newline =
        static_cast<const char*>(std::memchr(text.data() + begin, '\n', text.size() - begin));
    const std::size_t end = newline ? static_cast<std::size_t>(newline - text.data()) : text.size();
    ++line_number;
    const std::string_view line = text.substr(begin, end - begin);
    // Most lines hold no 'o' at all; only those are looked at closely.
    if (std::any_of(line.begin(), line.end(), [](char c) { return (c | 0x20) == 'o'; })) {
      OLine o;
      o.begin = begin;
      o.end = end;
      o.line = line_number;
      try {
        if (const std::optional<OWordHead> head = o_word_head(line)) {
          o.kind = head->kind;
          o.label = head->label;
          add(std::move(o));
        }
      } catch (const BlockError& e) {
        o.kind = OKind::ProgramNumber;
        o.problem = e.what();
        lines_.push_back(std::move(o));
      }
    }
    begin = end + 1;
  }
  close_open();
}

void ProgramIndex::add(OLine o) {
  const std::size_t k = lines_.size();
  auto open_top = [&](OKind kind) -> std::size_t {
    if (open_.empty()) return kNone;
    const OLine& top = lines_[open_.back()];
    return top.kind == kind && top.label == o.label ? open_.back() : kNone;
  };
  auto mismatch = [&](const char* expected) {
    o.problem = name_of(o) + " without a matching o" + o.label + " " + expected;
    if (!open_.empty()) o.problem += " (the open block is " + name_of(lines_[open_.back()]) + ")";
  };
  switch (o.kind) {
    case OKind::Sub:
      for (std::size_t s : open_)
        if (lines_[s].kind == OKind::Sub) o.problem = "a sub cannot be defined inside another sub";
      if (subs_.count(o.label)) o.problem = "o" + o.label + " sub is defined twice";
      subs_.emplace(o.label, k);
      open_.push_back(k);
      last_branch_.push_back(kNone);
      break;
    case OKind::If:
      open_.push_back(k);
      last_branch_.push_back(k);
      break;
    case OKind::Do:
    case OKind::Repeat:
      open_.push_back(k);
      last_branch_.push_back(kNone);
      break;
    case OKind::While: {
      const std::size_t d = open_top(OKind::Do);
      if (d != kNone) {
        o.closes_do = true;
        o.partner = d;
        lines_[d].partner = k;
        open_.pop_back();
        last_branch_.pop_back();
      } else {
        open_.push_back(k);
        last_branch_.push_back(kNone);
      }
      break;
    }
    case OKind::ElseIf:
    case OKind::Else: {
      const std::size_t i = open_top(OKind::If);
      if (i == kNone) {
        mismatch("if");
        break;
      }
      const std::size_t last = last_branch_.back();
      if (lines_[last].kind == OKind::Else) {
        o.problem = name_of(o) + " after o" + o.label + " else";
        break;
      }
      lines_[last].next_branch = k;
      last_branch_.back() = k;
      break;
    }
    case OKind::EndIf: {
      const std::size_t i = open_top(OKind::If);
      if (i == kNone) {
        mismatch("if");
        break;
      }
      lines_[last_branch_.back()].next_branch = k;
      for (std::size_t b = i; b != k && b != kNone; b = lines_[b].next_branch) lines_[b].partner = k;
      o.partner = i;
      open_.pop_back();
      last_branch_.pop_back();
      break;
    }
    case OKind::EndSub:
    case OKind::EndWhile:
    case OKind::EndRepeat: {
      const OKind start = o.kind == OKind::EndSub     ? OKind::Sub
                          : o.kind == OKind::EndWhile ? OKind::While
                                                      : OKind::Repeat;
      const std::size_t s = open_top(start);
      if (s == kNone) {
        mismatch(to_string(start));
        break;
      }
      o.partner = s;
      lines_[s].partner = k;
      open_.pop_back();
      last_branch_.pop_back();
      break;
    }
    case OKind::Break:
    case OKind::Continue:
    case OKind::Return: {
      for (auto it = open_.rbegin(); it != open_.rend(); ++it) {
        const OLine& l = lines_[*it];
        // A return leaves the sub it is in, whatever its label (as in LinuxCNC).
        const bool fits =
            o.kind == OKind::Return ? l.kind == OKind::Sub : is_loop_start(l) && l.label == o.label;
        if (fits) {
          o.loop = *it;
          break;
        }
      }
      if (o.loop == kNone)
        o.problem = name_of(o) + (o.kind == OKind::Return ? std::string(" outside a sub")
                                                          : " outside a loop labelled o" + o.label);
      break;
    }
    default:
      break;
  }
  lines_.push_back(std::move(o));
}

void ProgramIndex::close_open() {
  for (std::size_t s : open_) {
    OLine& l = lines_[s];
    if (l.problem.empty())
      l.problem = name_of(l) + " is never closed (no matching o" + l.label + " " +
                  (l.kind == OKind::Sub      ? "endsub"
                   : l.kind == OKind::If     ? "endif"
                   : l.kind == OKind::Do     ? "while"
                   : l.kind == OKind::Repeat ? "endrepeat"
                                             : "endwhile") +
                  ")";
  }
}

std::size_t ProgramIndex::sub(const std::string& label) const {
  const auto it = subs_.find(label);
  return it == subs_.end() ? kNone : it->second;
}

std::size_t ProgramIndex::first_at_or_after(std::size_t offset) const {
  const auto it = std::lower_bound(lines_.begin(), lines_.end(), offset,
                                   [](const OLine& l, std::size_t o) { return l.begin < o; });
  return static_cast<std::size_t>(it - lines_.begin());
}

}  // namespace morph::gcode
