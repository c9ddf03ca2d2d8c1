// SPDX-License-Identifier: Apache-2.0
#pragma once
// Jobs built in code for the vdb_ref tests and benchmarks, with their closed-form truths.
#include <morph/job.h>

#include <cmath>

namespace vdb_ref_test {

inline morph::Job box_job(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  morph::Job job;
  job.name = "test";
  job.stock.type = morph::StockType::Box;
  job.stock.box = Eigen::AlignedBox3d(lo, hi);
  return job;
}

inline void add_tool(morph::Job& job, int number, morph::ToolType type, double radius, double length = 0.0) {
  morph::Tool tool;
  tool.number = number;
  tool.type = type;
  tool.radius = radius;
  tool.length = length;
  job.tools[number] = tool;
}

inline morph::Move line(const Eigen::Vector3d& a, const Eigen::Vector3d& b, int tool, int line_number) {
  morph::Move move;
  move.kind = morph::MoveKind::Linear;
  move.start = a;
  move.end = b;
  move.tool = tool;
  move.line = line_number;
  return move;
}

inline void add_path(morph::Job& job, std::vector<morph::Move> moves) {
  morph::Path path;
  path.source = "paths[" + std::to_string(job.paths.size()) + "]";
  path.moves = std::move(moves);
  job.paths.push_back(std::move(path));
}

/// Area of the part of a disc of radius r between the chord at distance r - d from the centre
/// and the rim (a circular segment of height d, 0 <= d <= 2r).
inline double circular_segment_area(double r, double d) {
  return r * r * std::acos((r - d) / r) - (r - d) * std::sqrt(2.0 * r * d - d * d);
}

/// Arc length of that segment's rim.
inline double circular_segment_arc(double r, double d) {
  return 2.0 * r * std::acos((r - d) / r);
}

/// Integral of the chord width 2*sqrt(r^2 - u^2) over u in [u0, u1] (area of a disc slice).
inline double disc_slice_area(double r, double u0, double u1) {
  auto f = [r](double u) { return u * std::sqrt(r * r - u * u) + r * r * std::asin(u / r); };
  return f(u1) - f(u0);
}

}  // namespace vdb_ref_test
