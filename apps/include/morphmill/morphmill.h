// SPDX-License-Identifier: Apache-2.0
#pragma once
/// \file morphmill.h
/// MorphMill's public C++ API: what the `morphmill` command line does, as functions, for programs
/// and scripts (the Python module `morphmill` wraps exactly these).
///
/// \code
///   const morph::Job job = morphmill::load_job("data/jobs/single_slot.json");
///   const morphmill::ErodeReport part = morphmill::erode(job);          // exact generator
///   const vdb_ref::ReferenceResult ref = morphmill::reference(job);     // OpenVDB reference
///   const raytest::TwoSidedDeviation d = morphmill::deviation(part.mesh, ref.mesh);
///   const morphmill::VerifyReport v = morphmill::verify(job);           // all three + verdict
/// \endcode
///
/// Lengths are in the job's units (Job::units: millimetres or inches) throughout; volumes in those
/// units cubed. Nothing here prints or exits: errors are exceptions derived from the standard ones
/// (morph/exceptions.h): morph::InputError for bad input (the message names the file and the
/// line or JSON path), morph::IoError for files that cannot be read or written, morph::LimitError
/// for work over a memory cap, morph::Interrupted when a Progress asks to stop.
///
/// Also part of the API, declared in the headers included here: load_job (job files and CAMotics
/// projects, morphmill/job_io.h), read_mesh / write_mesh (PLY, STL, OBJ, morphmill/mesh_io.h),
/// morph::topology_report (morph/topology.h) and the types of the results (morph/mesh.h,
/// vdb_ref/reference.h, raytest/deviation.h). CMake: find_package(MorphMill), target
/// MorphMill::morphmill.
#include <morph/erode.h>
#include <morph/job.h>
#include <morph/mesh.h>
#include <morph/progress.h>
#include <morph/topology.h>
#include <morphmill/job_io.h>
#include <morphmill/mesh_io.h>
#include <raytest/deviation.h>
#include <vdb_ref/reference.h>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>

namespace morphmill {

/// MorphMill's version, as `morphmill --version` prints it ("0.1.0").
std::string version();

/// How to run the generator (`morphmill erode`).
struct ErodeSettings {
  /// Largest distance of the surface from the exact boundary, job units; 0 uses the job's tolerance.
  double tolerance = 0.0;
  /// Refuse (morph::LimitError, before the long work) a job estimated to need more memory than
  /// this, bytes; 0: no cap.
  std::size_t memory_cap_bytes = 0;
  morph::Progress* progress = nullptr;  ///< optional progress and interruption
};

/// The generator's surface and what `morphmill erode` checks about it.
struct ErodeReport {
  morph::TriangleMesh mesh;            ///< job units, wound outward, every face tagged (FaceTag)
  morph::ErodeStats stats;             ///< sizes and timings (seconds)
  morph::TopologyReport topology;      ///< closed? manifold? pieces, area, volume
  std::size_t self_intersections = 0;  ///< triangle pairs that intersect (exact predicates)
  /// What erode promises: a closed, oriented 2-manifold free of self-intersections.
  bool valid() const { return topology.closed_manifold() && self_intersections == 0; }
};

/// The boundary of what the tool leaves of the stock (morph::erode: every tool of revolution,
/// every stock), checked as `morphmill erode` checks it.
ErodeReport erode(const morph::Job& job, const ErodeSettings& settings = {});

/// The reference voxel size `verify` and `study` pick when none is given: a sixth of the smallest
/// tool radius, larger when the stock is so big that the reference would not fit in memory.
double default_voxel_size(const morph::Job& job);

/// How to compute the OpenVDB reference (`morphmill reference`).
struct ReferenceSettings {
  double voxel_size = 0.0;                              ///< voxel edge, job units; 0: default_voxel_size(job)
  std::size_t memory_cap_bytes = std::size_t(8) << 30;  ///< morph::LimitError above this estimate
  morph::Progress* progress = nullptr;
};

/// The level-set reference of the job's erosion at one voxel size (vdb_ref::compute_reference).
vdb_ref::ReferenceResult reference(const morph::Job& job, const ReferenceSettings& settings = {});

/// How to sample and measure (`morphmill deviation`; same defaults).
struct DeviationSettings {
  std::size_t face_samples = 100000;  ///< area-uniform samples per surface
  std::size_t edge_samples = 0;       ///< samples along the unique edges, by length
  bool vertices = true;               ///< a sample on every vertex as well
  std::uint64_t seed = 1;             ///< the samples are a deterministic function of it
  raytest::DeviationMode mode = raytest::DeviationMode::Unsigned;
  double max_distance = std::numeric_limits<double>::infinity();  ///< farther: a miss (NaN)
};

/// Samples each surface and measures it against the other (exact closest points, or rays in
/// Ray mode): per-sample values, statistics and the two-sided Hausdorff distance, mesh units.
raytest::TwoSidedDeviation deviation(const morph::TriangleMesh& a, const morph::TriangleMesh& b,
                                     const DeviationSettings& settings = {});

/// How to verify (`morphmill verify`; same defaults).
struct VerifySettings {
  double voxel_size = 0.0;            ///< reference voxel, job units; 0: default_voxel_size(job)
  double tolerance = 0.0;             ///< generator tolerance, job units; 0: the job's
  std::size_t face_samples = 100000;  ///< area-uniform samples per surface
  std::uint64_t seed = 1;
  /// Judge only the reference against the exact surface (the generator is not run).
  bool reference_only = false;
  std::size_t reference_memory_cap_bytes = std::size_t(8) << 30;
  morph::Progress* progress = nullptr;
};

/// The outcome of verify: the verdict, its parts, and the surfaces and samples it was decided on.
struct VerifyReport {
  /// The verdict `morphmill verify` exits 0 for.
  bool verdict = false;
  bool generator_within_tolerance = false;  ///< generator <-> exact surface within the tolerance
  bool sides_agree = false;                 ///< generator <-> reference within agreement_bound
  bool pieces_match = false;                ///< same solid pieces, volumes within the bound
  /// Why the generator was not run ("" when it was): reference_only.
  std::string generator_skipped;
  double tolerance = 0.0;        ///< job units
  double voxel_size = 0.0;       ///< job units
  double agreement_bound = 0.0;  ///< tolerance + sqrt(3) * voxel, job units
  /// Largest generator <-> reference deviation where the surface is resolvable at the voxel size.
  double resolvable_hausdorff = 0.0;
  morph::TriangleMesh generator_mesh;  ///< empty when the generator was not run
  morph::TriangleMesh reference_mesh;
  /// The generator's samples against the exact surface (signed: + outside the exact solid).
  raytest::OneSidedDeviation generator_to_exact;
  /// The reference's samples against the exact surface.
  raytest::OneSidedDeviation reference_to_exact;
  /// Everything verify measured, as `morphmill verify` writes it to deviation.json.
  nlohmann::json summary;
};

/// Runs the generator, the reference and the deviation measurement on `job` and decides the
/// verdict exactly as `morphmill verify` does, without writing files.
VerifyReport verify(const morph::Job& job, const VerifySettings& settings = {});

}  // namespace morphmill
