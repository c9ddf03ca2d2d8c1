// SPDX-License-Identifier: Apache-2.0
#pragma once
// Private to the generator: replacing small defects left by the seam work (a few open or
// non-manifold edges where a tool's contact with another sweep is singular or tangent) with a
// fan around a point of the exact surface.
#include <morph/mesh.h>

#include <array>
#include <cstddef>
#include <map>
#include <set>
#include <vector>

#include "generator/erode_seams.h"
#include "mesh/edge_uses.h"

namespace morph::detail {

struct RepairOptions {
  double max_radius = 0.1;        ///< largest ball (job units) whose triangles may be replaced
  double max_field_error = 0.01;  ///< every replacement triangle stays this close to the exact surface
};

struct RepairStats {
  std::size_t defects = 0;   ///< clusters of open / non-manifold edges and vertices found
  std::size_t repaired = 0;  ///< of which replaced by a fan
};

/// Finds clusters of open edges, non-manifold or inconsistently oriented edges and non-manifold
/// vertices; for each cluster smaller than `max_radius`, removes the triangles with a vertex in
/// the smallest ball about it (reached over the surface from the cluster) whose removal leaves
/// one simple hole in an otherwise manifold ring, and closes that hole with a fan around the
/// nearest point of the exact surface (`field` is zero there), a fan from one of the hole's
/// vertices, or the hole's least-area triangulation, provided every new triangle's centroid and
/// edge midpoints stay within `max_field_error` of it. A ball whose ring meets another cluster
/// takes that cluster in. Larger or unrepairable defects are left as they are.
/// `patch_of_triangle` is kept in step with `mesh.triangles` (and tags).
/// Removes the triangles flagged in `remove` (one flag per triangle) and the vertices no triangle
/// uses any more, keeping the order of what stays.
/// `new_index_out` (if given): each old vertex's new index, kDropped for those removed.
constexpr std::uint32_t kDropped = UINT32_MAX;
void remove_triangles(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                      const std::vector<bool>& remove, std::vector<std::uint32_t>* new_index_out = nullptr);

/// Merges into each vertex of an open or non-manifold edge the vertices within `distance` of it
/// that share its cell of side `distance`, then drops the triangles this makes degenerate and
/// each triangle lying on its own reverse (a sliver folded flat). Seams of tangent contacts and
/// of nearly coincident tool positions leave strips far thinner than the tolerance that no fan
/// can close without needles. (Taking the neighbouring cells too, every vertex within
/// `distance`, welds across the cusps of the 100k-move raster: 7 open edges where there were
/// none.) Returns the number of merges.
std::size_t weld_near_defects(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                              double distance, std::vector<EdgeUse>& uses);

/// The same around every non-manifold vertex (two fans meeting at one point; see
/// morph::non_manifold_vertices), with every vertex within `distance` of it. `among` (if given,
/// sorted): the only vertices that can be non-manifold (a repair pass's suspects, which hold
/// every vertex the repair would find defective, pinches among them).
std::size_t weld_near_pinches(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                              double distance, const std::vector<std::uint32_t>* among = nullptr);

/// The same around the vertices `defect` (sorted, unique): with `whole_reach` every vertex within
/// `distance` of one, else those in its own cell of side `distance`.
std::size_t weld_near(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                      const std::vector<std::uint32_t>& defect, double distance, bool whole_reach);

/// What one repair pass leaves for the next with the same options: the defects it could not
/// repair, each with the vertices (by position: passes renumber them) whose triangles it looked
/// at, and the vertices whose triangles a repair changed. A defect found again whose vertices
/// none of those repairs touched would fail again and is not retried.
struct RepairMemory {
  using Point = std::array<double, 3>;
  std::map<std::vector<Point>, std::vector<Point>> failed;  // defect's vertices -> vertices read
  std::set<Point> changed;
};

/// The only vertices where a pass can find a defect once the pass before it has run (`known`):
/// those of the defects it left and of every triangle its repairs removed or added. Any other
/// vertex was sound then and its fan has not changed since. Each pass replaces them with its
/// own; whatever else changes the mesh between passes must clear `known`.
struct DefectSuspects {
  bool known = false;
  std::vector<std::uint32_t> vertices;  // sorted, unique
};

/// `suspects` (if given): where to look for defects when known, then what this pass leaves.
RepairStats repair_small_defects(TriangleMesh& mesh, std::vector<TriangleOrigin>& patch_of_triangle,
                                 const RepairOptions& options, const FieldFunction& field,
                                 RepairMemory* memory = nullptr, DefectSuspects* suspects = nullptr);

}  // namespace morph::detail
