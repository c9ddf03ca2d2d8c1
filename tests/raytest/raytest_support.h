// SPDX-License-Identifier: Apache-2.0
#pragma once
// Meshes with closed-form geometry for the raytest suites.
#include <morph/mesh.h>

namespace raytest_test {

/// UV sphere of radius r centred at the origin: poles plus (nlat - 1) rings of nlon vertices, all
/// exactly on the sphere (up to the rounding of sin/cos); outward-wound. Polar angle i*pi/nlat.
morph::TriangleMesh uv_sphere(double r, int nlat, int nlon);

/// Axis-aligned box [lo, hi], each face split into n x n squares of two triangles; outward-wound.
morph::TriangleMesh box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int n);

/// Every vertex multiplied by `factor`.
morph::TriangleMesh scaled(morph::TriangleMesh mesh, double factor);

/// Exact signed distance to the solid box [lo, hi] (negative inside).
double box_signed_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi);

}  // namespace raytest_test
