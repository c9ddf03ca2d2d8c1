// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file pieces.h
/// verify's piece check: whether the generator's solid pieces are the ones the voxel reference
/// and, below the voxels' resolution, the exact field find. Sizes in job units.
#include <morph/mesh.h>
#include <morph/sweep_distance.h>

#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

namespace morphmill {

/// One solid piece as a side sees it.
struct PieceRecord {
  double volume = 0.0;
  double area = 0.0;
  Eigen::AlignedBox3d bounds;
  /// The centre of its volume (generator pieces only; zero for the reference's).
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
};

/// The connected components of a closed mesh as pieces, largest volume first.
std::vector<PieceRecord> mesh_pieces(const morph::TriangleMesh& mesh);

/// Whether the generator's pieces are the reference's: as many, each (by volume, largest first)
/// within half a voxel times its area of the reference's. Failing that, pieces under (2 voxels)^3,
/// which the voxels miss, swell or cut off, are judged by the exact field: the larger ones must
/// match so; each small one of the generator's must hold material of the exact solid, the field
/// below the tolerance (holds_exact_material: a chip; else a phantom); each small one of the reference's must
/// lie within a voxel of one of those, or be material that the exact solid joins to more of itself two voxels
/// around (material_reaches_out over its bounds grown by a voxel at the tolerance's step, bridging gaps up to
/// twice the tolerance and voids where the field stays below it, a ReferencePiece's bounds being its voxels'
/// centres: a neck narrower than the voxels, which the level set cut). *below_resolution: the small pieces
/// judged so, of both sides, when that decided.
bool match_pieces(const std::vector<PieceRecord>& morph_pieces,
                  const std::vector<PieceRecord>& reference_pieces, double voxel_size, double tolerance,
                  const morph::ErosionField& field, std::size_t* below_resolution = nullptr);

/// Whether a generator's piece is material of the exact solid: the field below `within` at its
/// centroid, or failing that (a chip about the tolerance's size, its centroid shifted by its flat
/// facets) at a point of a 12^3 grid of cell centres over its bounds. `within` 0: inside the
/// exact solid; the tolerance (match_pieces): inside it or where the field stays below the
/// tolerance, as the deviation checks hold the generator.
bool holds_exact_material(const morph::ErosionField& field, const PieceRecord& piece, double within = 0.0);

/// Whether the exact solid's material in `box` reaches out of it: the points of a grid of `step`
/// over the box grown by `margin` where the field is below `within` (0: the exact solid; the
/// tolerance: the solid with the voids where the field stays below the tolerance), joined when 6-connected or
/// no farther apart than `bridge`, include some in the box (or within half a step of it: a flat box holds
/// points too) and join those to the grown box's border. False when none is material (a phantom) or when the
/// material in the box is a piece of its own there, apart from the rest by more than `bridge`. A gap narrower
/// than `step` may be bridged.
bool material_reaches_out(const morph::ErosionField& field, const Eigen::AlignedBox3d& box, double margin,
                          double step, double bridge = 0.0, double within = 0.0);

}  // namespace morphmill
