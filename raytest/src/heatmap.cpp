// SPDX-License-Identifier: Apache-2.0
#include <morph/exceptions.h>
#include <raytest/heatmap.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace raytest {

namespace {

using Anchor = std::array<double, 3>;

// viridis sampled at 9 evenly spaced points (matplotlib's map, as in R's viridisLite::viridis(9)).
constexpr std::array<Anchor, 9> kViridis{{{68, 1, 84},
                                          {71, 45, 123},
                                          {59, 82, 139},
                                          {44, 114, 142},
                                          {33, 145, 140},
                                          {40, 174, 128},
                                          {94, 201, 98},
                                          {173, 220, 48},
                                          {253, 231, 37}}};

// Moreland's diverging cool-warm map (2009) sampled at 9 evenly spaced points; neutral grey at 0.5.
constexpr std::array<Anchor, 9> kCoolWarm{{{59, 76, 192},
                                           {98, 130, 234},
                                           {141, 176, 254},
                                           {184, 208, 249},
                                           {221, 221, 221},
                                           {245, 196, 173},
                                           {244, 154, 123},
                                           {222, 96, 77},
                                           {180, 4, 38}}};

morph::Color interpolate(const std::array<Anchor, 9>& table, double t) {
  const double x = std::clamp(t, 0.0, 1.0) * (table.size() - 1);
  const auto i = std::min<std::size_t>(static_cast<std::size_t>(x), table.size() - 2);
  const double f = x - static_cast<double>(i);
  morph::Color c;
  for (int k = 0; k < 3; ++k)
    c[k] = static_cast<std::uint8_t>(std::lround((1 - f) * table[i][k] + f * table[i + 1][k]));
  return c;
}

}  // namespace

morph::Color map_color(ColorMap map, double t) {
  if (std::isnan(t)) return {128, 128, 128};
  return interpolate(map == ColorMap::Viridis ? kViridis : kCoolWarm, t);
}

morph::Color map_value(ColorMap map, const ScalarRange& range, double value) {
  if (std::isnan(value)) return map_color(map, value);
  const double span = range.high - range.low;
  return map_color(map, span > 0 ? (value - range.low) / span : 0.5);
}

ScalarRange auto_range(const std::vector<double>& values, bool symmetric) {
  double low = std::numeric_limits<double>::infinity(), high = -low;
  for (double v : values)
    if (std::isfinite(v)) {
      low = std::min(low, v);
      high = std::max(high, v);
    }
  if (low > high) return {0, 1};
  if (symmetric) {
    const double m = std::max(std::abs(low), std::abs(high));
    return {-m, m};
  }
  return {low, high};
}

void apply_heatmap(morph::TriangleMesh& mesh, const std::string& name, const std::vector<double>& values,
                   ColorMap map, const ScalarRange& range) {
  if (values.size() != mesh.vertices.size())
    throw morph::InputError("apply_heatmap: " + std::to_string(values.size()) + " values for " +
                            std::to_string(mesh.vertices.size()) + " vertices");
  auto existing = std::find_if(mesh.scalars.begin(), mesh.scalars.end(),
                               [&](const morph::VertexScalar& s) { return s.name == name; });
  if (existing != mesh.scalars.end())
    existing->values = values;
  else
    mesh.scalars.push_back({name, values});
  mesh.colors.resize(values.size());
  for (std::size_t v = 0; v < values.size(); ++v) mesh.colors[v] = map_value(map, range, values[v]);
}

}  // namespace raytest
