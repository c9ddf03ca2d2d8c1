// SPDX-License-Identifier: Apache-2.0
#pragma once
// The G-code interpreter's state and stages. One Interpreter reads one program:
//   gcode.cpp          the line loop: program end, '%', O-word control flow, block order
//   gcode_modal.cpp    G and M codes that set modes, coordinate systems, offsets and tools
//   gcode_motion.cpp   straight moves, arcs, G28/G30, G53, and emitting moves
//   gcode_cycles.cpp   canned cycles expanded into their moves
// Positions are kept in job units as "machine position less the tool length offset": the
// program's coordinates plus the work (G54..) and G92/G52 offsets, as LinuxCNC's canon sees them.
#include <morph/gcode.h>

#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>

#include "gcode/gcode_block.h"
#include "gcode/gcode_parameters.h"
#include "gcode/gcode_program.h"

namespace morph::gcode {

enum class Plane { XY, XZ, YZ };

/// The arc plane as the RS-274 (first, second) axis pair and the normal (G18 is (Z, X), +Y).
struct PlaneAxes {
  int first, second, normal;
  const char* code;
};
PlaneAxes axes_of(Plane plane);

/// Synchronized: G33, a straight feed locked to the spindle (its path is a straight line).
enum class Motion { None, Rapid, Linear, ArcClockwise, ArcCounterClockwise, Synchronized, Cycle };
enum class FeedMode { PerMinute, InverseTime, PerRevolution };

constexpr char kAxisLetters[3] = {'x', 'y', 'z'};
constexpr char kOffsetLetters[3] = {'i', 'j', 'k'};
constexpr std::uint32_t kAxisBits = bit('x') | bit('y') | bit('z');

/// The G codes of one line sorted into LinuxCNC's modal groups (-1: none on the line).
struct LineCodes {
  int non_modal = -1;  ///< group 0: G4, G10, G28, G28.1, G30, G30.1, G52, G92, G92.x
  bool g53 = false;
  int motion = -1, plane = -1, distance = -1, arc_distance = -1, feed_mode = -1, units = -1;
  int cutter = -1, length = -1, retract = -1, system = -1, path = -1;
};

class Interpreter {
 public:
  Interpreter(const std::string& name, const GcodeOptions& options);
  GcodeResult run(std::string_view text);

 private:
  // ---- gcode.cpp: the line loop and block order ----
  void execute_line(std::string_view line);
  void execute_o_word(std::size_t k);
  void execute_block();
  void jump_to(std::size_t k, bool past);
  void count_words();
  void warn(std::string message);
  std::optional<double> live_parameter(int number, std::string_view name) const;

  // ---- gcode_modal.cpp ----
  LineCodes sort_g_codes();
  void execute_m_codes(bool& stop);
  void select_and_change_tools();
  void set_units(Units units);
  void set_length_offset(int code10);
  void select_system(int index);
  void set_offsets(int code10);
  void set_tool_table();
  void set_work_offsets(int l);
  void update_tip_shift();
  void settle_touch_off();
  double length_of(int tool, const char* word) const;
  struct ModalState {
    Units units;
    bool incremental, incremental_centre;
    Plane plane;
    FeedMode feed_mode;
    double feed, spindle;
    int spindle_direction;
    bool mist, flood;
    int system;
    bool retract_to_r;
    bool restore_on_return;  ///< M73
  };
  void modal_state(int m);
  void restore(const ModalState& state);
  std::vector<std::optional<ModalState>> saved_;  ///< per call level

  // ---- gcode_motion.cpp ----
  Eigen::Vector3d target(std::array<bool, 3>& known_after, bool machine) const;
  Eigen::Vector3d polar_target(std::array<bool, 3>& known_after, bool machine) const;
  void straight(MoveKind kind, bool machine);
  void arc(bool clockwise);
  void go_home(int code10);
  void store_home(int code10);
  void move_to(MoveKind kind, const Eigen::Vector3d& end, const std::array<bool, 3>& known_after);
  void emit(Move move);
  Move make_move(MoveKind kind, const Eigen::Vector3d& end) const;
  void require_feed(const char* what);
  void note_missing_units();
  bool all_known() const { return known_[0] && known_[1] && known_[2]; }
  double program_coordinate(int axis) const;

  // ---- gcode_cycles.cpp ----
  void canned_cycle();

