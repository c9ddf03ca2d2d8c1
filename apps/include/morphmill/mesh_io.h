// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file mesh_io.h
/// Mesh files: binary/ASCII PLY (face tags, vertex scalars and colours kept), STL (binary and
/// ASCII), OBJ. The format follows the file extension. Reading accepts regular files only;
/// writing replaces the file atomically (see morph/file_io.h).
#include <morph/mesh.h>

#include <string>

namespace morphmill {

/// Reads a triangle mesh; polygons are split into triangles. PLY face properties
/// `patch_kind`, `source`, `line` become FaceTags; float/double vertex properties other than
/// x,y,z,nx,ny,nz become VertexScalars; red/green/blue become colours. Coincident vertices of
/// STL files are merged. Throws morph::IoError (cannot open) or morph::InputError (naming the
/// file and what is wrong).
morph::TriangleMesh read_mesh(const std::string& path);

/// The same from bytes already in memory; `name` chooses the format by its extension and names
/// the source in messages.
morph::TriangleMesh read_mesh_bytes(const std::string& data, const std::string& name);

struct MeshWriteOptions {
  bool binary = true;  ///< PLY and STL: binary (default) or ASCII
};

/// Writes a mesh, keeping tags (PLY face properties patch_kind, source, line), scalars and
/// colours where the format can hold them; `comments` (units, provenance; one line each, no line
/// breaks) go into a PLY header, other formats leave them out. Throws morph::IoError on failure.
void write_mesh(const morph::TriangleMesh& mesh, const std::string& path,
                const MeshWriteOptions& options = {}, const std::vector<std::string>& comments = {});

}  // namespace morphmill
