// SPDX-License-Identifier: Apache-2.0
#pragma once
// Provenance of the reference's faces: the move whose sweep a face lies on, found through a
// bounding-volume hierarchy of the moves' sweeps searched only as far as the face can be from
// the sweep that decides its tag.
#include <morph/job.h>
#include <morph/mesh.h>
#include <morph/progress.h>

namespace vdb_ref::detail {

/// Tags every face PatchKind::Reference with source = the move (global index) whose exact sweep
/// distance at the face centroid is smallest and line = its G-code line when that distance is
/// within the centroid's distance to the stock (|sweep| <= |stock|); otherwise source = -1,
/// line = 0. Moves within 1e-9 units of the smallest distance tie (consecutive moves do where
/// they meet); the earliest of them wins. `search_radius` (job units, > 0) is how
/// far from a sweep's surface most centroids are expected (about the voxel size): centroids
/// further from every sweep and from the stock cost a second, wider search. Throws
/// morph::Interrupted if `progress` asks to stop.
void tag_faces(const morph::Job& job, double search_radius, morph::TriangleMesh& mesh,
               morph::Progress& progress);

}  // namespace vdb_ref::detail
