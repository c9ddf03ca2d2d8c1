// The optional comparison with LinuxCNC's own interpreter: where Debian's linuxcnc-uspace is
// installed, its standalone `rs274` runs every G-code program under data/ and MorphMill reads the
// same program; both must refuse it, or both must make the same moves (kind, end point, arc
// centre, direction and turns, tool). rs274 prints 4 decimals, so positions agree to 1e-4 of the
// program's unit. Where rs274 is not installed the test is skipped, saying so.
#include <gtest/gtest.h>
#include <morph/exceptions.h>
#include <morph/gcode.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct CanonMove {
  morph::MoveKind kind;
  Eigen::Vector3d end, center;
  int turns = 0;  ///< signed: positive counter-clockwise
  int tool = 0;
  double unit = 1.0;  ///< mm per printed unit when it was printed
  /// A straight move whose printed end is its printed start: rs274 prints 4 decimals, so this is
  /// a move of no length or one shorter than its last digit (vcarve.ngc has hundreds).
  bool printed_still = false;
  int line = 0;  ///< the program line that made it (rs274 prints the N number the copy gives each line)
};

struct Canon {
  bool refused = false;
  bool compensated = false;  ///< a tool length offset other than 0 was in effect
  std::string error;
  std::vector<CanonMove> moves;
};

bool rs274_available() {
  return std::system("command -v rs274 > /dev/null 2>&1") == 0;
}

std::vector<double> numbers(const std::string& args) {
  std::vector<double> out;
  std::string token;
  std::istringstream in(args);
  while (in >> token) {
    while (!token.empty() && (token.back() == ',')) token.pop_back();
    try {
      out.push_back(std::stod(token));
    } catch (...) {
    }
  }
  return out;
}

/// Runs rs274 on `program` (block delete on, as MorphMill's default) and reads its canonical calls
/// into tool-tip moves in machine coordinates, millimetres.
Canon run_rs274(const fs::path& program, const fs::path& var_file, const fs::path& tool_table) {
  const fs::path dir = fs::temp_directory_path() / ("morph_rs274_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string command = "cd '" + dir.string() + "' && rs274 -g -b";
  if (!var_file.empty()) {
    fs::copy_file(var_file, dir / "run.var", fs::copy_options::overwrite_existing);
    command += " -v run.var";
  }
  if (!tool_table.empty()) command += " -t '" + fs::absolute(tool_table).string() + "'";
  command += " '" + fs::absolute(program).string() + "' < /dev/null 2>&1";
  Canon canon;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) {
    canon.refused = true;
    canon.error = "cannot run rs274";
    return canon;
  }
  std::string output;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  fs::remove_all(dir);

  static const std::regex call(R"(^\s*\d+ N(\d+|\.+)\s*(\w+)\((.*)\)\s*$)");
  double unit = 1.0;
  Eigen::Vector3d g5x = Eigen::Vector3d::Zero(), g92 = Eigen::Vector3d::Zero(), tlo = Eigen::Vector3d::Zero();
  int plane = 0;  // 0 XY, 1 YZ, 2 XZ
  int tool = 0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  // machine, mm
  std::istringstream lines(output);
  std::string line;
  while (std::getline(lines, line)) {
    std::smatch m;
    if (!std::regex_match(line, m, call)) {
      if (line != "executing" && !line.empty()) canon.error += line + "\n";
      continue;
    }
    const std::string name = m[2], args = m[3];
    const int source_line = std::isdigit(static_cast<unsigned char>(m.str(1)[0])) ? std::stoi(m.str(1)) : 0;
    const std::vector<double> v = numbers(args);
    auto machine = [&](double x, double y, double z) -> Eigen::Vector3d {
      return Eigen::Vector3d(x, y, z) * unit + g5x + g92 + tlo;
    };
    if (name == "USE_LENGTH_UNITS") {
      unit = args.find("INCHES") != std::string::npos ? 25.4 : 1.0;
    } else if (name == "SET_G5X_OFFSET" && v.size() >= 4) {
      g5x = Eigen::Vector3d(v[1], v[2], v[3]) * unit;
    } else if (name == "SET_G92_OFFSET" && v.size() >= 3) {
      g92 = Eigen::Vector3d(v[0], v[1], v[2]) * unit;
    } else if (name == "USE_TOOL_LENGTH_OFFSET" && v.size() >= 3) {
      tlo = Eigen::Vector3d(v[0], v[1], v[2]) * unit;
      if (!tlo.isZero()) canon.compensated = true;
    } else if (name == "SELECT_PLANE") {
      plane = args.find("YZ") != std::string::npos ? 1 : args.find("XZ") != std::string::npos ? 2 : 0;
    } else if (name == "CHANGE_TOOL" && !v.empty()) {
      tool = static_cast<int>(v[0]);
    } else if ((name == "STRAIGHT_TRAVERSE" || name == "STRAIGHT_FEED") && v.size() >= 3) {
      const Eigen::Vector3d end = machine(v[0], v[1], v[2]);
      canon.moves.push_back(
          CanonMove{name == "STRAIGHT_FEED" ? morph::MoveKind::Linear : morph::MoveKind::Rapid, end,
                    Eigen::Vector3d::Zero(), 0, tool, unit, (end - position).norm() <= 1e-9, source_line});
      position = end;
    } else if (name == "ARC_FEED" && v.size() >= 6) {
      // (first end, second end, first centre, second centre, rotation, normal-axis end)
      static constexpr int kAxes[3][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}};
      const int* axes = kAxes[plane];
      Eigen::Vector3d end_program, centre_program;
      end_program[axes[0]] = v[0];
      end_program[axes[1]] = v[1];
      end_program[axes[2]] = v[5];
      const Eigen::Vector3d end = machine(end_program.x(), end_program.y(), end_program.z());
      centre_program = end_program;
      centre_program[axes[0]] = v[2];
      centre_program[axes[1]] = v[3];
      Eigen::Vector3d centre = machine(centre_program.x(), centre_program.y(), centre_program.z());
      centre[axes[2]] = position[axes[2]];
      canon.moves.push_back(CanonMove{morph::MoveKind::Arc, end, centre, static_cast<int>(v[4]), tool, unit,
                                      false, source_line});
      position = end;
    }
  }
  canon.refused = status != 0;
  return canon;
}

