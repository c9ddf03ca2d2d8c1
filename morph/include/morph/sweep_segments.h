// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file sweep_segments.h
/// The generator's first stage: the job's moves as the straight segments it sweeps, in job order.
/// Arcs become chords within a tolerance, every end goes to the tools' grid (quantize.h), and
/// runs that sweep one solid become one segment: a segment that continues its predecessor (same
/// tool, exactly collinear on the grid, same direction) joins it, and a segment of zero length on
/// the grid is dropped where a neighbour of its tool touches its point. Both are exact, not
/// approximations: the sweep of [a, c] is the union of the sweeps of [a, b] and [b, c] when b lies
/// on [a, c], and a tool placed at b lies in any sweep through b. A raster of 0.1 mm moves
/// (CAM output at a fine step, the hostile 10^4-move raster) then costs what its rows cost.
#include <morph/job.h>

#include <Eigen/Core>

#include <cstdint>
#include <map>
#include <vector>

namespace morph {

/// One straight sweep: from, to on the grid (job units); move and line are the job's first move
/// of the run it stands for (its index in job.moves() and its source line); tool its tool number.
struct SweepSegment {
  Eigen::Vector3d from = Eigen::Vector3d::Zero();
  Eigen::Vector3d to = Eigen::Vector3d::Zero();
  std::int32_t move = 0;
  std::int32_t line = 0;
  int tool = 0;
};

/// Whether segment `next`, starting where `previous` ends, sweeps with it the sweep of
/// [previous.from, next.to]: the same tool, `next` on the line of `previous` going on the same way
/// (decided exactly on the grid of exponent `grid_exponent`). Zero-length segments are handled by
/// sweep_segments(), not here.
bool continues_straight(const SweepSegment& previous, const SweepSegment& next, int grid_exponent);

/// The job's segments as the generator sweeps them: chords within `chord_tolerance` (job units),
/// ends snapped to the grid of exponent `grid_exponent`, straight runs joined and zero-length
/// segments dropped where a neighbour of their tool covers them (see the file comment).
std::vector<SweepSegment> sweep_segments(const Job& job, double chord_tolerance, int grid_exponent);

/// Segment ends moved within `max_shift` (job units; the error budget's `ends` share) so that
/// every sweep is built from exact planes and no move shorter than half the share is swept. A
/// point moves the same way wherever it occurs (a function of the point, not of the segment), so
/// a retrace, a closed loop or a second lap still meets its first exactly; moving each segment's
/// end by itself left laps ~1e-7 apart, and their needles for the rounding to repair.
/// - Short: a segment's end within half the share of (the image of) its start joins it, in job
///   order: a 1e-6 mm step at a turn is not swept, nor the needles between its planes and its
///   neighbours', thinner than the doubles' spacing. Measured from the job's point, so chains
///   of short moves do not add up.
/// - Long: a sweep's silhouette plane through a tool edge has the normal reduced(edge) ×
///   reduced(motion) in grid integers, exact only while it fits the predicates' 53 bits
///   (SweepPolytopeBuilder::largest_exact_step(), `largest_step` per tool). A longer move in a
///   general direction got a plane rounded to doubles that missed the tool vertices it holds by
///   construction: the vertex and that plane's corner became two points ~1e-15 apart (the
///   self-crossing stars of the stress campaign). When any segment is so, every end goes to the
///   finest power-of-two grid, coarser than the tools', on which every segment's motion divided
///   by the spacing fits its tool's limit (nothing moves when that grid's half diagonal exceeds
///   half the share). Every end, not only the long segments': a level move between a moved end
///   and one left on the finer grid became a ramp of 1e-8 beside level ones.
/// A segment left of zero length is dropped where a neighbour of its tool covers its point. A
/// tool missing from `largest_step` (or at 0) keeps its long segments as they are.
struct SettledEnds {
  std::size_t aligned = 0;    ///< points moved to the coarser grid
  std::size_t collapsed = 0;  ///< points joined to an earlier one (short segments' ends)
};
SettledEnds settle_segment_ends(std::vector<SweepSegment>& segments,
                                const std::map<int, std::int64_t>& largest_step, int grid_exponent,
                                double max_shift);

/// How many segments sweep_segments() gives of each tool (by tool number), counted without
/// listing the chords (an arc is never joined, so its chords are counted, not made): for
/// estimates made before anything large is built. Doubles, as chord_count() is.
std::map<int, double> sweep_segment_counts(const Job& job, double chord_tolerance, int grid_exponent);

}  // namespace morph
