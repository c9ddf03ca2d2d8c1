// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file reference.h
/// The OpenVDB level-set reference of a job's erosion X \ (T (+) B): an independent computation
/// that shares only the job model and the exact per-move sweep distance with `morph`.
///
/// Pipeline (one voxel size per call): stock narrow-band level set (box and cylinder sampled from
/// their exact signed distance, mesh stock through OpenVDB's mesh-to-volume), swept-tool level set
/// (exact per-move sweep distance evaluated only in the leaf nodes near each move, unioned by
/// minimum; arcs and helices as chords within 0.01 voxel of the curve), level-set CSG difference,
/// rebuild to a clean signed distance (as OpenVDB's levelSetRebuild, but keeping internal voids),
/// volume-to-mesh, and segmentation into pieces measured by OpenVDB's level-set measures.
///
/// Accuracy: smooth parts of the surface are within a small fraction of a voxel of the exact one;
/// sharp edges (box edges, groove rims) are cut by about one voxel, as by any dual contouring, so
/// areas converge linearly in the voxel size (about -0.7 voxel of area per unit of sharp edge
/// length) and volumes quadratically. See docs/design/reference.md.
///
/// No OpenVDB type appears in this header: OpenVDB is private to the vdb_ref library.
#include <morph/job.h>
#include <morph/mesh.h>
#include <morph/progress.h>

#include <Eigen/Geometry>
#include <cstddef>
#include <string>
#include <vector>

namespace vdb_ref {

/// How to compute the reference.
struct ReferenceOptions {
  /// Edge of a cubic voxel, job units. Must be finite and > 0.
  double voxel_size = 0.0;
  /// Half width of the narrow band, in voxels (OpenVDB's level-set tools want >= 3).
  double half_width_voxels = 3.0;
  /// Largest memory the computation may use, bytes. The need is estimated from the stock and
  /// swept surface areas before anything is computed (see estimate_reference_memory); a larger
  /// estimate throws morph::LimitError.
  std::size_t memory_cap_bytes = std::size_t(8) << 30;
  /// Use TBB threads. The result is identical either way. false limits TBB to one thread (a
  /// tbb::global_control, so process-wide) for the duration of the call.
  bool threaded = true;
  /// Receives begin/advance/end per stage ("stock", "sweep culling", "sweep sampling",
  /// "difference", "mesh", "segment") and is polled for interruption (then morph::Interrupted is
  /// thrown). May be nullptr.
  morph::Progress* progress = nullptr;
  /// If not empty, the erosion level set is also written there as an OpenVDB file (one float
  /// grid named "erosion", class level set). Throws morph::IoError if it cannot be written.
  std::string vdb_output_path;
  /// Written with the grid as string metadata (name, value), e.g. units and provenance. The grid
  /// always carries "units" (the job's), "voxel_size" (job units) and "job" (its name) as well.
  std::vector<std::pair<std::string, std::string>> vdb_metadata;
};

/// One connected solid piece of the result (with its internal cavities, if any).
struct ReferencePiece {
  double volume = 0.0;  ///< job units cubed, OpenVDB level-set measure
  double area = 0.0;    ///< job units squared, including cavity walls
  /// Bounds of the piece's voxels on or inside its surface (job units): within one voxel of the
  /// bounds of the piece's surface.
  Eigen::AlignedBox3d bounds;
  int cavities = 0;  ///< closed internal voids (their walls count in `area`)
};

/// Size and cost of one computation.
struct ReferenceStats {
  double voxel_size = 0.0;                 ///< job units
  double half_width_voxels = 0.0;          ///< narrow band half width, voxels
  std::size_t active_voxels = 0;           ///< active voxels of the final erosion level set
  std::size_t estimated_bytes = 0;         ///< the up-front estimate checked against the cap
  std::size_t memory_bytes = 0;            ///< largest sum of grid and buffer sizes alive at once
  std::size_t sweep_leaf_evaluations = 0;  ///< (leaf node, straight move piece) pairs sampled
  double stock_seconds = 0.0;              ///< stock level set
  double sweep_seconds = 0.0;              ///< swept tool level set
  double difference_seconds = 0.0;         ///< CSG difference and rebuild
  double mesh_seconds = 0.0;               ///< volume to mesh and face provenance
  double segment_seconds = 0.0;            ///< segmentation and measures
  double total_seconds = 0.0;
};

/// The reference surface and its measures.
struct ReferenceResult {
  /// Closed triangle mesh of the erosion's boundary, outward winding. Every face is tagged
  /// PatchKind::Reference with source = nearest move (global index; of moves whose distances
  /// tie within 1e-9 units, as consecutive moves do where they meet, the earliest) and line = its
  /// G-code line when the face centroid lies on a sweep (|sweep distance| <= |stock distance|),
  /// else source = -1 and line = 0 (a stock face).
  morph::TriangleMesh mesh;
  /// Connected solid pieces, largest volume first (ties broken by bounds), deterministic.
  std::vector<ReferencePiece> pieces;
  ReferenceStats stats;

  /// Sum of the piece volumes and areas.
  double volume() const;
  double area() const;
};

/// Checks the job and options and returns the estimated peak memory in bytes, without
/// computing anything long. Throws morph::InputError for a voxel size that is not finite and
/// positive, a half width below 1, an unsupported tool (naming it), a non-closed stock mesh (naming
/// its file); morph::LimitError when the estimate exceeds options.memory_cap_bytes.
std::size_t estimate_reference_memory(const morph::Job& job, const ReferenceOptions& options);

/// Computes the reference for one voxel size. Validates first (as estimate_reference_memory).
/// Throws morph::Interrupted if the progress asks to stop, morph::IoError if the VDB file cannot be
/// written.
ReferenceResult compute_reference(const morph::Job& job, const ReferenceOptions& options);

/// The grids of an OpenVDB file (as written by compute_reference) with their string metadata
/// (OpenVDB's own entries, e.g. "class", included). Throws morph::IoError naming the file when
/// it cannot be read.
struct GridMetadata {
  std::string grid_name;
  std::vector<std::pair<std::string, std::string>> entries;  ///< string-valued metadata, sorted by name
};
std::vector<GridMetadata> read_grid_metadata(const std::string& path);

/// "ref.ply" with voxel 0.4 -> "ref_v0.4.ply" (shortest decimal form of the voxel size; the
/// suffix goes before the last extension, or at the end if there is none).
std::string path_with_voxel_suffix(const std::string& path, double voxel_size);

/// Parses "0.4,0.2,0.1" into voxel sizes; throws morph::InputError naming `what` for an empty
/// list, a non-number, or a value that is not finite and positive.
std::vector<double> parse_voxel_sizes(const std::string& text, const std::string& what);

}  // namespace vdb_ref
