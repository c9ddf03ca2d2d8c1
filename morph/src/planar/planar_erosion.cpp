// SPDX-License-Identifier: Apache-2.0
#include <morph/planar_erosion.h>

namespace morph::planar {

// Defined in planar_arrangement.cpp: stock \ union of the dilations, or the union if stock is null.
PlanarResult arrange(const Region* stock, const Trajectory& moves, double radius,
                     const PlanarOptions& options);

PlanarResult erode(const Region& stock, const Trajectory& moves, double radius,
                   const PlanarOptions& options) {
  return arrange(&stock, moves, radius, options);
}

PlanarResult dilate(const Trajectory& moves, double radius, const PlanarOptions& options) {
  return arrange(nullptr, moves, radius, options);
}

PlanarResult classical_erosion(const Region& stock, double radius, const PlanarOptions& options) {
  // The stock's own boundary is the trajectory: B_y lies inside X exactly when y is in X and at
  // least `radius` away from every boundary element.
  Trajectory boundary;
  std::int32_t k = 0;
  for (const Loop& loop : stock.loops)
    for (const Curve& c : loop.curves) {
      boundary.push_back(c);
      boundary.back().from = Provenance{Origin::Offset, k++, c.from.line};
    }
  return arrange(&stock, boundary, radius, options);
}

}  // namespace morph::planar