/// A LinuxCNC tool table's lengths (T<n> ... Z<length>), for programs that come with one.
std::map<int, morph::GcodeTool> read_tool_table(const fs::path& path) {
  std::map<int, morph::GcodeTool> tools;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    line = line.substr(0, line.find(';'));
    std::istringstream words(line);
    std::string word;
    int number = -1;
    morph::GcodeTool tool;
    while (words >> word) {
      const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(word[0])));
      const double value = std::atof(word.c_str() + 1);
      if (letter == 'T') number = static_cast<int>(value);
      if (letter == 'Z') tool.length_offset = value;
      if (letter == 'D') tool.diameter = value;
    }
    if (number >= 0) tools[number] = tool;
  }
  return tools;
}

std::string describe(const Eigen::Vector3d& p) {
  std::ostringstream out;
  out << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return out.str();
}

/// "" if MorphMill's move `m` (number `k`) is rs274's call `c`, else how they differ.
std::string differs(const morph::Move& m, const CanonMove& c, std::size_t k) {
  const double tolerance = 0.6e-4 * c.unit;  // half a unit in rs274's last printed digit, and a little
  const std::string where = "move " + std::to_string(k) + " (line " + std::to_string(m.line) + "): ";
  if (m.kind != c.kind)
    return where + "kind " + morph::to_string(m.kind) + " vs rs274 " + morph::to_string(c.kind);
  if ((m.end - c.end).cwiseAbs().maxCoeff() > tolerance)
    return where + "end " + describe(m.end) + " vs rs274 " + describe(c.end);
  if (m.tool != c.tool && c.tool != 0)
    return where + "tool " + std::to_string(m.tool) + " vs rs274 " + std::to_string(c.tool);
  if (m.is_arc()) {
    if ((m.center - c.center).cwiseAbs().maxCoeff() > tolerance)
      return where + "arc centre " + describe(m.center) + " vs rs274 " + describe(c.center);
    const int turns = static_cast<int>(std::ceil(std::abs(m.sweep) / (2 * M_PI) - 1e-9));
    const int signed_turns = m.sweep > 0 ? turns : -turns;
    if (signed_turns != c.turns)
      return where + "arc turns " + std::to_string(signed_turns) + " vs rs274 " + std::to_string(c.turns);
  }
  return "";
}

