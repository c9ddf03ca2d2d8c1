// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file planar_dilation.h
/// The paper's two-dimensional dilation of a trajectory by a disc (section 3, figures 9-11),
/// exact: each move of the tool centre (a segment or a circular arc) is dilated into the parallels
/// of its sides (offset segments, or offset arcs at radius +- r about an arc's centre) and the
/// half circles swept at its ends, which also fill the turns between moves. Moves come from a
/// G-code program or a job by projecting onto the XY plane.
#include <morph/path.h>
#include <morph/planar_curve.h>

#include <vector>

namespace morph::planar {

/// A planar trajectory: the tool centre's moves in order, as curves with Origin::Sweep provenance
/// (source = global move index, line = G-code line). A zero-length segment is a plunge: a disc.
using Trajectory = std::vector<Curve>;

/// Exact distance from p to the move (segment or arc).
double distance_to_move(const Curve& move, const Vec2& p);

/// Appends the curves that bound the move's dilation by a disc of `radius` (> 0): for a segment
/// the two parallels and the two half circles at its ends (a full circle for a zero-length move);
/// for an arc the offset arcs at radius +- `radius` (the inner one only while it exists) and the
/// half circles at its ends. Every point of the dilation's boundary lies on one of them; the
/// union's boundary is found by trimming them against each other. Each carries move.from.
void dilation_boundary(const Curve& move, double radius, std::vector<Curve>& out);

/// Bounds of the move's dilation.
Box2 dilation_bounds(const Curve& move, double radius);

/// The XY motion of `moves` (global move indices are their positions) that lies at or below
/// `cutting_height`: straight moves and helices/arcs about +-z are clipped to that height and
/// projected; rapids count too (they cut). Throws InputError for an arc about another axis, naming
/// the move and its line.
Trajectory planar_trajectory(const std::vector<const Move*>& moves, double cutting_height);

}  // namespace morph::planar
