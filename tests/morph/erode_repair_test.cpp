// SPDX-License-Identifier: Apache-2.0
// Tests of the generator's local repair (morph/src/generator/erode_repair.h, private to morph) against an
// exact field: holes cut into closed meshes of solids whose signed distance is known.
#include <gtest/gtest.h>
#include <morph/topology.h>

#include <algorithm>
#include <cmath>

#include "generator/erode_repair.h"

namespace {

using Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;
constexpr double kHoleRadius = 0.3;
constexpr double kFieldError = 0.004;

/// The lens where two balls of radius 2 centred at (0, 0, +-offset) overlap: two spherical caps
/// meeting in a convex crease along the circle of radius sqrt(4 - offset^2) in z = 0.
struct Lens {
  double offset;
  double radius = 2.0;
  double rim() const { return std::sqrt(radius * radius - offset * offset); }
  /// max of the balls' signed distances: exact inside and on the caps, a lower bound outside.
  double field(const Vector3d& x) const {
    return std::max((x - Vector3d(0, 0, offset)).norm(), (x + Vector3d(0, 0, offset)).norm()) - radius;
  }
  /// A closed, outward mesh: `around` segments, `rings` rings per cap from the rim to the pole.
  morph::TriangleMesh mesh(int around, int rings) const {
    morph::TriangleMesh mesh;
    auto add = [&](const Vector3d& p) {
      mesh.vertices.push_back(p);
      return static_cast<std::uint32_t>(mesh.vertices.size() - 1);
    };
    // The upper cap belongs to the ball centred below (and the other way round).
    const double rim_angle = std::asin(rim() / radius);
    std::vector<std::vector<std::uint32_t>> upper(rings), lower(rings);
    for (int k = 0; k < rings; ++k)
      for (int i = 0; i < around; ++i) {
        const double polar = rim_angle * (1.0 - static_cast<double>(k) / rings);
        const double azimuth = 2.0 * kPi * i / around;
        const Vector3d direction(std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
                                 std::cos(polar));
        const Vector3d up = Vector3d(0, 0, -offset) + radius * direction;
        upper[k].push_back(add(up));
        lower[k].push_back(k == 0 ? upper[0][i] : add(Vector3d(up.x(), up.y(), -up.z())));
      }
    const std::uint32_t top = add(Vector3d(0, 0, radius - offset)),
                        bottom = add(Vector3d(0, 0, offset - radius));
    for (int k = 0; k + 1 < rings; ++k)
      for (int i = 0; i < around; ++i) {
        const int j = (i + 1) % around;
        mesh.triangles.push_back({upper[k][i], upper[k][j], upper[k + 1][j]});
        mesh.triangles.push_back({upper[k][i], upper[k + 1][j], upper[k + 1][i]});
        mesh.triangles.push_back({lower[k][j], lower[k][i], lower[k + 1][i]});
        mesh.triangles.push_back({lower[k][j], lower[k + 1][i], lower[k + 1][j]});
      }
    for (int i = 0; i < around; ++i) {
      const int j = (i + 1) % around;
      mesh.triangles.push_back({upper[rings - 1][i], upper[rings - 1][j], top});
      mesh.triangles.push_back({lower[rings - 1][j], lower[rings - 1][i], bottom});
    }
    mesh.tags.assign(mesh.triangles.size(), morph::FaceTag{});
    return mesh;
  }
};

/// Largest |field| at the centroids and edge midpoints of the mesh.
template <class Field>
double largest_field_error(const morph::TriangleMesh& mesh, const Field& field) {
  double worst = 0.0;
  for (const auto& tri : mesh.triangles) {
    const Vector3d &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
    for (const Vector3d& p : {Vector3d((a + b + c) / 3.0), Vector3d((a + b) / 2.0), Vector3d((b + c) / 2.0),
                              Vector3d((c + a) / 2.0)})
      worst = std::max(worst, std::abs(field(p)));
  }
  return worst;
}

// A hole about 0.6 across cut into a lens's rim, where two caps of radius 2 meet with normals 60 degrees
// apart: the hole straddles the crease and a chord across it sags about 0.02 below the caps, so the fill
// needs points inside the hole on both caps and must follow the crease.
TEST(ErodeRepair, HoleAcrossACurvedCreaseIsClosedNearTheSurface) {
  const Lens lens{1.0};
  morph::TriangleMesh mesh = lens.mesh(128, 48);
  ASSERT_TRUE(morph::topology_report(mesh).closed_manifold());
  auto field = [&](const Vector3d& x) { return lens.field(x); };
  const double own_error = largest_field_error(mesh, field);
  ASSERT_LT(own_error, 0.002);
  const Vector3d centre(lens.rim(), 0.0, 0.0);
  std::vector<bool> cut(mesh.triangles.size(), false);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (std::uint32_t v : mesh.triangles[t])
      if ((mesh.vertices[v] - centre).norm() < kHoleRadius) cut[t] = true;
  std::vector<morph::detail::TriangleOrigin> patch_of(mesh.triangles.size());
  morph::detail::remove_triangles(mesh, patch_of, cut);
  ASSERT_GT(morph::topology_report(mesh).boundary_edges, 20u);

  morph::detail::RepairOptions options;
  options.max_radius = 1.0;
  options.max_field_error = kFieldError;
  const morph::detail::RepairStats stats =
      morph::detail::repair_small_defects(mesh, patch_of, options, field);
  EXPECT_EQ(stats.defects, 1u);
  EXPECT_EQ(stats.repaired, 1u);
  const morph::TopologyReport topology = morph::topology_report(mesh);
  EXPECT_TRUE(topology.closed_manifold())
      << topology.boundary_edges << " open, " << topology.non_manifold_edges << " non-manifold edges";
  EXPECT_EQ(topology.components, 1u);
  EXPECT_LE(largest_field_error(mesh, field), std::max(own_error, options.max_field_error));
}

// Two holes in a lens's rim; the first pass repairs only the small one (the other is too wide
// for its ball). The suspects it leaves must hold the other hole's vertices, so that a second pass
// told to look there alone finds and treats it as a search of every vertex does.
TEST(ErodeRepair, SuspectsLeftByAPassHoldEveryDefectTheNextPassFinds) {
  const Lens lens{1.0};
  morph::TriangleMesh mesh = lens.mesh(128, 48);
  auto field = [&](const Vector3d& x) { return lens.field(x); };
  const Vector3d small_hole(lens.rim(), 0.0, 0.0), wide_hole(-lens.rim(), 0.0, 0.0);
  std::vector<bool> cut(mesh.triangles.size(), false);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (std::uint32_t v : mesh.triangles[t])
      if ((mesh.vertices[v] - small_hole).norm() < kHoleRadius || (mesh.vertices[v] - wide_hole).norm() < 1.2)
        cut[t] = true;
  std::vector<morph::detail::TriangleOrigin> patch_of(mesh.triangles.size());
  morph::detail::remove_triangles(mesh, patch_of, cut);

  morph::detail::RepairOptions options;
  options.max_radius = 1.0;  // holds the small hole, not the wide one
  options.max_field_error = kFieldError;
  morph::detail::DefectSuspects suspects;
  const morph::detail::RepairStats first =
      morph::detail::repair_small_defects(mesh, patch_of, options, field, nullptr, &suspects);
  ASSERT_EQ(first.defects, 2u);
  ASSERT_EQ(first.repaired, 1u);
  ASSERT_TRUE(suspects.known);
  EXPECT_TRUE(std::is_sorted(suspects.vertices.begin(), suspects.vertices.end()));
  // Every open edge's ends are suspects.
  std::size_t open_ends = 0, missed = 0;
  const morph::TopologyReport before = morph::topology_report(mesh);
  ASSERT_GT(before.boundary_edges, 0u);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = mesh.triangles[t][k], b = mesh.triangles[t][(k + 1) % 3];
      bool paired = false;
      for (const auto& other : mesh.triangles)
        for (int m = 0; m < 3 && !paired; ++m) paired = other[m] == b && other[(m + 1) % 3] == a;
      if (paired) continue;
      for (std::uint32_t v : {a, b}) {
        ++open_ends;
        missed += !std::binary_search(suspects.vertices.begin(), suspects.vertices.end(), v);
      }
    }
  EXPECT_GT(open_ends, 0u);
  EXPECT_EQ(missed, 0u);
  // The next pass, looking at the suspects alone, finds what a search of every vertex finds:
  // the wide hole, and nothing at the repaired spot.
  morph::TriangleMesh full_mesh = mesh;
  std::vector<morph::detail::TriangleOrigin> full_patch_of = patch_of;
  const morph::detail::RepairStats full =
      morph::detail::repair_small_defects(full_mesh, full_patch_of, options, field);
  const morph::detail::RepairStats second =
      morph::detail::repair_small_defects(mesh, patch_of, options, field, nullptr, &suspects);
  EXPECT_EQ(full.defects, 1u);
  EXPECT_EQ(second.defects, full.defects);
  EXPECT_EQ(second.repaired, full.repaired);
  EXPECT_EQ(mesh.triangles, full_mesh.triangles);
}

}  // namespace
