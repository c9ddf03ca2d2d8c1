// SPDX-License-Identifier: Apache-2.0
#include "generator/tool_facet_groups.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace morph {

ToolFacetGroups::ToolFacetGroups(const ConvexPolytope& tool) {
  // A cube map of the normals: the dominant axis and its sign, then a grid of `cells` × `cells`
  // on the other two coordinates divided by the dominant one (each in [-1, 1]).
  const std::size_t facets = tool.facets.size();
  const int cells = std::max(1, static_cast<int>(std::lround(std::sqrt(static_cast<double>(facets) / 96.0))));
  std::map<int, std::vector<int>> by_cell;
  for (std::size_t k = 0; k < facets; ++k) {
    const Eigen::Vector3d& n = tool.facets[k].normal;
    int axis = 0;
    n.cwiseAbs().maxCoeff(&axis);
    const double d = std::fabs(n[axis]);
    auto bin = [&](int i) {
      const double t = d > 0.0 ? n[(axis + i) % 3] / d : 0.0;
      return std::clamp(static_cast<int>(std::floor((t + 1.0) * 0.5 * cells)), 0, cells - 1);
    };
    const int face = 2 * axis + (n[axis] < 0.0 ? 1 : 0);
    by_cell[(face * cells + bin(1)) * cells + bin(2)].push_back(static_cast<int>(k));
    max_norm_ = std::max(max_norm_, n.norm());
    max_offset_ = std::max(max_offset_, std::fabs(tool.facets[k].offset));
  }
  for (const auto& [cell, members] : by_cell) {
    Group g;
    g.begin = members_.size();
    Eigen::Vector3d mean = Eigen::Vector3d::Zero(), reference = Eigen::Vector3d::Zero();
    for (int k : members) {
      const PolytopeFacet& f = tool.facets[k];
      mean += f.normal;
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (int v : f.loop) centre += tool.vertices[v];
      reference += centre / static_cast<double>(std::max<std::size_t>(1, f.loop.size()));
      members_.push_back(k);
    }
    g.end = members_.size();
    g.mean = mean.norm() > 0.0 ? Eigen::Vector3d(mean.normalized()) : Eigen::Vector3d::Zero();
    g.reference = reference / static_cast<double>(members.size());
    g.excess = -std::numeric_limits<double>::infinity();
    double spread_of_normals = 0.0;
    for (int k : members) {
      const PolytopeFacet& f = tool.facets[k];
      spread_of_normals = std::max(spread_of_normals, (f.normal - g.mean).norm());
      g.excess = std::max(g.excess, f.normal.dot(g.reference) - f.offset);
    }
    // The spread and excess are rounded too: a little more than they are, never less.
    const double spread = spread_of_normals * (1.0 + 1e-12) + 1e-15;
    g.spread_squared = spread * spread * (1.0 + 1e-12);
    g.excess += 1e-12 * (1.0 + std::max(1.0, max_norm_) * g.reference.norm() + max_offset_);
    groups_.push_back(g);
  }
}

}  // namespace morph
