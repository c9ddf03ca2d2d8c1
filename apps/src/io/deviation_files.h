// SPDX-License-Identifier: Apache-2.0
#pragma once
// A deviation field on a surface written for the tools people open it with: a PLY that MeshLab
// (vertex `quality`), CloudCompare (`scalar_<name>` -> scalar field <name>) and any PLY reader
// (vertex colours) show as is, and a VTK XML PolyData (.vtp) for ParaView with the deviation as
// point and cell data, the move and G-code line of each face as cell data, and units and
// provenance as field data. See docs/deviation-files.md.
#include <morph/mesh.h>

#include <string>

#include "io/provenance.h"

namespace morphmill {

/// Writes `mesh` (which carries the vertex scalar `scalar` and, usually, heatmap colours) as a
/// binary PLY: the scalar as `quality` and as `scalar_<scalar>`, other scalars as they are, the
/// face tags, and the provenance (with units) as header comments. Throws morph::IoError.
void write_deviation_ply(const morph::TriangleMesh& mesh, const std::string& scalar, const std::string& path,
                         const Provenance& provenance);

/// Writes `mesh` as VTK XML PolyData: point data `scalar` (UNITS_LABEL = the provenance's units)
/// and the vertex colours as `colour`; cell data `scalar` (mean of the face's three vertices),
/// `move`, `gcode_line` and `patch_kind` when the mesh has tags; field data `units` and
/// `provenance` (one string per provenance line). Numbers are raw little-endian base64, so
/// positions and deviations keep double precision. Throws morph::IoError, std::invalid_argument
/// when the mesh lacks `scalar`.
void write_deviation_vtp(const morph::TriangleMesh& mesh, const std::string& scalar, const std::string& path,
                         const Provenance& provenance);

}  // namespace morphmill
