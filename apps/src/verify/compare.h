// SPDX-License-Identifier: Apache-2.0
#pragma once
// Design comparison (`morphmill compare`, and `verify` when the job names a design): the machined
// result, i.e. the generator's exact surface, against the design model the program was written
// for. Signed (raytest::kSignConvention): + excess, material left where the design wants none;
// - gouge, material removed where the design wants it.
#include <morph/job.h>
#include <morph/mesh.h>
#include <raytest/deviation.h>
#include <raytest/regions.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace morphmill {

struct CompareOptions {
  raytest::ToleranceBand band;  ///< allowed signed deviation, job units; must not be empty
  /// Longest edge of the machined surface's refinement for per-point classification and regions,
  /// job units; 0 picks the bounding-box diagonal / 400 (and at most the band width).
  double resolution = 0.0;
  std::size_t face_samples = 100000;  ///< area-uniform samples per surface for the statistics
  std::uint64_t seed = 1;
  std::size_t max_regions = 20;  ///< regions kept (deepest first); the counts cover all
};

/// A gouge or excess region and the move that came nearest to its deepest point.
struct DesignRegion {
  raytest::DeviationRegion region;  ///< sources: the faces' provenance (the moves that made them)
  int nearest_move = -1;            ///< global move index of the sweep nearest to region.location
  int nearest_line = 0;             ///< its line (G-code line, or polyline point index + 1)
  std::string nearest_source;       ///< its path's source (G-code file or "paths[i].polyline")
  double nearest_distance = 0.0;    ///< signed distance from region.location to that sweep
};

struct DesignComparison {
  raytest::ToleranceBand band;
  double resolution = 0.0;
  std::size_t machined_triangles = 0, design_triangles = 0;
  /// Samples of the machined surface against the design, signed as above.
  raytest::DeviationStats machined_to_design;
  /// Samples of the design against the machined surface, signed as the machined surface relative
  /// to the design (a design point outside the machined solid is a gouge, so negative).
  raytest::DeviationStats design_to_machined;
  /// Per vertex of the refined machined surface (classification and regions are on these).
  raytest::DeviationStats per_point;
  std::size_t gouge_regions = 0, excess_regions = 0;
  std::vector<DesignRegion> regions;  ///< deepest first, at most CompareOptions::max_regions
  raytest::RefinedMesh refined;       ///< the refined machined surface, tagged
  std::vector<double> point_values;   ///< one per vertex of refined.mesh
  bool within_band() const { return gouge_regions == 0 && excess_regions == 0; }
};

/// Compares `machined` (the generator's surface of `job`, tagged) with `design` (a closed,
/// outward-wound mesh in job units). Throws morph::InputError for an empty band or mesh.
DesignComparison compare_with_design(const morph::Job& job, const morph::TriangleMesh& machined,
                                     const morph::TriangleMesh& design, const CompareOptions& options);

/// The band a job's design entry gives, or the default [-5, +5] x the job's tolerance.
raytest::ToleranceBand default_band(const morph::Job& job, double low, double high);

/// The comparison as JSON (docs/compare.md), without the per-point arrays.
nlohmann::json comparison_to_json(const DesignComparison& comparison, const morph::Job& job);

/// "side sweep move 3 (line 7)" and the like.
std::string provenance_text(const morph::FaceTag& tag);

}  // namespace morphmill
