// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file planar_deviation.h
/// The deviation between two planar results (for example the exact erosion and a polygon
/// reference): for points along each boundary curve of one, the exact distance to the other's
/// boundary (segments and arcs), signed positive where the point lies outside the other region.
/// Both directions are measured. On every curve the distance is sampled at `spacing` and its
/// largest magnitude refined by golden-section search, so maxima between samples are found to
/// rounding.
#include <morph/parallel.h>
#include <morph/planar_region.h>

#include <vector>

namespace morph::planar {

struct DeviationOptions {
  /// Distance between samples along a curve, job units; 0 uses 1/2000 of the larger extent.
  double spacing = 0.0;
  ExecutionPolicy policy = ExecutionPolicy::Parallel;
};

/// One measured point on a boundary curve of the measured region.
struct DeviationSample {
  Vec2 point;
  double distance = 0.0;  ///< signed: positive outside the other region, job units
  Provenance from;        ///< the measured curve's provenance
};

/// Distances from one region's boundary to the other's.
struct DirectedDeviation {
  double max_outside = 0.0;  ///< largest positive distance (boundary outside the other region)
  double max_inside = 0.0;   ///< largest magnitude of a negative distance
  double mean_abs = 0.0;     ///< mean |distance| over the samples (length-weighted)
  DeviationSample worst;     ///< where |distance| is largest
  std::vector<DeviationSample> samples;
  double max_abs() const { return max_outside > max_inside ? max_outside : max_inside; }
};

struct PlanarDeviation {
  DirectedDeviation a_to_b;  ///< from the first region's boundary to the second's
  DirectedDeviation b_to_a;
  /// The Hausdorff distance between the two boundaries.
  double hausdorff() const {
    return a_to_b.max_abs() > b_to_a.max_abs() ? a_to_b.max_abs() : b_to_a.max_abs();
  }
};

/// Measures both directions. An empty region against a non-empty one gives +infinity.
PlanarDeviation planar_deviation(const Region& a, const Region& b, const DeviationOptions& options = {});

}  // namespace morph::planar