  // ---- state ----
  const std::string& name_;
  const GcodeOptions& options_;
  GcodeResult result_;
  Parameters parameters_;
  BlockReader reader_;
  Block block_;
  std::uint32_t used_ = 0;  ///< letters of the current block that a code consumed
  int line_ = 0;
  std::string_view text_;
  const ProgramIndex* index_ = nullptr;

  // Line loop and control flow.
  std::size_t pos_offset_ = 0;  ///< byte offset of the next line
  int next_line_ = 1;
  std::size_t next_o_ = 0;  ///< index of the next O-line at or after pos_offset_
  struct Call {
    std::size_t return_offset;
    int return_line;
    std::size_t loops;  ///< loop stack depth at the call
  };
  struct Loop {
    std::size_t start;  ///< O-line index of while/do/repeat
    std::size_t iterations = 0;
    long remaining = 0;  ///< repeat only
  };
  std::vector<Call> calls_;
  std::vector<Loop> loops_;
  std::size_t blocks_repeated_ = 0;  ///< lines run again by control flow
  int furthest_line_ = 0;            ///< the furthest line run so far
  bool returned_value_ = false;      ///< #<_value_returned>
  double return_value_ = 0.0;        ///< #<_value>
  bool ended_ = false;
  int ended_after_line_ = 0;
  std::string end_code_;

  // Machine state, lengths in job units.
  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();  ///< machine position less tool length offset
  std::array<bool, 3> known_{false, false, false};
  Eigen::Vector3d work_offset_ = Eigen::Vector3d::Zero();    ///< G54..G59.3 in effect
  Eigen::Vector3d axis_offset_ = Eigen::Vector3d::Zero();    ///< G92/G52 in effect
  Eigen::Vector3d length_offset_ = Eigen::Vector3d::Zero();  ///< G43.. in effect
  Eigen::Vector3d tip_shift_ = Eigen::Vector3d::Zero();      ///< tip = position_ + this
  int system_ = 1;
  std::array<bool, 2> home_known_{false, false};  ///< G28, G30 stored positions given
  std::map<int, GcodeTool> table_;                ///< the controller's table (G10 L1 edits it)
  double physical_length_ = 0.0;                  ///< the tool table's length of the tool in the spindle
  bool length_compensation_used_ = false;         ///< a G43, G43.1 or G43.2 ran
  /// Where a tool began to move with no length offset in effect (settle_touch_off warns).
  struct UncompensatedTool {
    int line, tool;
    double length;
  };
  std::vector<UncompensatedTool> uncompensated_;

  Motion motion_ = Motion::None;
  int cycle_code_ = 0;
  int previous_cycle_ = 0;  ///< the cycle in effect before this line (0: none)
  Plane plane_ = Plane::XY;
  Units program_units_ = Units::Millimetre;
  double scale_ = 1.0;  ///< job units per program unit
  struct {
    double radius_mismatch, radius_mismatch_min, radius_reach;
  } tolerances_{};
  bool units_declared_ = false, units_warned_ = false;
  bool incremental_ = false;
  bool incremental_centre_ = true;  // G91.1 is the RS-274/NGC default
  FeedMode feed_mode_ = FeedMode::PerMinute;
  bool feed_mode_warned_ = false;
  bool feed_missing_warned_ = false;
  double feed_program_ = 0.0;  ///< F in program units per minute
  double spindle_ = 0.0;
  int spindle_direction_ = 0;  ///< 1 clockwise, -1 counter-clockwise, 0 stopped
  bool coolant_mist_ = false, coolant_flood_ = false;
  int current_tool_ = 0;
  std::optional<int> selected_tool_;
  int selected_line_ = 0;
  bool selection_reached_spindle_ = true;
  bool retract_to_r_ = false;  ///< G99 (else G98: back to the initial level)

  // Canned-cycle memory (program units, as LinuxCNC keeps it).
  double cycle_r_ = 0.0, cycle_depth_ = 0.0, cycle_p_ = 0.0, cycle_q_ = 0.0;
  double cycle_i_ = 0.0, cycle_j_ = 0.0, cycle_k_ = 0.0;
  bool cycle_initial_set_ = false;
  double cycle_initial_ = 0.0;  ///< the initial level (G98), program units

  std::array<int, 26> letter_counts_{};
  std::unordered_map<int, int> g_counts_, m_counts_;
};

}  // namespace morph::gcode
