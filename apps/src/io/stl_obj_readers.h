// SPDX-License-Identifier: Apache-2.0
#pragma once
// Checked readers for STL and OBJ, from bytes already read through morph::read_regular_file.
// OpenMesh's readers cannot be made safe from outside: its STL type check loops forever on
// /dev/zero and directories, its OBJ reader aborts on `f /1` (an assertion) and opens any file an
// `mtllib` line names (/dev/zero, a FIFO). These read only what MorphMill keeps (positions and
// faces), never open another file, and bound every count by the bytes present.
#include <morph/mesh.h>

#include <string>

namespace morphmill {

/// Binary STL when the length is exactly 84 + 50 x (the header's triangle count), else ASCII STL.
/// Positions are float32, as the format defines them; coincident corners are merged (in order of
/// first appearance). Throws morph::InputError naming `name`, the line or triangle, and the problem.
morph::TriangleMesh read_stl_bytes(const std::string& data, const std::string& name);

/// `v x y z` and `f a b c ...` (with `a/t/n` forms and negative, relative indices); every other
/// statement (vn, vt, g, o, s, usemtl, mtllib, ...) is skipped without opening anything. Positions
/// are rounded to float32, as OpenMesh did. Polygons become triangle fans. Throws morph::InputError
/// naming `name`, the line and the problem.
morph::TriangleMesh read_obj_bytes(const std::string& data, const std::string& name);

}  // namespace morphmill
