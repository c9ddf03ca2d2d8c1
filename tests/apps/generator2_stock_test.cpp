// SPDX-License-Identifier: Apache-2.0
// Generator 2 on cylinder and mesh stock, checked by the exact self-intersection test that
// `erode` runs (CGAL, in apps): a cylinder cut by a slot across its top and a groove into its
// side, the bundled mesh_stock job and the shared reproducer r12 (a mesh with sliver triangles
// next to a groove) are closed, oriented 2-manifolds with no intersecting triangle pair, and
// their volumes are the closed forms within the tolerance.
#include <gtest/gtest.h>
#include <morph/erode.h>
#include <morph/tool.h>
#include <morph/topology.h>
#include <morphmill/job_io.h>
#include <morphmill/mesh_io.h>
#include <morphmill/self_intersections.h>

#include <cmath>
#include <fstream>
#include <string>

namespace {

using Eigen::Vector3d;

// `flat`: the zero-area triangles allowed (the rounding stage's needles at a joint of two moves).
morph::TopologyReport expect_valid_solid(const morph::Job& job, const std::string& what,
                                         std::size_t flat = 0) {
  const morph::TriangleMesh mesh = morph::erode(job).mesh;
  const morph::TopologyReport t = morph::topology_report(mesh);
  EXPECT_TRUE(t.closed_manifold()) << what;
  EXPECT_EQ(t.degenerate_triangles, flat) << what;
  EXPECT_EQ(morphmill::find_self_intersections(mesh).pairs, 0u) << what;
  return t;
}

TEST(Generator2Stock, CylinderWithASlotAndAGrooveIsAValidSolid) {
  morph::Job job;
  job.stock.type = morph::StockType::Cylinder;
  job.stock.base = Vector3d(0, 0, 0);
  job.stock.radius = 10;
  job.stock.height = 8;
  job.tolerance = 0.05;
  job.tools.emplace(1, morph::flat_tool(1.5, 10));
  job.tools.emplace(2, morph::sphere_tool(2));
  morph::Path slot, groove;
  morph::Move m;
  m.tool = 1, m.line = 1, m.start = Vector3d(-14, 0, 7), m.end = Vector3d(14, 0, 7);
  slot.moves.push_back(m);
  // The sphere 1 mm into the side, a quarter turn in 6 chords.
  for (int k = 0; k < 6; ++k) {
    const double a0 = k * M_PI / 12, a1 = (k + 1) * M_PI / 12;
    m.tool = 2, m.line = 2 + k;
    m.start = Vector3d(11 * std::cos(a0), 11 * std::sin(a0), 4);
    m.end = Vector3d(11 * std::cos(a1), 11 * std::sin(a1), 4);
    groove.moves.push_back(m);
  }
  job.paths = {slot, groove};
  const morph::TopologyReport t = expect_valid_solid(job, "cylinder");
  EXPECT_EQ(t.components, 1u);
  // Slot: 1 deep over the strip |y| <= 1.5 of the disc. Groove: a sphere cap 1 deep swept along
  // a quarter of the side, bounded by the whole cap's area times the arc (an upper bound).
  const double r = 10, R = 1.5;
  const double strip = 2 * (R * std::sqrt(r * r - R * R) + r * r * std::asin(R / r));
  const double cylinder = M_PI * r * r * 8, slot_volume = strip * 1.0;
  EXPECT_LT(t.volume, cylinder - slot_volume + job.tolerance * t.area);
  EXPECT_GT(t.volume, cylinder - slot_volume - M_PI * 4 * 11 * M_PI / 2 - job.tolerance * t.area);
}

TEST(Generator2Stock, FineCurvedMeshStockIsAValidSolid) {
  // 41,090 triangles, many under a millimetre: on the tolerance's grid (2^-9 mm) some would
  // degenerate; the finest grid on which every plane is exact keeps them whole.
  morph::Job job;
  job.stock.type = morph::StockType::Mesh;
  job.stock.mesh_path = std::string(MORPHMILL_TEST_DATA) + "/meshes/design_gouge_excess.stl";
  job.stock.mesh = morphmill::read_mesh(job.stock.mesh_path);
  job.tolerance = 0.01;
  job.tools.emplace(1, morph::ball_tool(2, 30));
  morph::Path path;
  morph::Move m;
  m.tool = 1, m.line = 1, m.start = Vector3d(-5, 13, 18), m.end = Vector3d(30, 17, 16);
  path.moves.push_back(m);
  m.line = 2, m.start = m.end, m.end = Vector3d(65, 25, 17);
  path.moves.push_back(m);
  job.paths.push_back(path);
  // No flat triangle: the needle where the groove turns (two silhouette planes meeting a ring
  // edge only up to rounding) is gone with the sweeps' exact planes (quantize.h).
  const morph::TopologyReport t = expect_valid_solid(job, "design_gouge_excess");
  EXPECT_EQ(t.components, 1u);
  EXPECT_LT(t.volume, morph::enclosed_volume(job.stock.mesh) - 100.0);  // the groove is there
}

TEST(Generator2Stock, MeshStockJobsAreValidSolids) {
  // The block as a mesh gives the block's surface: the same volume, and no more flat triangles
  // than the box stock's (4 needles where the groove turns, from the rounding of the sweeps).
  morph::Job block = morphmill::load_job(std::string(MORPHMILL_TEST_DATA) + "/jobs/mesh_stock.json");
  const morph::TriangleMesh as_mesh = morph::erode(block).mesh;
  block.stock = morph::Stock{};
  block.stock.box = Eigen::AlignedBox3d(Vector3d(0, 0, 0), Vector3d(100, 60, 20));
  const morph::TopologyReport box = morph::topology_report(morph::erode(block).mesh);
  const morph::TopologyReport t = morph::topology_report(as_mesh);
  EXPECT_TRUE(t.closed_manifold());
  EXPECT_EQ(morphmill::find_self_intersections(as_mesh).pairs, 0u);
  EXPECT_LE(t.degenerate_triangles, box.degenerate_triangles);
  EXPECT_EQ(t.components, 1u);
  EXPECT_NEAR(t.volume, box.volume, 1e-9 * box.volume);
  EXPECT_LT(t.volume, 100 * 60 * 20 - 1000.0);  // the groove is there

  const std::string r12 = std::string(MORPHMILL_SHARED_DIR) + "/repro/generator/r12_bracket_top_groove.json";
  if (!std::ifstream(r12)) GTEST_SKIP() << "reproducers not found at " << MORPHMILL_SHARED_DIR;
  const morph::TopologyReport b = expect_valid_solid(morphmill::load_job(r12), "r12");
  EXPECT_EQ(b.components, 1u);
  // The bracket (56316.2797 mm³ by the divergence theorem) minus a ball end's half disc (radius
  // 3, its centre on the top face) across its 40 mm width; within the tolerance times the area.
  EXPECT_NEAR(b.volume, 56316.2797 - 40 * M_PI * 9 / 2, 0.01 * b.area);
}

}  // namespace