/// A copy of `program` in which every line starts with N<its line number> (an N word of its own is
/// replaced), so that rs274's output names the line of each call; with "M2" appended if asked.
fs::path numbered_copy(const fs::path& program, bool append_end) {
  const fs::path copy = fs::temp_directory_path() /
                        ("morph_rs274_numbered_" + std::to_string(::getpid()) + program.extension().string());
  static const std::regex own_number(R"(^\s*[Nn]\s*\d+(\.\d*)?\s*)");
  std::ifstream in(program, std::ios::binary);
  std::ofstream out(copy, std::ios::binary);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '%') {
      out << line << "\n";
      continue;
    }
    std::string prefix, rest = line;
    if (line[first] == '/') {
      prefix = line.substr(0, first + 1);
      rest = line.substr(first + 1);
    }
    std::smatch m;
    if (std::regex_search(rest, m, own_number)) rest = m.suffix();
    out << prefix << "N" << number << " " << rest << "\n";
  }
  if (append_end) out << "M2\n";
  return copy;
}

/// "" if MorphMill and rs274 agree on `program`, else the first difference. LinuxCNC refuses a
/// file with no program end and MorphMill deliberately reads it (docs/gcode.md): then rs274 runs
/// the program with M2 appended, and `*end_appended` says so.
std::string compare(const fs::path& program, bool* end_appended = nullptr) {
  fs::path var_file = program, tool_table = program;
  var_file.replace_extension(".var");
  tool_table.replace_extension(".tbl");
  if (!fs::exists(var_file)) var_file.clear();
  if (!fs::exists(tool_table)) tool_table.clear();
  fs::path numbered = numbered_copy(program, false);
  Canon canon = run_rs274(numbered, var_file, tool_table);
  if (canon.refused &&
      canon.error.find("File ended with no percent sign or program end") != std::string::npos) {
    numbered = numbered_copy(program, true);
    canon = run_rs274(numbered, var_file, tool_table);
    if (end_appended) *end_appended = true;
  }
  fs::remove(numbered);

  morph::GcodeOptions options;
  options.start = Eigen::Vector3d::Zero();  // rs274 starts at the machine origin
  options.var_file = var_file.string();
  if (var_file.empty())
    for (int k = 0; k < 3; ++k)
      options.parameters[5161 + k] = options.parameters[5181 + k] = 0.0;  // its defaults
  if (!tool_table.empty()) options.tools = read_tool_table(tool_table);
  // Without -t, rs274 runs with a tool table of its own (lengths and diameters in inches): the
  // same machine for MorphMill.
  if (tool_table.empty())
    options.tools = {{1, {0.511 * 25.4, 0.125 * 25.4}},
                     {2, {0.1 * 25.4, 0.0625 * 25.4}},
                     {3, {1.273 * 25.4, 0.201 * 25.4}}};
  morph::GcodeResult result;
  std::string refusal;
  try {
    result = morph::read_gcode(program.string(), options);
  } catch (const morph::InputError& e) {
    refusal = e.what();
  }
  if (canon.refused || !refusal.empty()) {
    if (canon.refused && !refusal.empty()) return "";
    return canon.refused ? "rs274 refuses it (" + canon.error + ") but MorphMill reads it"
                         : "MorphMill refuses it (" + refusal + ") but rs274 reads it";
  }
  // Every rs274 motion call is matched in order to a MorphMill move of the same line, except the
  // calls whose printed end is their printed start: MorphMill makes no move of length 0 and rs274's
  // 4 decimals hide a move shorter than its last digit, so such a call matches the next MorphMill
  // move of its line or none.
  const std::vector<morph::Move>& moves = result.path.moves;
  const auto length_of = [&](int tool) {
    const auto it = options.tools.find(tool);
    return it == options.tools.end() ? 0.0 : it->second.length_offset;
  };
  double reference = 0.0;
  if (!canon.compensated && !canon.moves.empty()) {
    const auto cutting = std::find_if(canon.moves.begin(), canon.moves.end(),
                                      [](const CanonMove& c) { return c.kind != morph::MoveKind::Rapid; });
    reference = length_of((cutting == canon.moves.end() ? canon.moves.front() : *cutting).tool);
  }
  std::size_t k = 0;
  for (std::size_t j = 0; j < canon.moves.size(); ++j) {
    CanonMove c = canon.moves[j];
    // rs274 gives the gauge line; the tip is the tool's length below it, and above it the length of
    // the tool Z was touched off with in a program that never uses G43 (docs/gcode.md).
    const double tip = reference - length_of(c.tool);
    c.end.z() += tip;
    c.center.z() += tip;
    std::string difference = k < moves.size() ? differs(moves[k], c, k) : "MorphMill has no more moves";
    if (difference.empty() && c.line != 0 && moves[k].line != c.line)
      difference = "move " + std::to_string(k) + " is on line " + std::to_string(moves[k].line) +
                   ", rs274's on line " + std::to_string(c.line);
    if (difference.empty()) {
      ++k;
      continue;
    }
    if (c.printed_still) continue;
    return difference + " (rs274 call " + std::to_string(j) + " of " + std::to_string(canon.moves.size()) +
           ")";
  }
  if (k != moves.size())
    return "MorphMill makes " + std::to_string(moves.size()) + " moves, rs274's calls match only " +
           std::to_string(k) + " of them";
  return "";
}

}  // namespace

