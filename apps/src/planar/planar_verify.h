// SPDX-License-Identifier: Apache-2.0
#pragma once
// morphmill verify2d: the exact planar erosion against the Clipper reference, with pictures and a
// report.
#include <morph/planar_deviation.h>
#include <morph/planar_erosion.h>
#include <morph/progress.h>
#include <morphmill/planar_io.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "io/provenance.h"

namespace morphmill {

struct Verify2dOptions {
  std::string job_path;
  std::string out_dir;
  double tolerance = 0.0;  ///< reference chord tolerance; 0 uses the job's
  morph::Progress* progress = nullptr;
};

struct ConvergenceRow {
  double chord_tolerance = 0.0;
  double hausdorff = 0.0;
  double area_difference = 0.0;  ///< reference area - exact area
  std::size_t reference_vertices = 0;
  double reference_seconds = 0.0;
};

struct Verify2dOutcome {
  PlanarJob job;
  morph::planar::PlanarResult exact;
  morph::planar::PlanarResult dilation;
  morph::planar::PlanarResult classical;
  morph::planar::Region reference;
  morph::planar::PlanarDeviation deviation;  ///< exact -> reference and back, at the tolerance
  std::vector<ConvergenceRow> convergence;   ///< tolerance x 10, 1, 1/10
  double tolerance = 0.0;
  Provenance provenance;  ///< of this run: inputs hashed, options, build
  bool pieces_match = false;
  bool within_bound = false;  ///< Hausdorff <= 2 x tolerance (see docs/planar.md)
  bool verdict() const { return pieces_match && within_bound; }
};

/// report.json's document: the areas, pieces, deviation, convergence and verdict, with format,
/// units and provenance; also what `verify2d --json` writes.
nlohmann::json verify2d_summary_json(const Verify2dOutcome& outcome);

/// Runs everything and writes out_dir/{result.svg,result.dxf,result.json,dilation.svg,classical.svg,
/// reference.svg,deviation.svg,report.json,report.md}.
Verify2dOutcome run_verify2d(const Verify2dOptions& options);

/// Heatmap: the first region's boundary coloured by |distance| to the other, over the other's outline.
void write_deviation_svg(const morph::planar::Region& measured,
                         const morph::planar::DirectedDeviation& deviation,
                         const morph::planar::Region& other, double colour_max, const std::string& title,
                         const std::string& path);

}  // namespace morphmill
