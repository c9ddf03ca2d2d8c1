// SPDX-License-Identifier: Apache-2.0
// The conformance suite: small programs per feature under data/gcode/conformance/, each motion
// line carrying the tool-tip positions LinuxCNC makes there, written by hand from its documentation
// as a comment:
//   G1 X#2   (expect: feed 7 0 0)
//   G81 ...  (expect: rapid 5 5 10; rapid 5 5 2; feed 5 5 -2; rapid 5 5 10)
//   G2 ...   (expect: arc 50.8 25.4 0 centre 38.1 25.4 0)
// Every move the reader makes must be expected on its line, in order (a line in a loop or a
// subroutine lists the moves of all its runs). A line with (expect-error: text) must be the one
// the reader refuses, with that text in the message. Programs start at the machine origin, in mm.
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/gcode.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Expected {
  morph::MoveKind kind;
  Eigen::Vector3d end;
  bool has_centre = false;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
};

struct Program {
  std::map<int, std::vector<Expected>> moves;  ///< by line
  int error_line = 0;
  std::string error_text;
};

std::string trim(std::string s) {
  const auto blank = [](unsigned char c) { return std::isspace(c) != 0; };
  s.erase(s.begin(), std::find_if_not(s.begin(), s.end(), blank));
  s.erase(std::find_if_not(s.rbegin(), s.rend(), blank).base(), s.end());
  return s;
}

Program read_expectations(const fs::path& path) {
  Program program;
  std::ifstream in(path);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::size_t error = line.find("(expect-error:");
    if (error != std::string::npos) {
      program.error_line = number;
      program.error_text = trim(line.substr(error + 14, line.find(')', error) - error - 14));
      continue;
    }
    const std::size_t at = line.find("(expect:");
    if (at == std::string::npos) continue;
    std::istringstream items(line.substr(at + 8, line.find(')', at) - at - 8));
    std::string item;
    while (std::getline(items, item, ';')) {
      std::istringstream words(item);
      std::string kind;
      words >> kind;
      Expected e;
      if (kind == "rapid")
        e.kind = morph::MoveKind::Rapid;
      else if (kind == "feed")
        e.kind = morph::MoveKind::Linear;
      else if (kind == "arc")
        e.kind = morph::MoveKind::Arc;
      else
        continue;  // prose
      words >> e.end.x() >> e.end.y() >> e.end.z();
      std::string centre;
      if (words >> centre && centre == "centre") {
        e.has_centre = true;
        words >> e.centre.x() >> e.centre.y() >> e.centre.z();
      }
      program.moves[number].push_back(e);
    }
  }
  return program;
}

std::vector<fs::path> conformance_programs() {
  std::vector<fs::path> programs;
  for (const auto& entry : fs::directory_iterator(std::string(MORPHMILL_TEST_DATA) + "/gcode/conformance"))
    if (entry.path().extension() == ".ngc") programs.push_back(entry.path());
  std::sort(programs.begin(), programs.end());
  return programs;
}

}  // namespace

TEST(GcodeConformance, EveryProgramMakesTheExpectedMoves) {
  const std::vector<fs::path> programs = conformance_programs();
  ASSERT_GE(programs.size(), 12u);
  int checked_moves = 0, refusals = 0;
  for (const fs::path& path : programs) {
    SCOPED_TRACE(path.filename().string());
    const Program expected = read_expectations(path);
    morph::GcodeOptions options;
    options.start = Eigen::Vector3d::Zero();
    if (expected.error_line != 0) {
      try {
        morph::read_gcode(path.string(), options);
        ADD_FAILURE() << "expected a refusal on line " << expected.error_line;
      } catch (const morph::InputError& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find(path.string() + ":" + std::to_string(expected.error_line) + ": "),
                  std::string::npos)
            << message;
        EXPECT_NE(message.find(expected.error_text), std::string::npos) << message;
        ++refusals;
      }
      continue;
    }
    ASSERT_FALSE(expected.moves.empty()) << "no (expect: ...) in the program";
    const morph::GcodeResult result = morph::read_gcode(path.string(), options);
    std::map<int, std::size_t> seen;  // moves met so far on each line
    for (const morph::Move& m : result.path.moves) {
      const auto it = expected.moves.find(m.line);
      ASSERT_NE(it, expected.moves.end()) << "unexpected move on line " << m.line;
      const std::size_t k = seen[m.line]++;
      ASSERT_LT(k, it->second.size()) << "more moves than expected on line " << m.line;
      const Expected& e = it->second[k];
      EXPECT_EQ(m.kind, e.kind) << "line " << m.line << " move " << k;
      EXPECT_LT((m.end - e.end).norm(), 1e-9)
          << "line " << m.line << " move " << k << ": (" << m.end.transpose() << ") expected ("
          << e.end.transpose() << ")";
      if (e.has_centre) {
        EXPECT_LT((m.center - e.centre).norm(), 1e-9) << "line " << m.line << " centre";
      }
      ++checked_moves;
    }
    for (const auto& [line, list] : expected.moves)
      EXPECT_EQ(seen[line], list.size()) << "line " << line << " made fewer moves than expected";
  }
  EXPECT_GT(checked_moves, 100);
  EXPECT_GE(refusals, 2);
}

TEST(GcodeConformance, MessagesAreKeptWithTheirLine) {
  morph::GcodeOptions options;
  options.start = Eigen::Vector3d::Zero();
  const morph::GcodeResult r = morph::read_gcode(
      std::string(MORPHMILL_TEST_DATA) + "/gcode/conformance/units_and_centres.ngc", options);
  ASSERT_EQ(r.messages.size(), 1u);
  EXPECT_EQ(r.messages[0].line, 9);
  EXPECT_EQ(r.messages[0].message, " conformance: units and centres done");
}
