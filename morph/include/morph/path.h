// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file path.h
/// The ordered trajectory model: moves that keep their kind and source line.
#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace morph {

enum class MoveKind : std::uint8_t {
  Rapid = 0,   ///< G0: still removes material if it passes through the stock
  Linear = 1,  ///< G1 or a job polyline segment
  Arc = 2,     ///< G2/G3 arc or helix (direction in the sign of `sweep`)
};

const char* to_string(MoveKind kind);

/// One tool motion from `start` to `end`, in job units. The tool point is the tool's reference
/// point (the tip for milling tools, the centre for a sphere).
///
/// An arc turns about the unit `axis` through `center` by `sweep` radians (right-handed: positive
/// is counter-clockwise seen from the tip of `axis`; |sweep| may exceed 2*pi for multi-turn
/// helices). `center` lies in the plane through `start` normal to `axis`. The radius goes linearly
/// from |start - center| to the end's radial distance, and the axial component linearly from 0 to
/// (end - start).dot(axis) (a helix), so point_at(1) == end exactly.
struct Move {
  MoveKind kind = MoveKind::Linear;
  Eigen::Vector3d start = Eigen::Vector3d::Zero();
  Eigen::Vector3d end = Eigen::Vector3d::Zero();
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< arcs only
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();   ///< arcs only, unit length
  double sweep = 0.0;                                ///< arcs only, radians, signed
  int tool = 0;                                      ///< tool number in Job::tools
  int line = 0;          ///< 1-based source line (G-code line, or polyline point index + 1)
  double feed = 0.0;     ///< F word in effect, job units per minute (0 if none)
  double spindle = 0.0;  ///< S word in effect

  bool is_arc() const { return kind == MoveKind::Arc; }
};

/// Position on the move at parameter t in [0, 1].
Eigen::Vector3d point_at(const Move& move, double t);

/// point_at for many parameters of one move (the arc's frame made once): the same values, bit
/// for bit. Holds a reference to the move.
class MovePoints {
 public:
  explicit MovePoints(const Move& move);
  Eigen::Vector3d operator()(double t) const;

  /// An arc's frame: what its points share.
  struct Frame {
    Eigen::Vector3d u, v;     ///< in-plane unit vectors, v = axis x u
    double r0, r1, rise;      ///< start radius, end radius, axial travel
    Eigen::Vector3d closure;  ///< end - unclosed point at t=1, spread linearly so the point at 1 is the end
  };

 private:
  const Move& move_;
  Frame frame_{};
  Eigen::Vector3d base_ = Eigen::Vector3d::Zero();  ///< the centre moved to the start's height
};
/// Derivative of point_at with respect to t (not normalised).
Eigen::Vector3d derivative_at(const Move& move, double t);
/// Arc length of the move (exact for lines and circular arcs; helices by closed form when the
/// radius is constant, otherwise by fine quadrature).
double length(const Move& move);
/// Most chords chord_parameters gives one arc (2^24: 128 MiB of parameters).
inline constexpr std::size_t kMaxChordsPerArc = std::size_t(1) << 24;
/// How many chords keep an arc within `chord_tolerance` (1 for a line), as a double so that no
/// count overflows: a P1000000 circle at 1e-12 needs about 7e12.
double chord_count(const Move& move, double chord_tolerance);
/// Parameters 0 = t0 < t1 < ... < tn = 1 such that the chords between consecutive points stay
/// within `chord_tolerance` of the move (one segment for a line). Throws LimitError (naming the
/// move's line) past kMaxChordsPerArc.
std::vector<double> chord_parameters(const Move& move, double chord_tolerance);

/// An ordered sequence of moves done with one tool set-up, from one polyline or one G-code file.
struct Path {
  std::string source;  ///< G-code file path, or "paths[i].polyline"
  std::vector<Move> moves;
  std::string name;  ///< optional label from the job file ("paths[i].name"), "" if none
};

}  // namespace morph
