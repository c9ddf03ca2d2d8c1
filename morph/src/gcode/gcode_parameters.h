// SPDX-License-Identifier: Apache-2.0
#pragma once
// The G-code reader's parameters: LinuxCNC's numbered parameters #1-#5602, named local and global
// parameters, the subroutine frames that keep #1-#30 and named locals per call, and the LinuxCNC
// var file. Values are plain doubles; lengths held here (offsets, stored positions) are in the
// job's units, which play the part of LinuxCNC's machine ("user") units.
#include <array>
#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace morph::gcode {

/// A problem in the block being read. The reader adds the file and line.
class BlockError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};
[[noreturn]] void fail(const std::string& problem);

/// Numbered parameters with a special meaning (LinuxCNC's numbering).
namespace param {
constexpr int kG28 = 5161;          ///< 5161-5163: G28 stored position, machine coordinates
constexpr int kG30 = 5181;          ///< 5181-5183: G30 stored position
constexpr int kG92Applied = 5210;   ///< 1 while G92/G52 offsets are applied
constexpr int kG92 = 5211;          ///< 5211-5213: G92/G52 offsets
constexpr int kCoordSystem = 5220;  ///< active system 1 (G54) .. 9 (G59.3)
/// First parameter (X) of coordinate system `index` 1..9: 5221, 5241, ... 5381; +9 is rotation.
constexpr int system_base(int index) {
  return 5201 + 20 * index;
}
constexpr int kLast = 5602;
}  // namespace param

class Parameters {
 public:
  /// Live values computed by the interpreter: #5400-#5428 and the predefined `_` names.
  using Live = std::function<std::optional<double>(int number, std::string_view name)>;

  explicit Parameters(Live live);

  double numbered(int number) const;
  void set_numbered(int number, double value);
  /// Named parameter (lower case, no spaces); nullopt if it does not exist in scope.
  std::optional<double> named(std::string_view name) const;
  void set_named(std::string_view name, double value);
  bool exists(std::string_view name) const { return named(name).has_value(); }

  /// A subroutine call: saves #1-#30 and starts a fresh named-local scope; `args` become #1...
  void push_call(const std::vector<double>& args);
  void pop_call();
  int call_depth() const { return static_cast<int>(frames_.size()) - 1; }

 private:
  static bool read_only(int number) { return number >= 5399 && number <= 5428; }
  struct Frame {
    std::array<double, 30> saved{};
    std::map<std::string, double, std::less<>> locals;
  };
  Live live_;
  std::vector<double> numbered_;
  std::map<std::string, double, std::less<>> globals_;
  std::vector<Frame> frames_;  // frames_[0]: the main program's named locals
};

/// Reads a LinuxCNC parameter (.var) file: lines "number value", anything after is ignored.
/// Throws IoError if unreadable and InputError naming "file:line" for a malformed line.
std::map<int, double> read_var_file(const std::string& path);

}  // namespace morph::gcode
