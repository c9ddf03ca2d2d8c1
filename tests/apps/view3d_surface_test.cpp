// SPDX-License-Identifier: Apache-2.0
// The 3D view of a large part: the surface embedded in report.html is decimated to a cap, stays
// close to the part, keeps the moves that made each place, and the report stays a bounded size.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "verify/view3d.h"
#include "verify/view3d_surface.h"

namespace {

constexpr double kRadius = 10.0;  // mm

// A closed UV sphere of radius kRadius with 2 * rings * (segments) triangles; faces of the upper
// half are tagged as made by move 1 (G-code line 10), of the lower half by move 2 (line 20).
morph::TriangleMesh tagged_sphere(int rings, int segments) {
  morph::TriangleMesh mesh;
  mesh.vertices.emplace_back(0, 0, kRadius);
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double theta = M_PI * r / rings, phi = 2 * M_PI * s / segments;
      mesh.vertices.emplace_back(kRadius * std::sin(theta) * std::cos(phi),
                                 kRadius * std::sin(theta) * std::sin(phi), kRadius * std::cos(theta));
    }
  mesh.vertices.emplace_back(0, 0, -kRadius);
  const auto ring = [&](int r, int s) { return std::uint32_t(1 + (r - 1) * segments + (s % segments)); };
  const std::uint32_t south = std::uint32_t(mesh.vertices.size() - 1);
  for (int s = 0; s < segments; ++s) {
    mesh.triangles.push_back({0, ring(1, s), ring(1, s + 1)});
    for (int r = 1; r + 1 < rings; ++r) {
      mesh.triangles.push_back({ring(r, s), ring(r + 1, s), ring(r + 1, s + 1)});
      mesh.triangles.push_back({ring(r, s), ring(r + 1, s + 1), ring(r, s + 1)});
    }
    mesh.triangles.push_back({ring(rings - 1, s), south, ring(rings - 1, s + 1)});
  }
  for (const morph::Triangle& t : mesh.triangles) {
    const double z = (mesh.vertices[t[0]] + mesh.vertices[t[1]] + mesh.vertices[t[2]]).z() / 3.0;
    morph::FaceTag tag;
    tag.source = z > 0 ? 1 : 2;
    tag.line = z > 0 ? 10 : 20;
    mesh.tags.push_back(tag);
  }
  return mesh;
}

}  // namespace

TEST(View3dSurface, SmallPartIsShownWhole) {
  const morph::TriangleMesh sphere = tagged_sphere(20, 40);
  const morphmill::ViewSurface shown = morphmill::decimated_for_view(sphere, 10'000);
  EXPECT_FALSE(shown.decimated);
  EXPECT_EQ(shown.mesh.triangles.size(), sphere.triangles.size());
  EXPECT_EQ(shown.source_triangles, sphere.triangles.size());
  EXPECT_THROW(morphmill::decimated_for_view(sphere, 0), std::invalid_argument);
}

TEST(View3dSurface, LargePartIsDecimatedCloseToItAndKeepsItsMoves) {
  // A cap of 20k on 72k triangles stands for the default 150k on a part of millions (the work of
  // decimating grows with the source; this keeps the test at a few seconds).
  constexpr std::size_t kCap = 20'000;
  const morph::TriangleMesh sphere = tagged_sphere(120, 300);  // 71,400 triangles
  const morphmill::ViewSurface shown = morphmill::decimated_for_view(sphere, kCap);
  EXPECT_TRUE(shown.decimated);
  EXPECT_EQ(shown.source_triangles, sphere.triangles.size());
  EXPECT_LE(shown.mesh.triangles.size(), kCap);
  EXPECT_GT(shown.mesh.triangles.size(), kCap / 2);
  // Still the sphere: every kept vertex on it, and the faces cover it (area within 1 % of 4 pi r^2).
  double area = 0;
  for (const Eigen::Vector3d& v : shown.mesh.vertices) EXPECT_NEAR(v.norm(), kRadius, 0.01);
  for (const morph::Triangle& t : shown.mesh.triangles)
    area += 0.5 * (shown.mesh.vertices[t[1]] - shown.mesh.vertices[t[0]])
                      .cross(shown.mesh.vertices[t[2]] - shown.mesh.vertices[t[0]])
                      .norm();
  EXPECT_NEAR(area, 4 * M_PI * kRadius * kRadius, 0.01 * 4 * M_PI * kRadius * kRadius);
  // Each face names the move of the source face under it: line 10 above the equator, 20 below.
  ASSERT_EQ(shown.mesh.tags.size(), shown.mesh.triangles.size());
  std::size_t checked = 0;
  for (std::size_t t = 0; t < shown.mesh.triangles.size(); ++t) {
    const morph::Triangle& tri = shown.mesh.triangles[t];
    const double z =
        (shown.mesh.vertices[tri[0]] + shown.mesh.vertices[tri[1]] + shown.mesh.vertices[tri[2]]).z() / 3;
    if (std::abs(z) < 0.5) continue;  // a face across the equator may take either
    EXPECT_EQ(shown.mesh.tags[t].line, z > 0 ? 10 : 20) << "face " << t << " at z = " << z;
    ++checked;
  }
  EXPECT_GT(checked, shown.mesh.triangles.size() * 9 / 10);

  // The report's block stays bounded by the cap, not the source: about 45 bytes per shown triangle
  // (base64 of positions, colours and values per vertex, indices, move and line per triangle) plus
  // three.js (about 700 kB).
  morphmill::View3d view;
  view.mesh = shown.mesh;
  view.values.assign(view.mesh.vertices.size(), 0.0);
  for (std::size_t i = 0; i < view.values.size(); ++i) view.values[i] = view.mesh.vertices[i].z() / 1000;
  view.range = {-0.02, 0.02};
  view.band_low = -0.01;
  view.band_high = 0.01;
  view.unit = "mm";
  view.title = "sphere";
  view.source_triangles = shown.source_triangles;
  view.decimated = shown.decimated;
  const std::string html = morphmill::view3d_html(view, morphmill::default_three_dir());
  EXPECT_LT(html.size(), 50 * kCap + 1'000'000);
  EXPECT_NE(html.find("Shown decimated: " + std::to_string(shown.mesh.triangles.size()) + " of the " +
                      std::to_string(sphere.triangles.size()) + " triangles"),
            std::string::npos);
}