TEST(GcodeRs274, EveryBundledProgramAgreesWithLinuxCnc) {
  if (!rs274_available())
    GTEST_SKIP() << "LinuxCNC's rs274 is not installed (Debian package linuxcnc-uspace): comparison skipped";
  std::vector<fs::path> programs;
  for (const auto& entry : fs::recursive_directory_iterator(MORPHMILL_TEST_DATA)) {
    const std::string ext = entry.path().extension().string();
    if (entry.is_regular_file() && (ext == ".ngc" || ext == ".nc")) programs.push_back(entry.path());
  }
  std::sort(programs.begin(), programs.end());
  int agree = 0, ended = 0;
  for (const fs::path& program : programs) {
    bool end_appended = false;
    const std::string difference = compare(program, &end_appended);
    ended += end_appended;
    if (difference.empty())
      ++agree;
    else
      ADD_FAILURE() << program.string() << ": " << difference;
  }
  std::cout << "rs274 comparison: " << agree << " of " << programs.size() << " programs under data/ agree ("
            << ended << " without a program end, which rs274 ran with M2 appended)\n";
  EXPECT_FALSE(programs.empty());
}

/// Measures agreement on any folder of programs (not run by default): set
/// MORPHMILL_RS274_DIR=/usr/share/linuxcnc/ncfiles and run with --gtest_also_run_disabled_tests.
TEST(GcodeRs274, DISABLED_AgreementOnAFolder) {
  const char* dir = std::getenv("MORPHMILL_RS274_DIR");
  if (!rs274_available() || !dir) GTEST_SKIP() << "needs rs274 and MORPHMILL_RS274_DIR";
  std::vector<fs::path> programs;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.path().extension() == ".ngc" || entry.path().extension() == ".nc")
      programs.push_back(entry.path());
  std::sort(programs.begin(), programs.end());
  int agree = 0;
  for (const fs::path& program : programs) {
    bool end_appended = false;
    const std::string difference = compare(program, &end_appended);
    if (difference.empty())
      ++agree;
    else
      std::cout << program.filename().string() << ": " << difference << "\n";
    if (end_appended)
      std::cout << program.filename().string() << ": no program end (rs274 ran it with M2 appended)"
                << (difference.empty() ? ", agrees" : "") << "\n";
  }
  std::cout << "rs274 comparison: " << agree << " of " << programs.size() << " programs in " << dir
            << " agree\n";
}
