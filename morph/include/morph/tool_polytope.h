// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file tool_polytope.h
/// The generator's tool: a convex polytope within a given Hausdorff distance of the exact tool of
/// revolution (tool_profile.h), built once per tool and translated along the path.
///
/// The meridian profile is replaced by a polygon whose chords keep within the budget (arcs and
/// ellipses subdivided, lines kept whole), revolved into rings of one common set of angles
/// 2πk/N anchored to the global frame (so every placement of the tool has parallel facets).
/// Such a ring set has known facets: between consecutive rings, one planar trapezoid per sector
/// (the profile is convex, so they are the hull's facets), flat N-gons or apex fans at the ends.
/// A pole (an arc or ellipse meeting the axis level: a ball's tip, a sphere's top) is cut off
/// by a level chord where the piece bulges beyond it by one chord's sagitta, so its end is a flat
/// N-gon too, not an apex: two passes at one depth share that facet's exact plane, where two fans
/// of nearly level facets about apexes a hair apart would cut a cloud of distinct exact points.
/// A cone's apex stays an apex (its facets are steep).
/// The inscribed polytope lies inside the tool; it is pushed out by half its own sagitta (each
/// chord's line offset by half the chord's sagitta, ring radii scaled by 2 / (1 + cos(π/N))), so
/// it straddles the exact surface and its error is about half the sagitta both ways. The
/// meridian's and the rings' sagittas share the budget, half each.
/// The vertices are then moved onto a power-of-two grid (quantize.h) with the rings kept
/// homothetic, so every facet is exactly planar on it; that moves the surface by at most an
/// eighth of the budget more.
#include <morph/convex_polytope.h>
#include <morph/tool_profile.h>

#include <Eigen/Core>
#include <vector>

namespace morph {

struct ToolPolytope {
  /// The polytope with the tool point at the origin (tool axis +z).
  ConvexPolytope polytope;
  int sectors = 0;  ///< N: vertices per ring
  /// Every vertex lies on the grid of this exponent (quantize.h) and every facet carries its
  /// exact plane there: rings homothetic about the axis, of one set of integer directions.
  int grid_exponent = 0;
  /// The straddling meridian polygon (r, z above the tool point), from the axis at the bottom
  /// to the axis at the top, before the rings' radial scaling.
  std::vector<Eigen::Vector2d> meridian;
};

/// The size of tool_polytope(profile, max_deviation) without building it, for the memory
/// estimate made before anything large is built. `facets` is exact for tools with a pointed or
/// rounded end and at most 2 × sectors over for flat ends (counted as fans).
struct ToolPolytopeSize {
  std::size_t meridian_points = 0;  ///< of the straddling meridian, the axis points included
  int sectors = 0;                  ///< of every ring
  std::size_t facets = 0;
};
ToolPolytopeSize tool_polytope_size(const ToolProfile& profile, double max_deviation);

/// The tool polytope of `profile` within `max_deviation` (job units, > 0) of the exact tool
/// surface in both directions. Throws InputError for an empty profile or a deviation that is
/// not positive and finite, LimitError when it would need more than 2^16 sectors or meridian
/// points.
ToolPolytope tool_polytope(const ToolProfile& profile, double max_deviation);

}  // namespace morph
