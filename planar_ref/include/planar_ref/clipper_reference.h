// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file clipper_reference.h
/// An independent reference for the planar model: the same regularized partial erosion computed
/// by a well-kept polygon library (Clipper 6, Angus Johnson, Debian's libpolyclipping-dev). Each
/// chain of connected moves is offset with round joins and round ends, the offsets are united and
/// subtracted from the stock. Arcs become chords: the result's boundary is within
/// `chord_tolerance` of the exact one (half of it for the moves' arcs, 0.45 of it for the round
/// joins and ends, all of it for the stock's arcs) plus Clipper's integer grid (1/1000 of it),
/// except where two boundaries meet at a shallow angle: there the displaced chords move the
/// meeting point along the boundary by up to the chord error over the sine of half the angle.
#include <morph/planar_dilation.h>
#include <morph/planar_region.h>

#include <cstddef>

namespace planar_ref {

struct ReferenceOptions {
  /// Largest distance between the reference's boundary and the exact one from flattening arcs,
  /// job units (> 0).
  double chord_tolerance = 0.01;
};

struct ReferenceResult {
  morph::planar::Region region;  ///< polygons (segments only), outer loops counter-clockwise
  std::size_t vertices = 0;      ///< polygon vertices of the result
  double grid = 0.0;             ///< Clipper's integer unit in job units
  double seconds = 0.0;
};

/// X \ (T (+) B) by Clipper. Throws morph::InputError for a non-positive radius or tolerance.
ReferenceResult reference_erosion(const morph::planar::Region& stock, const morph::planar::Trajectory& moves,
                                  double radius, const ReferenceOptions& options = {});

/// T (+) B by Clipper.
ReferenceResult reference_dilation(const morph::planar::Trajectory& moves, double radius,
                                   const ReferenceOptions& options = {});

}  // namespace planar_ref
