// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file heatmap.h
/// Colour maps for per-vertex scalars: viridis (perceptually uniform, for unsigned values) and
/// a diverging blue-white-red map (Moreland's cool-warm, for signed values).
#include <morph/mesh.h>

#include <string>
#include <vector>

namespace raytest {

enum class ColorMap { Viridis, CoolWarm };

/// Closed range of values mapped to the colour map's ends.
struct ScalarRange {
  double low = 0;
  double high = 1;
};

/// Colour of t in [0, 1] (clamped; NaN gives mid grey).
morph::Color map_color(ColorMap map, double t);

/// Colour of `value` with `range` mapped to [0, 1] (a degenerate range maps everything to 0.5).
morph::Color map_value(ColorMap map, const ScalarRange& range, double value);

/// [min, max] of the finite values; with `symmetric`, [-m, m] with m = max |value|.
/// Returns [0, 1] when there is no finite value.
ScalarRange auto_range(const std::vector<double>& values, bool symmetric);

/// Stores `values` as the vertex scalar `name` (replacing one of that name) and sets the vertex
/// colours from `map` over `range`. Throws morph::InputError if the count does not match.
void apply_heatmap(morph::TriangleMesh& mesh, const std::string& name, const std::vector<double>& values,
                   ColorMap map, const ScalarRange& range);

}  // namespace raytest
